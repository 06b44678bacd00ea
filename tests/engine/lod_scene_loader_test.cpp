// Terrain to a view distance without a GPU (engine/scene_loader.h, issue 16): the LOD scene's
// chunks cover every chunk of the full-detail scene exactly once, and its coarse chunks, made by
// pool jobs, are generate_lod() meshed with air aprons.
#include <gtest/gtest.h>

#include <unordered_set>

#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/mesh/mesher.h"

namespace vx::engine {
namespace {

using world::LodCoord;

// Level 0 within 2 chunks (vertical 1), coarse boxes 2 of their chunks wide, to 200 blocks:
// levels 0..2 (level-k boxes reach 2 * 32 * 2^k = 64, 128, 256 blocks).
SceneLoadInfo view(bool lod) {
    SceneLoadInfo info;
    info.kind = SceneKind::Terrain;
    info.seed = 5;
    info.radius = 2;
    info.vradius = 1;
    info.view_distance = 200;
    info.lod_ring = 2;
    info.lod = lod;
    return info;
}

TEST(LodSceneLoader, CoversFullDetailExactlyOnceWithCoarseChunksMeshedInIsolation) {
    JobSystem jobs(batch_job_system_info(2));
    auto lod = load_scene(jobs, view(true));
    ASSERT_TRUE(lod) << lod.error();
    auto full = load_scene(jobs, view(false));
    ASSERT_TRUE(full) << full.error();
    ASSERT_EQ(lod->top_level, 2);

    std::unordered_set<LodCoord, world::LodCoordHash> drawn;
    for (const auto& [c, mc] : lod->meshes)
        drawn.insert({0, c});
    for (const auto& [c, mesh] : lod->coarse)
        drawn.insert(c);
    EXPECT_EQ(drawn.size(), lod->meshes.size() + lod->coarse.size());
    // Exactly one of each full-detail chunk and its ancestors is drawn: no gap, no overlap.
    for (const auto& [c, mc] : full->meshes) {
        int found = 0;
        for (int k = 0; k <= lod->top_level; ++k)
            found += int(drawn.count(world::lod_ancestor({0, c}, k)));
        EXPECT_EQ(found, 1) << "chunk " << c.x << "," << c.y << "," << c.z;
    }
    // Full detail spans the terrain's height: y -48..162 is chunk rows -2..5.
    int lo = 0, hi = 0;
    for (const auto& [c, mc] : full->meshes) {
        lo = std::min(lo, c.y);
        hi = std::max(hi, c.y);
    }
    EXPECT_EQ(lo, -2);
    EXPECT_EQ(hi, 5);

    // Every coarse chunk is its generate_lod() chunk meshed alone, with air around it.
    const world::TerrainGenerator gen(5);
    world::GreedyMesher mesher;
    const world::Apron air = world::Apron::air();
    uint64_t quads = 0;
    for (const auto& [c, mesh] : lod->coarse) {
        const Result<world::Chunk> chunk = world::generate_lod(gen, c);
        ASSERT_TRUE(chunk);
        world::ChunkMesh expected;
        mesher.mesh({*chunk, air, lod->world->registry()}, expected);
        EXPECT_TRUE(mesh == expected) << "level " << c.level;
        quads += mesh.quad_count();
        EXPECT_GE(c.level, 1);
    }
    EXPECT_GT(quads, 0u);
    EXPECT_EQ(lod->levels[1].quads + lod->levels[2].quads, quads);
    EXPECT_EQ(lod->levels[0].chunks, lod->meshes.size());
}

// An eye far above the terrain with a wide ring: the coarse boxes reach down to the terrain from
// 65,000 blocks up and would hold 27 million chunks (`vx render --view-distance 4096 --lod-ring 64
// --eye 0,65000,0`): refused with the count, as the engine refuses such settings at create.
TEST(LodSceneLoader, TooManyCoarseChunksAreRefused) {
    JobSystem jobs(batch_job_system_info(1));
    SceneLoadInfo info = view(true);
    info.view_distance = 4096;
    info.lod_ring = 64;
    info.eye = WorldPos{{0, 65000, 0}, glm::dvec3(0.5)};
    auto scene = load_scene(jobs, info);
    ASSERT_FALSE(scene);
    EXPECT_NE(scene.error().find("coarse chunks around the eye (at most 1048576)"), std::string::npos) << scene.error();
    info.eye.reset(); // The same settings from the default eye, near the ground, load.
    info.view_distance = 300;
    info.lod_ring = 2;
    EXPECT_TRUE(load_scene(jobs, info));
}

} // namespace
} // namespace vx::engine
