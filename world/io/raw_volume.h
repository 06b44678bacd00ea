#pragma once
// Dense raw volumes of block ids: the interchange format of `vx mesh` and `vx render`.
// Layout: x fastest, then y, then z; y is up; little-endian u8 or u16 per block; 0 = air.
// Not thread-safe (fills a World).

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "world/base/result.h"
#include "world/world.h"

namespace vx::world {

enum class RawType : uint8_t { U8, U16 };

struct RawVolumeDesc {
    glm::i64vec3 dims{0};    // Blocks along x, y, z; each > 0.
    RawType type = RawType::U8;
    BlockPos origin{0};      // World position of the volume's block (0,0,0).
};

struct RawVolumeStats {
    uint64_t blocks = 0;     // Non-air blocks read.
    uint64_t chunks = 0;     // Chunks holding them.
};

// Largest volume accepted (blocks): 2^34, so a bad --dims cannot ask for terabytes.
inline constexpr uint64_t kMaxRawBlocks = uint64_t(1) << 34;
// Largest z-plane (x × y blocks): 2^28 (16384 × 16384). A plane is read whole (512 MiB of u16 at
// most) and the chunks of a layer of 32 planes it touches are staged dense (64 KiB each): a
// 131072 × 131072 plane asked for 32 GiB at once, and aborted.
inline constexpr uint64_t kMaxRawPlaneBlocks = uint64_t(1) << 28;

// Reads `path` into `world`, streaming one chunk layer (32 z-planes) at a time. Checks the file
// size against dims × type size and reports a clear error on any mismatch or I/O failure; on
// error `world` may hold part of the volume.
Result<RawVolumeStats> load_raw_volume(const std::string& path, const RawVolumeDesc& desc, World& world);

// Writes a box of `world` as a raw volume (the inverse of load_raw_volume).
Status save_raw_volume(const std::string& path, const RawVolumeDesc& desc, const World& world);

} // namespace vx::world
