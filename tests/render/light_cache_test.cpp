// The light cache (render/light_cache.h, shaders/shared/light_cache.glsl) on lavapipe: hits that
// share their light through the cache give a frame with far less noise and nearly the same long
// mean; a table too small for the frame's cells, and no memory for the cache, lose no light.
#include <cmath>
#include <cstdio>
#include <utility>

#include "render/image_metrics.h"
#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// A small version of issue 18's hidden-style scene: a checker floor of stone and sand, a mirror
// wall, two pillars and an overhang casting soft shadows.
world::World courtyard() {
    world::World w;
    const world::BlockId stone = test::block_id("stone"), sand = test::block_id("sand");
    for (int x = 0; x < 24; ++x)
        for (int z = 0; z < 24; ++z)
            w.set_block({x, 0, z}, ((x / 2 + z / 2) & 1) ? sand : stone);
    test::fill_box(w, {0, 1, 0}, {24, 7, 1}, test::block_id("mirror"));
    test::fill_box(w, {5, 1, 6}, {7, 5, 8}, stone);
    test::fill_box(w, {15, 1, 4}, {17, 5, 6}, stone);
    test::fill_box(w, {4, 5, 3}, {18, 6, 10}, stone);
    return w;
}

const Camera kView = Camera::look_at({21.0, 4.0, 16.0}, {10.0, 1.5, 2.0}, {0, 1, 0}, 60.f);

RenderSettings lit(uint32_t spp, bool cache) {
    RenderSettings s;
    s.width = 48;
    s.height = 32;
    s.shadow_samples = spp;
    s.max_bounces = 2;
    s.light_cache = cache;
    return s;
}

// The root mean square over seeds 1-2 of one frame's RMSE against `reference`.
double one_frame_error(Renderer& r, RenderSettings s, const ImageF& reference) {
    double e2 = 0;
    for (uint32_t seed = 1; seed <= 2; ++seed) {
        s.seed = seed;
        const double e = rmse(to_float(r.render(s, kView)), reference);
        e2 += e * e / 2;
    }
    return std::sqrt(e2);
}

// The cache's frame has far less noise than the hits' own samples, and its long mean (its bias:
// the light's change over a cell, which the resolve weighs against the noise) stays close to
// the plain mean.
// A light-cache width or a sampling exponent that is not finite means the default (renderer.h):
// accumulated frames with it are the default's frames, byte for byte. NaN compared unequal to
// itself, so the history restarted in every frame and never accumulated.
TEST(RendererSettings, NonFiniteMeansTheDefaultAndKeepsTheHistory) {
    const world::MeshMap meshes = test::mesh_world(courtyard());
    auto frame_8 = [&](const RenderSettings& s) {
        std::unique_ptr<Renderer> r = test::make_renderer();
        EXPECT_NE(r, nullptr);
        if (!r)
            return RenderImage{};
        test::load_meshes(*r, meshes);
        RenderImage img;
        for (int i = 0; i < 8; ++i)
            img = r->render(s, kView);
        EXPECT_EQ(r->validation_errors(), 0u);
        return img;
    };
    RenderSettings cached = lit(2, true), weighted = lit(2, false);
    cached.accumulate = weighted.accumulate = 8;
    cached.denoise = true;
    weighted.samples_by_weight = true;
    RenderSettings nan_cell = cached, nan_exponent = weighted;
    nan_cell.light_cache_pixels = nan_exponent.weight_exponent = std::nanf("");
    for (const auto& [given, nan] : {std::pair{cached, nan_cell}, std::pair{weighted, nan_exponent}})
        EXPECT_EQ(test::differing_bytes(frame_8(given), frame_8(nan)), 0) << "light cache " << given.light_cache;
}

TEST_F(RendererTest, SharedLightHasLessNoiseAndNearlyTheSameMean) {
    test::load_meshes(*m_renderer, test::mesh_world(courtyard()));
    RenderSettings ref_s = lit(16, false);
    ref_s.seed = 1000;
    const RenderImage ref = test::accumulated(*m_renderer, ref_s, kView, 32, 16);
    const ImageF reference = to_float(ref);
    const double own = one_frame_error(*m_renderer, lit(4, false), reference);
    const double shared = one_frame_error(*m_renderer, lit(4, true), reference);
    const RenderImage cached_mean = test::accumulated(*m_renderer, lit(16, true), kView, 32, 16);
    const double bias = rmse(to_float(cached_mean), reference);
    std::printf("4 spp one frame RMSE: own samples %.5f, light cache %.5f; cached long mean against the plain "
                "one: RMSE %.5f, mean byte %.3f against %.3f\n",
                own, shared, bias, test::mean_byte(cached_mean), test::mean_byte(ref));
    test::maybe_save(ref, "light_cache_reference");
    test::maybe_save(cached_mean, "light_cache_mean");
    EXPECT_LT(shared, 0.75 * own);
    EXPECT_LT(bias, 0.5 * shared);
    EXPECT_NEAR(test::mean_byte(cached_mean) / test::mean_byte(ref), 1.0, 0.01);
    // Samples by weight: each hit's samples (in its record) weigh its share of the cell's mean.
    RenderSettings own_weighted = lit(4, false), cached_weighted = lit(4, true);
    own_weighted.samples_by_weight = cached_weighted.samples_by_weight = true;
    const double own_w = one_frame_error(*m_renderer, own_weighted, reference);
    const double shared_w = one_frame_error(*m_renderer, cached_weighted, reference);
    std::printf("samples by weight: own samples %.5f, light cache %.5f\n", own_w, shared_w);
    EXPECT_LT(shared_w, 0.75 * own_w);
}

// A table of 4 cells: all but a few hits find their probes taken and add their own light as with
// the cache off; the frame differs from that only where the few claimed cells are seen.
TEST_F(RendererTest, AFullTableKeepsEachHitsOwnLight) {
    test::load_meshes(*m_renderer, test::mesh_world(courtyard()));
    const RenderImage own = m_renderer->render(lit(4, false), kView);
    m_renderer->limit_light_cache_cells(4);
    const RenderImage full = m_renderer->render(lit(4, true), kView);
    m_renderer->limit_light_cache_cells(0);
    const RenderImage sized = m_renderer->render(lit(4, true), kView);
    const int differ_full = test::differing_bytes(full, own), differ_sized = test::differing_bytes(sized, own);
    std::printf("bytes differing from the own samples' frame: 4 cells %d, sized table %d of %zu\n", differ_full,
                differ_sized, own.rgba.size());
    EXPECT_LT(differ_full, int(own.rgba.size() / 10));
    EXPECT_GT(differ_sized, 4 * std::max(differ_full, 1));
    EXPECT_NEAR(test::mean_byte(full) / test::mean_byte(own), 1.0, 0.01);
}

// Out of GPU memory for the cache's table or records: a one-line error, no abort; the next frame
// renders as a renderer that never failed does (float sums in another order: within a step).
TEST_F(RendererTest, NoMemoryForTheLightCacheIsAnErrorThenTheNextFrameRenders) {
    const world::MeshMap meshes = test::mesh_world(courtyard());
    const RenderImage expected = test::fresh_render(meshes, lit(4, true), kView);

    test::load_meshes(*m_renderer, meshes);
    for (const char* what : {"light cache table", "light cache records"}) {
        m_renderer->fail_allocations(what);
        Result<RenderImage> failed = m_renderer->try_render(lit(4, true), kView);
        ASSERT_FALSE(failed) << what;
        EXPECT_NE(failed.error().find("out of GPU memory for the light cache"), std::string::npos) << failed.error();
        EXPECT_EQ(failed.error().find('\n'), std::string::npos);
    }
    m_renderer->fail_allocations("");
    Result<RenderImage> img = m_renderer->try_render(lit(4, true), kView);
    ASSERT_TRUE(img) << img.error();
    ASSERT_EQ(img->rgba.size(), expected.rgba.size());
    EXPECT_LE(test::largest_step(*img, expected), 1);
}

} // namespace
} // namespace vx::render
