#pragma once
// Levels of detail (issue 16). Level k has cells of 2^k blocks; a level-k chunk is 32³ cells, so
// it spans 2^(5+k) blocks per edge and is stored in the same Chunk class (palette format) as
// level 0: one mesher and one BLAS path serve every level, and the instance transform scales
// the mesh by the cell size. Level 0 is the blocks themselves (LodCoord{0, c} is chunk c).
//
// Coordinate spaces:
//   Level-k chunk coordinates: 32-bit signed (glm::ivec3); level-k chunk c holds the blocks
//   [c * 2^(5+k), (c + 1) * 2^(5+k)) on each axis, world block coordinates.
//   Level-k cell coordinates: world block coordinate >> k (floors negative values).
// The level-(k+1) parent of a level-k chunk c is c >> 1 (floored); its 8 children are
// 2c + (i & 1, (i >> 1) & 1, i >> 2), i = 0..7 (x fastest), and child i fills the octant of
// the parent whose cells start at 16 * (i & 1, (i >> 1) & 1, i >> 2).
// All helpers are pure functions. Thread-safe.

#include <cstdint>
#include <tuple>
#include <vector>

#include "world/coords.h"

namespace vx::world {

// Highest level the helpers accept: cells of 1,024 blocks, chunks of 32,768. Far beyond any
// view distance planned (4,096 blocks is level 3 to 4), and origins stay well inside int64.
inline constexpr int kMaxLodLevel = 10;
inline constexpr int kLodChildren = 8;

inline constexpr bool valid_lod_level(int level) { return level >= 0 && level <= kMaxLodLevel; }

struct LodCoord {
    int level = 0;        // 0..kMaxLodLevel.
    ChunkCoord chunk{0};  // In level-`level` chunks.

    friend bool operator==(const LodCoord& a, const LodCoord& b) = default;
};

// A total order (level, then x, y, z): for sorted lists that must not depend on a hash's order.
inline bool lod_coord_less(const LodCoord& a, const LodCoord& b) {
    return std::tie(a.level, a.chunk.x, a.chunk.y, a.chunk.z) < std::tie(b.level, b.chunk.x, b.chunk.y, b.chunk.z);
}

struct LodCoordHash {
    size_t operator()(const LodCoord& c) const noexcept {
        // The chunk hash, with the level folded in by another odd multiplier (ChunkCoordHash style).
        uint64_t h = uint64_t(ChunkCoordHash{}(c.chunk)) ^ (uint64_t(uint32_t(c.level)) * 0xD6E8FEB86659FD93ull);
        return size_t(h ^ (h >> 31));
    }
};

// Edge of one level-k cell, blocks.
inline constexpr int64_t lod_cell_size(int level) { return int64_t(1) << level; }
// Edge of one level-k chunk, blocks.
inline constexpr int64_t lod_chunk_blocks(int level) { return int64_t(kChunkSize) << level; }

// World block position of the chunk's cell (0,0,0) corner (its minimum block). World space puts
// block b at [b, b + 1), so the chunk occupies [origin, origin + lod_chunk_blocks(level)) in world
// units and cell (x, y, z) occupies [origin + cell_size * (x, y, z), ... + cell_size).
inline BlockPos lod_origin(LodCoord c) {
    return BlockPos(c.chunk) * lod_chunk_blocks(c.level);
}

// The blocks a level-k chunk covers: [min, max] inclusive on each axis.
struct LodBlockBox {
    BlockPos min{0};
    BlockPos max{0};
};
inline LodBlockBox lod_block_box(LodCoord c) {
    const BlockPos o = lod_origin(c);
    return {o, o + BlockPos(lod_chunk_blocks(c.level) - 1)};
}

// The level-k chunk holding world block `p`.
inline LodCoord lod_chunk_of(BlockPos p, int level) {
    const int s = kChunkBits + level;
    return {level, ChunkCoord(int32_t(p.x >> s), int32_t(p.y >> s), int32_t(p.z >> s))};
}
// Local cell (0..31 per axis) of block `p` inside its level-k chunk.
inline LocalPos lod_local_of(BlockPos p, int level) {
    return LocalPos(int((p.x >> level) & (kChunkSize - 1)), int((p.y >> level) & (kChunkSize - 1)),
                    int((p.z >> level) & (kChunkSize - 1)));
}

// The level-(k+1) chunk containing a level-k chunk. Precondition: c.level < kMaxLodLevel.
inline LodCoord lod_parent(LodCoord c) { return {c.level + 1, c.chunk >> 1}; }
// Child i (0..7, x fastest) of a level-k chunk: a level-(k-1) chunk. Precondition: c.level >= 1.
inline LodCoord lod_child(LodCoord c, int i) {
    return {c.level - 1, c.chunk * 2 + ChunkCoord(i & 1, (i >> 1) & 1, i >> 2)};
}
// Which child of its parent a chunk is (0..7, x fastest): lod_child(lod_parent(c), lod_octant(c)) == c.
inline int lod_octant(LodCoord c) {
    return (c.chunk.x & 1) | ((c.chunk.y & 1) << 1) | ((c.chunk.z & 1) << 2);
}
// The level-`level` chunk (level >= c.level) that contains chunk c.
inline LodCoord lod_ancestor(LodCoord c, int level) {
    return {level, c.chunk >> (level - c.level)};
}
// The ancestors of level-0 chunk c at levels from..kMaxLodLevel, finest first (the coarse chunks
// an edit of it changes).
inline std::vector<LodCoord> lod_ancestors(ChunkCoord c, int from) {
    std::vector<LodCoord> out;
    for (int k = from; k <= kMaxLodLevel; ++k)
        out.push_back(lod_ancestor({0, c}, k));
    return out;
}

} // namespace vx::world
