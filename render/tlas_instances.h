#pragma once
// The TLAS's instances, kept from frame to frame so that a frame costs the CPU work of what
// changed, not of every drawn chunk: a dense array (add, update and remove are O(1); a removal
// moves the last instance into the hole, so the array stays gap-free and the TLAS build reads
// exactly size() instances), mirrored into each frame slot's host-visible buffers by writing
// only the entries changed since that slot's last frame (each slot has its own buffers: the
// slot's previous frame may still be reading the other's).
//
// Translations are relative to a render origin, not to the camera: the 64-bit difference
// chunk origin - render origin is exact and then rounded to float, as the camera-relative
// transforms were. A level-k chunk (world/lod/lod_coords.h: cells of 2^k blocks) is the same
// chunk-local mesh scaled by 2^k (the 3x3 part of its transform) at lod_origin(); level 0 is the
// identity scale. The origin follows the camera only when the camera strays more than
// kRebaseDistance blocks from it (every instance is rewritten once then; counted in rebases()),
// so shaders see positions within about 2^12 blocks of the origin plus the view distance, and
// a world at 2^24 blocks still renders like one at the origin (tests/render/far_origin_test.cpp).
//
// Instance i has instanceCustomIndex i and its chunk's Quad buffer at table entry i; a move
// rewrites both, so the shaders' lookups stay consistent whatever the order. The order depends
// only on the sequence of calls (never on hash order).
// Not thread-safe (a value; the renderer's main thread).

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "render/vk_common.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

// A chunk the TLAS draws, in instance order (the raster pipeline draws them too).
struct DrawChunk {
    world::LodCoord coord;     // Level and chunk: the mesh is in cells of 2^level blocks.
    VkDeviceAddress quads = 0; // Quad records, one per slot (Quad{} in spare slots).
    uint32_t slots = 0;
    bool opaque = false; // Only opaque blocks (SceneAccel::set_chunk): raster's see-through pass skips it.
};

class TlasInstances {
public:
    static constexpr uint32_t kNone = UINT32_MAX;
    // The camera may stray this far (blocks, any axis) from the render origin before it moves:
    // float positions near the camera then keep an ulp of at most 2^-11 blocks.
    static constexpr int64_t kRebaseDistance = int64_t(1) << 12;

    // `frame_slots`: how many mirrors sync() is called for (at most 8).
    explicit TlasInstances(uint32_t frame_slots);

    // Adds chunk `c`'s instance (BLAS at `blas`); returns its index. Indices change only by
    // remove() of another instance (which reports the move).
    uint32_t add(const DrawChunk& chunk, VkDeviceAddress blas);
    // Changes instance i's BLAS and quads (a rebuild or a compaction).
    void update(uint32_t i, const DrawChunk& chunk, VkDeviceAddress blas);
    // Removes instance i. The last instance moves to index i: returns its chunk (nullopt when i
    // was the last), whose recorded index the caller updates.
    std::optional<world::LodCoord> remove(uint32_t i);
    void clear();
    uint32_t size() const { return uint32_t(m_draw.size()); }
    // Instances of level-`level` chunks (kept as they are added and removed: O(1)).
    const std::array<uint32_t, world::kMaxLodLevel + 1>& level_counts() const { return m_level_counts; }

    // Before a frame's sync: moves the origin to `camera` when it is more than kRebaseDistance
    // from it, or when the array was empty since the last call (free: nothing to rewrite).
    // True when the origin moved.
    bool follow_camera(world::BlockPos camera);
    world::BlockPos origin() const { return m_origin; }
    uint64_t rebases() const { return m_rebases; } // Origin moves that rewrote instances.

    // Writes into frame slot `slot`'s buffers (size() entries each, persistently mapped) the
    // instances and table entries changed since the slot's last sync; `all`: the buffers are
    // new, write every entry. Returns the entries written.
    uint32_t sync(uint32_t slot, VkAccelerationStructureInstanceKHR* instances, uint64_t* table, bool all);

    std::span<const DrawChunk> draw_list() const { return m_draw; }
    std::span<const VkAccelerationStructureInstanceKHR> instances() const { return m_instances; }
    // The instance of `chunk` at index `index` for origin `origin` (what sync() writes): the
    // chunk-local mesh (cell units) scaled by lod_cell_size(chunk.level) and translated by
    // lod_origin(chunk) - origin (blocks).
    static VkAccelerationStructureInstanceKHR make_instance(world::LodCoord chunk, world::BlockPos origin,
                                                            uint32_t index, VkDeviceAddress blas);

private:
    void mark(uint32_t i);
    void write(uint32_t i);

    uint32_t m_slots;
    std::vector<VkAccelerationStructureInstanceKHR> m_instances;
    std::vector<DrawChunk> m_draw;
    std::array<uint32_t, world::kMaxLodLevel + 1> m_level_counts{};
    std::vector<uint8_t> m_marked;                 // Per index: bit s = listed in m_dirty[s].
    std::vector<std::vector<uint32_t>> m_dirty;    // Per slot: indices changed since its sync.
    std::vector<bool> m_all_dirty;                 // Per slot: every entry changed (a re-base).
    world::BlockPos m_origin{0, 0, 0};
    bool m_origin_free = true; // Empty since the last follow_camera(): the origin may move for free.
    uint64_t m_rebases = 0;
};

} // namespace vx::render
