// `vx render --versus-raw` (tools/render_versus.h): the quartiles it prints, the raw frame it
// compares with, interleaving that leaves the view's frames as they were, and a failed frame
// that stops it with the renderer's line. Lavapipe, validation on.
#include <gtest/gtest.h>

#include "render_versus.h"
#include "scene_util.h"

namespace vx::tools {
namespace {

TEST(RenderVersus, QuartilesAreTheMediansOfTheHalves) {
    const Quartiles even = quartiles({8, 1, 7, 2, 6, 3, 5, 4});
    EXPECT_DOUBLE_EQ(even.q1, 2.5);
    EXPECT_DOUBLE_EQ(even.median, 4.5);
    EXPECT_DOUBLE_EQ(even.q3, 6.5);
    const Quartiles odd = quartiles({5, 1, 4, 2, 3}); // The median (3) is in neither half.
    EXPECT_DOUBLE_EQ(odd.q1, 1.5);
    EXPECT_DOUBLE_EQ(odd.median, 3);
    EXPECT_DOUBLE_EQ(odd.q3, 4.5);
    const Quartiles one = quartiles({2});
    EXPECT_DOUBLE_EQ(one.q1, 2);
    EXPECT_DOUBLE_EQ(one.q3, 2);
    EXPECT_DOUBLE_EQ(quartiles({}).median, -1);
}

TEST(RenderVersus, TheRawFrameHasTheSamplesAndNothingElse) {
    render::RenderSettings s;
    s.shadow_samples = 4;
    s.bounce_shadow_samples = 2;
    s.samples_by_weight = true;
    s.denoise = true;
    s.accumulate = 8;
    s.light_cache = true;
    s.max_bounces = 3;
    const render::RenderSettings raw = raw_settings(s, 25);
    EXPECT_EQ(raw.shadow_samples, 25u);
    EXPECT_EQ(raw.bounce_shadow_samples, std::optional<uint32_t>(25u));
    EXPECT_FALSE(raw.samples_by_weight);
    EXPECT_FALSE(raw.denoise);
    EXPECT_EQ(raw.accumulate, 1u);
    EXPECT_FALSE(raw.light_cache);
    EXPECT_EQ(raw.max_bounces, 3u); // The scene's settings stay.
}

class RenderVersusFrames : public render::test::RendererTest {};

// The figures are the pairs' (a ratio within its quartiles), and a denoised frame after the
// interleaved raw ones is the frame a fresh renderer makes: the comparison changes nothing it times.
TEST_F(RenderVersusFrames, InterleavedFramesLeaveTheViewsFrameAsItWas) {
    render::Renderer& r = *m_renderer;
    render::test::load_meshes(r, render::test::mesh_world(render::test::hills()));
    render::RenderSettings s = render::test::daylight(2);
    s.width = 32;
    s.height = 24;
    s.denoise = true;
    s.light_cache = true;
    s.denoise_passes = 2;
    const render::Camera cam = render::Camera::look_at(glm::dvec3(-6, 14, -6), glm::dvec3(16, 2, 16));
    const render::RenderImage before = r.render(s, cam);
    const VersusFigures f = versus_raw(r, s, cam, 8, 3);
    ASSERT_TRUE(f.failure.empty()) << f.failure;
    EXPECT_EQ(f.pairs, 3u);
    EXPECT_GT(f.frame_ms, 0.0);
    EXPECT_GT(f.raw_ms, 0.0);
    EXPECT_LE(f.ratio_q1, f.ratio);
    EXPECT_LE(f.ratio, f.ratio_q3);
    EXPECT_GT(f.ratio_q1, 0.0);
    const render::RenderImage after = r.render(s, cam);
    ASSERT_EQ(after.rgba.size(), before.rgba.size());
    EXPECT_EQ(after.rgba, before.rgba);
    const std::string line = format_versus(f, 8);
    EXPECT_NE(line.find("versus 8 spp raw, frames interleaved (3 pairs)"), std::string::npos) << line;
}

// A lost device stops it at the first frame: its line, no figures.
TEST_F(RenderVersusFrames, AFailedFrameStopsItWithTheRenderersLine) {
    render::Renderer& r = *m_renderer;
    render::RenderSettings s = render::test::daylight(1);
    s.width = 16;
    s.height = 12;
    s.denoise = true;
    const render::Camera cam = render::Camera::look_at(glm::dvec3(0.5, 8.5, 0.5), glm::dvec3(8.5, 0.5, 8.5));
    r.render(s, cam);
    r.simulate_device_loss();
    const VersusFigures f = versus_raw(r, s, cam, 4, 2);
    EXPECT_NE(f.failure.find("lost"), std::string::npos) << f.failure;
    EXPECT_EQ(f.pairs, 0u);
    EXPECT_EQ(f.ratio, -1.0);
    EXPECT_EQ(f.frame_ms, -1.0);
}

} // namespace
} // namespace vx::tools
