// The raster baseline against the ray tracer: same chunks, same camera.
#include <cstdio>

#include "scene_util.h"

#include "render/image_metrics.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Sky pixels: the sky colour (Flat mode writes the linear sky unencoded), no block's albedo.
bool is_sky(glm::u8vec4 px, glm::vec3 sky) { return test::rgb_near(px, sky); }

TEST_F(RendererTest, RasterFlatCoversThePixelsTheRayTracerDoes) {
    world::World w = test::hills();
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.width = 96;
    s.height = 64;
    s.mode = ShadingMode::Flat;
    const Camera cam = Camera::look_at({-45.3, 22.2, -40.7}, {0.0, 6.0, 0.0});
    const RenderImage rt = m_renderer->render(s, cam);
    s.pipeline = PipelineKind::Raster;
    const RenderImage raster = m_renderer->render(s, cam);
    test::maybe_save(rt, "raster_vs_rt_rt");
    test::maybe_save(raster, "raster_vs_rt_raster");
    uint32_t sky = 0, coverage_diff = 0, colour_diff = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const bool a = is_sky(rt.at(x, y), s.sky), b = is_sky(raster.at(x, y), s.sky);
            sky += a;
            coverage_diff += a != b;
            colour_diff += rt.at(x, y) != raster.at(x, y);
        }
    // Both sample at pixel centres: coverage may differ only where a centre lies on a triangle
    // edge (the rasteriser's tie rule against the ray's), a handful of pixels at most.
    std::printf("raster vs ray tracer, %ux%u: %u sky pixels, %u differ in coverage, %u in colour\n", s.width,
                s.height, sky, coverage_diff, colour_diff);
    EXPECT_GT(sky, 100u);
    EXPECT_LT(sky, s.width * s.height - 100u); // The view shows both terrain and sky.
    EXPECT_LE(coverage_diff, s.width * s.height / 200) << coverage_diff << " pixels differ in coverage";
    // Block colours agree too except along block silhouettes (depth ties between faces).
    EXPECT_LE(colour_diff, s.width * s.height / 50) << colour_diff << " pixels differ in colour";
    EXPECT_GT(m_renderer->last_stats().instances, 1u);
}

TEST_F(RendererTest, RasterFullIsLitByThePointLight) {
    world::World w = test::hills();
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.pipeline = PipelineKind::Raster;
    s.mode = ShadingMode::Full;
    s.light.block = {8, 40, 8};
    const Camera cam = Camera::look_at({-45.3, 22.2, -40.7}, {0.0, 6.0, 0.0});
    const RenderImage lit = m_renderer->render(s, cam);
    s.light.emission = glm::vec3(0.f);
    const RenderImage dark = m_renderer->render(s, cam);
    // Without light every surface is black (no emitters in hills()); with it, many are lit.
    uint32_t brighter = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x)
            brighter += int(lit.at(x, y).r) + lit.at(x, y).g > int(dark.at(x, y).r) + dark.at(x, y).g + 20;
    EXPECT_GT(brighter, s.width * s.height / 10);
}

} // namespace
} // namespace vx::render
