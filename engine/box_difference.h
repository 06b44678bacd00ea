#pragma once
// Visiting what a moving box gained or lost: the streamers (engine/chunk_streamer.h,
// engine/lod_streamer.h) keep per-frame work proportional to what moved, not to the box.
// Coordinates: chunk coordinates of any one level. Thread-safe (pure).

#include <algorithm>

#include <glm/glm.hpp>

#include "world/coords.h"

namespace vx::engine {

// Calls f(c) for every chunk c of the box around `a` that is not in the box around `b` (half
// widths r horizontally, rv vertically), or of the whole box when `all`. A one-chunk move visits
// one slab of the box, plus (2r+1)(2rv+1) cheap range tests: no hash lookups outside the slab.
template <class F>
void for_each_in_difference(world::ChunkCoord a, world::ChunkCoord b, bool all, int r, int rv, F&& f) {
    const glm::ivec3 half(r, rv, r);
    const glm::ivec3 lo = a - half, hi = a + half;
    const glm::ivec3 blo = all ? glm::ivec3(1) : b - half, bhi = all ? glm::ivec3(0) : b + half; // all: empty b.
    for (int x = lo.x; x <= hi.x; ++x) {
        const bool in_x = x >= blo.x && x <= bhi.x;
        for (int y = lo.y; y <= hi.y; ++y) {
            if (!in_x || y < blo.y || y > bhi.y) {
                for (int z = lo.z; z <= hi.z; ++z)
                    f(world::ChunkCoord(x, y, z));
                continue;
            }
            for (int z = lo.z; z <= std::min(hi.z, blo.z - 1); ++z)
                f(world::ChunkCoord(x, y, z));
            for (int z = std::max(lo.z, bhi.z + 1); z <= hi.z; ++z)
                f(world::ChunkCoord(x, y, z));
        }
    }
}

} // namespace vx::engine
