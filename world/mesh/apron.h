#pragma once
// The blocks just outside a chunk, one 32×32 layer across each of its six faces: what the mesher
// needs from the neighbours so that no face between two solid blocks is emitted across a chunk
// border. Layers use the plane (u, v) axes of chunk_mesh.h, index u + 32 v.
// A job's snapshot of a chunk is the chunk plus its apron. Not thread-safe for writes.

#include <array>
#include <cstdint>
#include <vector>

#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/coords.h"

namespace vx::world {

class World;

// One face of an apron in transit: the neighbour's touching layer as palette entries, taken on
// the thread that owns the world (whole rows unpacked, no per-block lookups: ~1 µs) and expanded
// into an Apron elsewhere (a mesh job's worker; the expansion is most of copy_face's cost).
// Not thread-safe; a plain value once taken (it points into nothing).
struct ApronLayer {
    BlockId uniform = kAir;                                 // The whole face, when `palette` is empty.
    std::vector<BlockId> palette;                           // Entry -> id (palettes of <= 256 entries).
    std::array<uint8_t, kChunkSize * kChunkSize> entries;   // Index u + 32 v, when `palette` is set.
    std::vector<BlockId> ids;                               // Wider palettes: the ids, index u + 32 v.

    // The layer of `neighbour` that touches face `f` of a chunk (null: air).
    void take(Face f, const Chunk* neighbour);
};

struct Apron {
    std::array<std::array<BlockId, kChunkSize * kChunkSize>, 6> ids{}; // Indexed by Face.
    std::array<std::array<uint32_t, kChunkSize>, 6> opaque{};          // Row v, bit u.
    std::array<uint8_t, 6> any_transparent{}; // A non-air, non-opaque block on that face.

    // All six faces air: a chunk in isolation (the thesis's padding).
    static Apron air() { return Apron{}; }
    static Apron filled(BlockId id, const BlockRegistry& registry);

    void fill_face(Face f, BlockId id, const BlockRegistry& registry);
    void set(Face f, int u, int v, BlockId id, const BlockRegistry& registry);
    // Copies the layer of `neighbour` that touches face `f` of the chunk (its opposite border).
    void copy_face(Face f, const Chunk* neighbour, const BlockRegistry& registry);
    // The same from a layer taken earlier (ApronLayer::take).
    void set_face(Face f, const ApronLayer& layer, const BlockRegistry& registry);
    // Recomputes opaque rows and flags of one face from its ids.
    void refresh_face(Face f, const BlockRegistry& registry);
};

// The apron of chunk `c` in `world`; absent neighbours are air.
Apron make_apron(const World& world, ChunkCoord c);

// Maps a (layer, u, v) position on planes perpendicular to `axis` to chunk-local coordinates.
inline LocalPos plane_to_local(int axis, int layer, int u, int v) {
    return axis == 0 ? LocalPos(layer, u, v) : axis == 1 ? LocalPos(u, layer, v) : LocalPos(u, v, layer);
}

} // namespace vx::world
