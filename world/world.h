#pragma once
// The world: a sparse map of chunks addressed by chunk coordinates, with block access across
// chunk borders in 64-bit world block coordinates. Chunks not present read as air.
// Not thread-safe: the main thread owns a World; jobs work on copies (snapshots) of chunks.

#include <cstddef>
#include <unordered_map>

#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/coords.h"

namespace vx::world {

class World {
public:
    explicit World(BlockRegistry registry = BlockRegistry::default_registry())
        : m_registry(std::move(registry)) {}

    const BlockRegistry& registry() const { return m_registry; }
    BlockRegistry& registry() { return m_registry; }

    BlockId get_block(BlockPos p) const; // Air outside the world.
    // Sets a block, creating its chunk if needed; returns the id it replaced. p must be in_world().
    BlockId set_block(BlockPos p, BlockId id);

    const Chunk* find_chunk(ChunkCoord c) const;
    Chunk* find_chunk(ChunkCoord c);
    // The face neighbour of c towards f; null when absent or beyond the world's edge.
    const Chunk* find_neighbour(ChunkCoord c, Face f) const {
        return has_neighbour(c, f) ? find_chunk(c + face_normal(f)) : nullptr;
    }
    Chunk& chunk(ChunkCoord c); // Creates an air chunk if absent.
    void put_chunk(ChunkCoord c, Chunk chunk);
    bool remove_chunk(ChunkCoord c);
    size_t chunk_count() const { return m_chunks.size(); }
    // Makes room for n chunks, so inserting them never rehashes (no frame-time spikes).
    void reserve_chunks(size_t n) { m_chunks.reserve(n); }

    template <class F> void for_each_chunk(F&& f) const {
        for (const auto& [c, chunk] : m_chunks)
            f(c, chunk);
    }

    // Bounds of present chunks in chunk coordinates (inclusive); false when the world is empty.
    bool chunk_bounds(ChunkCoord& lo, ChunkCoord& hi) const;

private:
    BlockRegistry m_registry;
    std::unordered_map<ChunkCoord, Chunk, ChunkCoordHash> m_chunks;
};

} // namespace vx::world
