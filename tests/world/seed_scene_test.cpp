// The thesis seed scene (world/gen/seed_scene.h) is pinned: docs/benchmarks.md and the renderer's
// figures are measured on it, so a change to its generator or to the mesher that moves its size
// must show up here, not as a silent shift in those figures.

#include <cstdint>

#include <gtest/gtest.h>

#include "world/block_registry.h"
#include "world/gen/seed_scene.h"
#include "world/mesh/apron.h"
#include "world/mesh/chunk_mesh.h"
#include "world/mesh/mesher.h"

namespace vx::world {
namespace {

TEST(SeedScene, TriangleCountIsPinned) {
    // 32 x 32 chunks on the XZ plane, each meshed isolated (air apron) with the greedy mesher, as
    // the thesis meshes them. 30,912,940 triangles with the splitmix64 stream (the thesis's C
    // rand() gave 30,917,848: same 10% fill, other numbers). About 30,000 triangles per chunk.
    GreedyMesher mesher;
    ChunkMesh mesh;
    uint64_t triangles = 0, solid = 0;
    for (int z = 0; z < kSeedSceneSide; ++z)
        for (int x = 0; x < kSeedSceneSide; ++x) {
            const Chunk chunk = seed_scene_chunk({x, 0, z});
            for (int i = 0; i < kChunkVolume; ++i)
                solid += chunk.get(i) != kAir;
            mesher.mesh({chunk, Apron::air(), BlockRegistry::default_registry()}, mesh);
            triangles += mesh.triangle_count();
        }
    EXPECT_EQ(triangles, 30'912'940u);
    // The fill is 10%: 1024 chunks of 32,768 blocks hold 3,355,443 solid blocks on average, with
    // a standard deviation of sqrt(n p (1 - p)) = 1,737; the stream is fixed, so this only guards
    // against a degenerate stream (all air or all solid) that might still hit a triangle count.
    EXPECT_NEAR(double(solid), 3'355'443.0, 6 * 1'737.0);
}

} // namespace
} // namespace vx::world
