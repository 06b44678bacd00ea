#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

const world::BlockRegistry& reg() { return world::BlockRegistry::default_registry(); }

// A floor y in [0, 4): stone for x < 16, sand for x >= 16, over one chunk (x, z in [0, 32)).
world::World floor_world() {
    world::World w;
    test::fill_box(w, {0, 0, 0}, {16, 4, 32}, test::block_id("stone"));
    test::fill_box(w, {16, 0, 0}, {32, 4, 32}, test::block_id("sand"));
    return w;
}

TEST_F(RendererTest, FlatRenderShowsSkyAndBlockColours) {
    world::World w = floor_world();
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.mode = ShadingMode::Flat;
    // Eye 6.5 blocks above the floor top, looking along -z: the image's lower half sees the floor
    // (the bottom row's ray descends 30 degrees and lands at z ~ 5, inside the chunk), the upper
    // half sees the sky.
    const Camera cam = Camera::look_at({16.0, 10.5, 16.5}, {16.0, 10.5, 0.0});
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "flat_floor");
    ASSERT_EQ(img.width, 64u);
    EXPECT_TRUE(test::rgb_near(img.at(32, 0), s.sky));
    EXPECT_TRUE(test::rgb_near(img.at(0, 0), s.sky));
    EXPECT_TRUE(test::rgb_near(img.at(4, 63), reg().info(test::block_id("stone")).albedo));
    EXPECT_TRUE(test::rgb_near(img.at(59, 63), reg().info(test::block_id("sand")).albedo));
    EXPECT_EQ(m_renderer->last_stats().instances, 1u);
    EXPECT_EQ(m_renderer->last_stats().blas_builds, 1u);
}

TEST_F(RendererTest, OneCallSceneApiReplacesTheScene) {
    world::World w = floor_world();
    const world::MeshMap meshes = test::mesh_world(w);
    Scene scene;
    for (const auto& [c, mc] : meshes)
        scene.chunks.emplace_back(c, &mc.mesh);
    m_renderer->set_chunk({5, 5, 5}, meshes.begin()->second.mesh); // Dropped by the next call.
    RenderSettings s;
    s.mode = ShadingMode::Flat;
    const RenderImage img = m_renderer->render(s, Camera::look_at({16.0, 10.5, 16.5}, {16.0, 10.5, 0.0}), scene);
    EXPECT_TRUE(test::rgb_near(img.at(4, 63), reg().info(test::block_id("stone")).albedo));
    EXPECT_EQ(m_renderer->last_stats().instances, 1u);
}

TEST_F(RendererTest, EmptySceneIsAllSky) {
    RenderSettings s;
    s.mode = ShadingMode::Full;
    s.sky = {0.2f, 0.4f, 0.6f};
    const RenderImage img = m_renderer->render(s, Camera{});
    // Full mode encodes sRGB; all pixels equal.
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x)
            ASSERT_EQ(img.at(x, y), img.at(0, 0));
    EXPECT_EQ(m_renderer->last_stats().instances, 0u);
}

TEST_F(RendererTest, FullRenderLightsTheFloor) {
    world::World w = floor_world();
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.width = 128;
    s.height = 96;
    s.mode = ShadingMode::Full;
    s.light.block = {0, 30, 0};
    // This test is about the area light alone: no sun, no sky term (lighting_test.cpp has those).
    s.sun.irradiance = glm::vec3(0.f);
    s.sky_light = 0.f;
    const RenderImage img = m_renderer->render(s, Camera::look_at({16.0, 10.5, 40.5}, {16.0, 0.0, 10.0}));
    test::maybe_save(img, "full_floor");
    // The image centre looks at the floor top near (16, 4, 18), which faces the light: lit.
    const glm::u8vec4 px = img.at(64, 48);
    EXPECT_GT(int(px.r) + px.g + px.b, 100);
    // The bottom rows see the slab's +z side (y 0..4 at z = 32), facing away from the light: black.
    EXPECT_EQ(img.at(64, 94), glm::u8vec4(0, 0, 0, 255));
    // With the sky term that side is lit by the sky (it sees half of it), no longer black.
    s.sky_light = 1.f;
    const glm::u8vec4 sky_lit = m_renderer->render(s, Camera::look_at({16.0, 10.5, 40.5}, {16.0, 0.0, 10.0})).at(64, 94);
    EXPECT_GT(int(sky_lit.r) + sky_lit.g + sky_lit.b, 60);
}

} // namespace
} // namespace vx::render
