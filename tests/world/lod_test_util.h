#pragma once
// Helpers shared by the world-side level-of-detail tests (lod_test.cpp, lod_coarse_terrain_test.cpp):
// a chunk's dense ids, and the pointers downsample() takes to 8 children.

#include <array>
#include <vector>

#include "world/lod/downsample.h"
#include "world/lod/lod_coords.h"

namespace vx::world::test {

inline std::vector<BlockId> dense_of(const Chunk& c) {
    std::vector<BlockId> d(kChunkVolume);
    c.to_dense(d);
    return d;
}

inline std::array<const Chunk*, kLodChildren> pointers(const std::array<Chunk, kLodChildren>& kids) {
    std::array<const Chunk*, kLodChildren> p;
    for (size_t i = 0; i < p.size(); ++i)
        p[i] = &kids[i];
    return p;
}

} // namespace vx::world::test
