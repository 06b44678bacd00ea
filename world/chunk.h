#pragma once
// A 32³ block of the world. A uniform chunk (all one id) stores only that id (16 bytes in all);
// any other holds a palette of ids with a reference count each and packed palette indices of
// ceil(log2(palette size)) bits, so a chunk with 5 block types costs 12 KiB.
// Local coordinates 0..31; linear index x fastest (see coords.h).
// Not thread-safe for writes; concurrent reads are safe. Jobs copy chunks (a snapshot) instead of
// sharing a live one.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "world/block_registry.h"
#include "world/coords.h"
#include "world/packed_array.h"

namespace vx::world {

// Palette storage of a non-uniform chunk.
struct ChunkPalette {
    std::vector<BlockId> ids;     // Palette entry -> block id. Entries may be unused (count 0).
    std::vector<uint16_t> counts; // Blocks using each entry; sums to kChunkVolume.
    PackedArray indices;          // kChunkVolume palette indices.
};

class Chunk {
public:
    Chunk() = default; // All air.
    explicit Chunk(BlockId fill) : m_uniform(fill) {}
    Chunk(const Chunk& other);
    Chunk& operator=(const Chunk& other);
    Chunk(Chunk&&) noexcept = default;
    Chunk& operator=(Chunk&&) noexcept = default;

    // Builds a chunk from kChunkVolume ids in local-index order.
    static Chunk from_dense(std::span<const BlockId> ids);
    // Adopts palette storage as is (the chunk record decoder). Preconditions, checked by the
    // caller: ids.size() == counts.size() >= 2, indices.size() == kChunkVolume, every index <
    // ids.size(), counts match the indices, no id repeats, and no count equals kChunkVolume.
    static Chunk from_palette(ChunkPalette palette);
    // Writes kChunkVolume ids in local-index order.
    void to_dense(std::span<BlockId> out) const;

    bool is_uniform() const { return !m_palette; }
    BlockId uniform_id() const { return m_uniform; } // Only meaningful when is_uniform().
    bool is_empty() const { return is_uniform() && m_uniform == kAir; }

    BlockId get(int index) const {
        return m_palette ? m_palette->ids[m_palette->indices.get(uint32_t(index))] : m_uniform;
    }
    BlockId get(int x, int y, int z) const { return get(local_index(x, y, z)); }
    BlockId get(LocalPos p) const { return get(local_index(p)); }

    // Sets one block; returns the id it replaced. A chunk that becomes all one id turns uniform.
    BlockId set(int index, BlockId id);
    BlockId set(int x, int y, int z, BlockId id) { return set(local_index(x, y, z), id); }
    BlockId set(LocalPos p, BlockId id) { return set(local_index(p), id); }

    void fill(BlockId id);
    // Drops unused palette entries and narrows the indices. Cheap to call when nothing is unused.
    void compact();

    // Palette storage, or null for a uniform chunk (fast paths in the mesher and serializer).
    const ChunkPalette* palette() const { return m_palette.get(); }
    // Distinct block ids present (1 for a uniform chunk).
    uint32_t distinct_ids() const;
    // Heap and inline bytes this chunk occupies.
    size_t memory_bytes() const;

    friend bool operator==(const Chunk& a, const Chunk& b);

private:
    uint32_t find_or_add_entry(BlockId id);

    std::unique_ptr<ChunkPalette> m_palette;
    BlockId m_uniform = kAir;
};

} // namespace vx::world
