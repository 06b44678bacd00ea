#pragma once
// Coordinate spaces of vx.
//   World block coordinates: 64-bit signed integers (glm::i64vec3), one unit per block; y is up.
//   Chunk coordinates: 32-bit signed integers (glm::ivec3); chunk c holds blocks [32c, 32c + 32).
//   Local coordinates: 0..31 inside one chunk.
// All helpers here are pure functions. Thread-safe.

#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <functional>

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

namespace vx::world {

using BlockPos = glm::i64vec3;  // World block coordinates.
using ChunkCoord = glm::ivec3;  // Chunk coordinates.
using LocalPos = glm::ivec3;    // 0..31 per component.

inline constexpr int kChunkBits = 5;
inline constexpr int kChunkSize = 1 << kChunkBits;                 // 32 blocks per edge.
inline constexpr int kChunkVolume = kChunkSize * kChunkSize * kChunkSize; // 32768 blocks.
inline constexpr int kPlanesPerAxis = kChunkSize + 1;             // 33 boundary planes per axis.
inline constexpr int kSliceCount = 3 * kPlanesPerAxis;            // 99 slices per chunk.

// The world spans every block whose chunk coordinate fits in 32 bits: [-2^36, 2^36).
inline constexpr int64_t kWorldMinBlock = int64_t(INT32_MIN) * kChunkSize;
inline constexpr int64_t kWorldMaxBlock = int64_t(INT32_MAX) * kChunkSize + (kChunkSize - 1);
inline constexpr bool in_world(int64_t v) { return v >= kWorldMinBlock && v <= kWorldMaxBlock; }
inline bool in_world(glm::i64vec3 p) { return in_world(p.x) && in_world(p.y) && in_world(p.z); }
// Points with a box of chunks around them (the streamer's viewer, a loaded scene's eye or volume)
// stay this far inside the world's edge, so the box's 32-bit chunk coordinates cannot overflow:
// 4096 chunks, past any box the engine makes (the streamer's reach at most 194 chunks).
inline constexpr int64_t kEdgeMarginBlocks = int64_t(4096) * kChunkSize; // 2^17
inline bool inside_edge_margin(glm::i64vec3 p) {
    const glm::i64vec3 lo(kWorldMinBlock + kEdgeMarginBlocks), hi(kWorldMaxBlock - kEdgeMarginBlocks);
    return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
}

// Linear index of a local position: x fastest, then y, then z.
inline constexpr int local_index(int x, int y, int z) { return x | (y << kChunkBits) | (z << (2 * kChunkBits)); }
inline constexpr int local_index(LocalPos p) { return local_index(p.x, p.y, p.z); }

// Chunk holding a world block. Arithmetic shift floors negative coordinates (C++20 defines it).
inline ChunkCoord chunk_of(BlockPos p) {
    return ChunkCoord(int32_t(p.x >> kChunkBits), int32_t(p.y >> kChunkBits), int32_t(p.z >> kChunkBits));
}
inline LocalPos local_of(BlockPos p) {
    return LocalPos(int(p.x & (kChunkSize - 1)), int(p.y & (kChunkSize - 1)), int(p.z & (kChunkSize - 1)));
}
// World position of a chunk's block (0,0,0).
inline BlockPos chunk_origin(ChunkCoord c) {
    return BlockPos(int64_t(c.x) * kChunkSize, int64_t(c.y) * kChunkSize, int64_t(c.z) * kChunkSize);
}

struct ChunkCoordHash {
    size_t operator()(const ChunkCoord& c) const noexcept {
        // Large odd multipliers spread neighbouring coordinates (Teschner et al. 2003 style).
        uint64_t h = uint64_t(uint32_t(c.x)) * 0x9E3779B185EBCA87ull;
        h ^= uint64_t(uint32_t(c.y)) * 0xC2B2AE3D27D4EB4Full;
        h ^= uint64_t(uint32_t(c.z)) * 0x165667B19E3779F9ull;
        return size_t(h ^ (h >> 29));
    }
};

// The six face directions. Axis = dir / 2; negative directions are even.
enum class Face : uint8_t { NegX = 0, PosX, NegY, PosY, NegZ, PosZ };
inline constexpr int face_axis(Face f) { return int(f) >> 1; }
inline constexpr bool face_positive(Face f) { return (int(f) & 1) != 0; }
inline constexpr Face make_face(int axis, bool positive) { return Face(axis * 2 + (positive ? 1 : 0)); }
inline glm::ivec3 face_normal(Face f) {
    glm::ivec3 n(0);
    n[face_axis(f)] = face_positive(f) ? 1 : -1;
    return n;
}
// Whether chunk c has a face neighbour towards f: a chunk on the world's edge has none there
// (outside the world reads as air), and c + face_normal(f) would overflow its 32 bits.
inline bool has_neighbour(ChunkCoord c, Face f) {
    const int v = c[face_axis(f)];
    return face_positive(f) ? v != INT32_MAX : v != INT32_MIN;
}

// A direction of any finite, non-zero length scaled by a power of two so its largest component
// lies in [0.5, 1): exact (the same ray, bit for bit, wherever no tiny component underflows;
// directions that differ by other factors give results within rounding of each other), and
// its squared length neither underflows nor overflows (a ray along (1e-200, 0, 0) had length 0,
// one along (1e200, 0, 0) infinite length). Zero stays zero. Any thread.
inline glm::dvec3 scaled_direction(const glm::dvec3& d) {
    const double m = glm::max(glm::max(glm::abs(d.x), glm::abs(d.y)), glm::abs(d.z));
    if (!(m > 0.0) || !std::isfinite(m))
        return d;
    int e = 0;
    std::frexp(m, &e);
    // A component that would round to zero keeps its sign (the smallest subnormal): the sign
    // decides which block a ray on a plane starts in (raycast.h's δ·d rule).
    auto scale = [e](double c) {
        const double s = std::ldexp(c, -e);
        return s == 0.0 && c != 0.0 ? std::copysign(std::numeric_limits<double>::denorm_min(), c) : s;
    };
    return {scale(d.x), scale(d.y), scale(d.z)};
}

// The same direction as a unit vector (zero for zero). Any thread.
inline glm::dvec3 unit_direction(const glm::dvec3& d) {
    const glm::dvec3 s = scaled_direction(d);
    return s == glm::dvec3(0.0) ? s : glm::normalize(s);
}

} // namespace vx::world
