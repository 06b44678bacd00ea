// Terrain to a view distance (engine/scene_loader.h, issue 16) rendered on lavapipe with the
// validation layer on: levels of detail against full detail to the same distance. Flat shading
// (block albedo, no haze) and the G-buffer's hit flag (albedo alpha) say which pixels see ground.
// CTest label vulkan.
#include <gtest/gtest.h>

#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "render/renderer.h"
#include "tests/test_device.h"

namespace vx::engine {
namespace {

// A small scene: level 0 within 2 chunks (vertical 1), coarse boxes 2 of their chunks wide, to
// 300 blocks: levels 0..3 (level-k boxes reach 2 * 32 * 2^k = 64, 128, 256, 512 blocks).
SceneLoadInfo small_view(bool lod) {
    SceneLoadInfo info;
    info.kind = SceneKind::Terrain;
    info.seed = 1;
    info.radius = 2;
    info.vradius = 1;
    info.view_distance = 300;
    info.lod_ring = 2;
    info.lod = lod;
    return info;
}

render::Camera default_camera(const LoadedScene& scene) {
    render::Camera cam;
    cam.block = scene.default_eye->block;
    cam.offset = glm::vec3(scene.default_eye->frac);
    cam.forward = glm::vec3(glm::dvec3(scene.default_target->block - scene.default_eye->block) +
                            (scene.default_target->frac - scene.default_eye->frac));
    return cam;
}

// 1 where the flat-shaded primary ray hit something.
std::vector<uint8_t> hits(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam) {
    render::GBufferImage g;
    r.render(s, cam, &g);
    std::vector<uint8_t> out(g.albedo.size());
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = g.albedo[i].a > 0.5f;
    return out;
}

TEST(LodScene, CoversEveryGroundPixelOfFullDetail) {
    JobSystem jobs(batch_job_system_info(2));
    auto lod = load_scene(jobs, small_view(true));
    ASSERT_TRUE(lod) << lod.error();
    auto full = load_scene(jobs, small_view(false));
    ASSERT_TRUE(full) << full.error();
    // The LOD scene is the cut: level 0 near the eye, coarse chunks (levels 1..3) beyond.
    EXPECT_EQ(lod->top_level, 3);
    EXPECT_GT(lod->levels[0].meshed, 0u);
    for (int k = 1; k <= 3; ++k)
        EXPECT_GT(lod->levels[size_t(k)].meshed, 0u) << "level " << k;
    EXPECT_EQ(full->top_level, 0);
    EXPECT_TRUE(full->coarse.empty());
    // Fewer chunks and triangles than full detail to the same distance.
    const size_t lod_chunks = lod->meshes.size() + lod->coarse.size();
    EXPECT_LT(2 * lod_chunks, full->meshes.size());
    EXPECT_LT(lod->triangles, full->triangles);
    EXPECT_EQ(lod->volume_box, full->volume_box); // Same box: same default light and view.

    auto choice = render::parse_device_choice(vx::test::test_device());
    ASSERT_TRUE(choice);
    auto created = render::Renderer::create({.validation = true, .device = *choice});
    if (!created)
        GTEST_SKIP() << "no ray-tracing device: " << created.error();
    render::Renderer& r = **created;
    r.set_registry(full->world->registry());
    render::RenderSettings s;
    s.width = 96;
    s.height = 54;
    s.mode = render::ShadingMode::Flat;
    const render::Camera cam = default_camera(*full);

    send_scene(*full, r);
    const std::vector<uint8_t> ground = hits(r, s, cam);
    // Level 0 of the LOD scene alone, then with its coarse chunks.
    r.clear_chunks();
    for (const auto& [c, mc] : lod->meshes)
        if (mc.mesh.quad_count() > 0)
            r.set_chunk(c, mc.mesh);
    const std::vector<uint8_t> near = hits(r, s, cam);
    r.clear_chunks();
    send_scene(*lod, r);
    const std::vector<uint8_t> covered = hits(r, s, cam);
    EXPECT_GT(r.last_stats().level_instances[3], 0u);

    size_t ground_px = 0, uncovered = 0, coarse_px = 0;
    for (size_t i = 0; i < ground.size(); ++i) {
        ground_px += ground[i];
        uncovered += ground[i] && !covered[i];
        coarse_px += covered[i] && !near[i];
    }
    // The default view looks 10 degrees down across the terrain, the horizon in the upper part.
    EXPECT_GT(ground_px, ground.size() / 3);
    EXPECT_LT(ground_px, ground.size()); // Some sky beyond the view distance.
    EXPECT_EQ(uncovered, 0u) << "pixels full detail hits and LOD leaves as sky";
    // A real share of the ground is drawn by coarse chunks (missing with level 0 alone).
    EXPECT_GT(coarse_px, ground_px / 4);
    EXPECT_EQ(r.validation_errors(), 0u);
}

TEST(LodScene, RejectsBadViewDistances) {
    JobSystem jobs(batch_job_system_info(1));
    SceneLoadInfo info = small_view(true);
    info.view_distance = 16385;
    auto r = load_scene(jobs, info);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), "--view-distance must be 1..16384 blocks, got 16385");
    info.view_distance = -5;
    EXPECT_FALSE(load_scene(jobs, info));
    info.view_distance = 300;
    info.lod_ring = 0;
    r = load_scene(jobs, info);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), "--lod-ring must be 1..64 chunks, got 0");
    info = small_view(true);
    info.kind = SceneKind::SeedScene;
    r = load_scene(jobs, info);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), "--view-distance needs generated terrain (--seed)");
}

} // namespace
} // namespace vx::engine
