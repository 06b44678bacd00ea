#include "world/gen/seed_scene.h"

#include <vector>

namespace vx::world {
namespace {

// splitmix64 (Steele, Lea, Flood 2014): a fast, well-mixed 64-bit stream.
uint64_t splitmix64(uint64_t& s) {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

} // namespace

Chunk random_fill_chunk(uint64_t seed, int percent, BlockId block) {
    std::vector<BlockId> ids(kChunkVolume);
    uint64_t s = seed;
    for (int i = 0; i < kChunkVolume; i += 2) {
        // Two draws per 64-bit value; (x mod 100) of a 32-bit value is biased by < 1e-7.
        const uint64_t r = splitmix64(s);
        ids[i] = uint32_t(r) % 100 < uint32_t(percent) ? block : kAir;
        ids[i + 1] = uint32_t(r >> 32) % 100 < uint32_t(percent) ? block : kAir;
    }
    return Chunk::from_dense(ids);
}

Chunk seed_scene_chunk(ChunkCoord c, uint64_t seed, BlockId block, int percent) {
    const uint64_t chunk_seed = seed * 0x100000001B3ull ^ (uint64_t(uint32_t(c.x)) << 32 | uint32_t(c.z));
    return random_fill_chunk(chunk_seed, percent, block);
}

} // namespace vx::world
