#pragma once
// The thesis's benchmark scene (chapter 6): 32×32×1 chunks of 32³ laid on the XZ plane, each
// block solid with probability 1/10 (`rand() % 10 == 0`). C's rand() is not the same on every
// platform, so a fixed splitmix64 stream per chunk stands in for it: same scene on every run and
// machine, the same statistics as the thesis's. Pure functions; thread-safe.

#include <cstdint>

#include "world/chunk.h"
#include "world/coords.h"

namespace vx::world {

inline constexpr uint64_t kSeedSceneSeed = 2020;
inline constexpr int kSeedSceneSide = 32; // Chunks per side: 1024 chunks.

// Chunk (cx, 0, cz) of the seed scene, 0 <= cx, cz < side: air or `block`.
Chunk seed_scene_chunk(ChunkCoord c, uint64_t seed = kSeedSceneSeed, BlockId block = 1, int percent = 10);

// A random chunk where each block is `block` with probability percent/100.
Chunk random_fill_chunk(uint64_t seed, int percent, BlockId block);

} // namespace vx::world
