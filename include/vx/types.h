#pragma once
// The plain value types of vx's public API: coordinates, block ids and materials, faces, images.
//
// Coordinate spaces (y is up everywhere):
//   World block coordinates: 64-bit signed integers (BlockPos), one unit per block; block
//     (x, y, z) fills the unit cube [x, x+1) × [y, y+1) × [z, z+1). The world spans [-2^36, 2^36).
//   Chunk coordinates: 32-bit signed integers (ChunkCoord); chunk c holds the 32³ blocks
//     [32c, 32c + 32) on each axis.
//   Chunk-local coordinates: 0..31 per axis; linear index x + 32·(y + 32·z) (x fastest).
// Everything here is a plain value or a pure function: thread-safe.

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

namespace vx {

using BlockPos = glm::i64vec3; // World block coordinates.
using ChunkCoord = glm::ivec3; // Chunk coordinates.
using BlockId = uint16_t;      // A block type; 0 is air.

inline constexpr BlockId kAir = 0;
inline constexpr int kChunkSize = 32;                                     // Blocks per chunk edge.
inline constexpr int kChunkVolume = kChunkSize * kChunkSize * kChunkSize; // 32768 blocks.

// Chunk holding a world block (floors negative coordinates).
inline ChunkCoord chunk_of(BlockPos p) { return ChunkCoord(int32_t(p.x >> 5), int32_t(p.y >> 5), int32_t(p.z >> 5)); }
// World position of chunk c's block (0, 0, 0).
inline BlockPos chunk_origin(ChunkCoord c) { return BlockPos(c) * int64_t(kChunkSize); }
// Index of chunk-local (x, y, z), each 0..31, in a dense 32³ array.
inline constexpr int chunk_index(int x, int y, int z) { return x + kChunkSize * (y + kChunkSize * z); }

// The six faces of a block, by the direction their normal points.
enum class Face : uint8_t { NegX = 0, PosX, NegY, PosY, NegZ, PosZ };
// The unit normal of a face.
inline glm::ivec3 face_normal(Face f) {
    glm::ivec3 n(0);
    n[int(f) >> 1] = (int(f) & 1) ? 1 : -1;
    return n;
}

// A block type's material. Colours are linear RGB. Engine::create refuses values outside these
// ranges (or not finite), naming the block.
struct BlockType {
    std::string name;          // Unique, non-empty; how game code finds the id again.
    glm::vec3 albedo{0.8f};    // 0..1 per channel; see-through: what one block of path through it
                               // passes, albedo^d over d blocks (Beer-Lambert: deep water darkens).
    float reflectivity = 0.f;  // Fraction of light mirrored, 0..1; see-through: at normal incidence,
                               // more at grazing (Fresnel; water 0.02, glass 0.04; 0: tint only),
                               // and it sets the index the view bends by (1.33, 1.5; 0: none).
    glm::vec3 emission{0.f};   // Radiance, >= 0 per channel, finite (lamps).
    bool opaque = true;        // False: faces behind it stay meshed (water, glass).
};

// The built-in palette, ids 1..N in this order after air: stone, dirt, grass, sand, water,
// glass, mirror, lamp, snow, wood, leaves, glazed. The built-in terrain uses these ids. Start from it and
// append a game's own blocks to keep the terrain's meaning.
std::vector<BlockType> default_blocks();

// An RGBA8 picture: width × height pixels, row 0 at the top, 4 bytes per pixel (sRGB encoded
// for the full shading mode). Owns its pixels.
struct Image {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba; // width * height * 4 bytes.

    glm::u8vec4 at(uint32_t x, uint32_t y) const {
        const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
        return {p[0], p[1], p[2], p[3]};
    }
};

} // namespace vx
