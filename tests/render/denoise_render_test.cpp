// The denoiser wired to the ray tracer's G-buffer: `RenderSettings::denoise` / `accumulate`.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene_util.h"

#include "render/image_metrics.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Hills under the area light, soft shadows: a view with sky, lit and shadowed ground.
RenderSettings soft_shadow_settings() {
    RenderSettings s;
    s.width = 128;
    s.height = 80;
    s.mode = ShadingMode::Full;
    s.light.block = {-8, 24, -8};
    s.light.edge_u = {12, 0, 0};
    s.light.edge_v = {0, 0, 12};
    s.max_bounces = 0;
    return s;
}

const Camera kView = Camera::look_at({-22.3, 17.2, -20.7}, {0.0, 6.0, 0.0});

TEST_F(RendererTest, DenoiserLeavesANoiseFreeFrameUnchanged) {
    test::load_meshes(*m_renderer, test::mesh_world(test::hills()));
    RenderSettings s = soft_shadow_settings();
    s.shadow_samples = 0; // Lights and sky unoccluded: no sampling, no noise.
    const ImageF plain = to_float(m_renderer->render(s, kView));
    EXPECT_EQ(m_renderer->last_stats().gpu_denoise_ms, 0.0); // Not run: 0, not a barrier's time.
    s.denoise = true;
    const ImageF denoised = to_float(m_renderer->render(s, kView));
    std::printf("noise-free frame, denoised: RMSE %.4f, SSIM %.4f\n", rmse(denoised, plain), ssim(denoised, plain));
    EXPECT_GT(m_renderer->last_stats().gpu_denoise_ms, 0.0);
    // Half-float radiance and 8-bit albedo round trips; edges between faces of one colour.
    EXPECT_LT(rmse(denoised, plain), 0.02);
    EXPECT_GT(ssim(denoised, plain), 0.95);
}

TEST_F(RendererTest, DenoiserLowersTheErrorOfTheRayTracer) {
    test::load_meshes(*m_renderer, test::mesh_world(test::hills()));
    RenderSettings s = soft_shadow_settings();
    // Reference: 48 accumulated frames of 8 samples (384 shadow samples per pixel), no filter,
    // no history clamp (the plain mean: tools/bench_render_frames.h, render_reference()).
    const RenderImage ref8 = test::accumulated(*m_renderer, s, kView, 48, 8);
    const ImageF ref = to_float(ref8);
    test::maybe_save(ref8, "denoise_reference");
    auto measure = [&](const char* what, uint32_t spp, bool denoise, uint32_t frames) {
        s.shadow_samples = spp;
        s.denoise = denoise;
        s.accumulate = frames;
        RenderImage img;
        for (uint32_t i = 0; i < frames; ++i)
            img = m_renderer->render(s, kView);
        const ImageError e = compare(to_float(img), ref);
        std::printf("ray tracer, %s: RMSE %.4f, PSNR %.1f dB, SSIM %.3f\n", what, e.rmse, e.psnr, e.ssim);
        return e;
    };
    // 1 spp: the spatial filter alone removes most of the noise.
    const ImageError noisy1 = measure("1 spp", 1, false, 1), filtered1 = measure("1 spp denoised", 1, true, 1);
    EXPECT_LT(filtered1.rmse, 0.7 * noisy1.rmse);
    EXPECT_GT(filtered1.ssim, noisy1.ssim);
    // The a-trous passes (RenderSettings::denoise_passes): one pass of step 1 reaches 2 pixels
    // and leaves more of 1 spp's noise than the default 5 (62 pixels); 0 is clamped to 1.
    s.denoise_passes = 1;
    const ImageError one_pass = measure("1 spp denoised, 1 pass", 1, true, 1);
    const RenderImage one = m_renderer->render(s, kView);
    s.denoise_passes = 0;
    EXPECT_EQ(m_renderer->render(s, kView).rgba, one.rgba);
    s.denoise_passes = kDefaultDenoisePasses;
    EXPECT_GT(one_pass.rmse, 1.2 * filtered1.rmse);
    // 4 spp: without history the filter's variance is each pixel's own, from its light samples
    // (render/gbuffer.h), so pixel-sized shadow and sky-term detail is not taken for noise (a
    // 3x3 spatial estimate made this frame worse than the raw one). Accumulating 8 frames of a
    // still camera (32 samples) lowers the error by about sqrt(8) where noise dominates.
    const ImageError noisy4 = measure("4 spp", 4, false, 1);
    const ImageError filtered4_single = measure("4 spp denoised", 4, true, 1);
    // 2026-12-01: 0.0287 -> 0.0198 (0.0210, 0.73x, before the first a-trous pass compared
    // neighbours with the centre's blurred luminance and the own variance was averaged over 5x5);
    // 2026-12-02: 0.0181 (0.63x; the sun flag keeps taps off the other side of sun shadows).
    EXPECT_LT(filtered4_single.rmse, 0.66 * noisy4.rmse);
    const ImageError accumulated4 = measure("4 spp, 8 frames accumulated", 4, false, 8);
    EXPECT_LT(accumulated4.rmse, 0.6 * noisy4.rmse);
    s.history_clamp = false;
    const ImageError plain4 = measure("4 spp, 8 frames accumulated, no history clamp", 4, false, 8);
    s.history_clamp = true;
    std::printf("history clamp: accumulated RMSE %.4f against %.4f without\n", accumulated4.rmse, plain4.rmse);
    // The clamp drops a few still pixels' history on noise alone: 0.0103 vs 0.0089 against the
    // plain-mean reference (2026-12-02; the earlier 9-15% were measured against a reference made
    // with the clamp, which shared some of its error).
    EXPECT_LT(accumulated4.rmse, 1.2 * plain4.rmse);
    // With 8 frames of history the filter's variance comes from temporal moments (SVGF), so it
    // keeps the detail: accumulated and filtered also beats the single frame by far.
    const ImageError filtered4 = measure("4 spp, 8 frames accumulated + denoised", 4, true, 8);
    EXPECT_LT(filtered4.rmse, 0.6 * noisy4.rmse);
}

// A mirror wall (x in [-1, 0), facing +x) over a checkered stone and sand floor, with pillars and
// an overhang casting soft shadows from the area light: what the mirror shows is mostly the
// floor's diffuse lighting, noisy at few samples.
world::World mirror_room() {
    world::World w;
    const world::BlockId stone = test::block_id("stone"), sand = test::block_id("sand");
    for (int64_t z = -12; z < 12; ++z)
        for (int64_t x = -1; x < 24; ++x)
            w.set_block({x, 0, z}, ((x + z) & 1) != 0 ? sand : stone);
    test::fill_box(w, {-1, 1, -12}, {0, 8, 12}, test::block_id("mirror"));
    for (int64_t z : {-6, 0, 6})
        test::fill_box(w, {5, 1, z}, {6, 6, z + 1}, stone);
    test::fill_box(w, {2, 6, -12}, {10, 7, 1}, stone); // The overhang.
    return w;
}

RenderSettings mirror_room_settings() {
    RenderSettings s;
    s.width = 80;
    s.height = 48;
    s.mode = ShadingMode::Full;
    s.light.block = {0, 16, -4};
    s.light.edge_u = {10, 0, 0};
    s.light.edge_v = {0, 0, 10};
    s.max_bounces = 2;
    return s;
}

// Looks at the mirror from the floor's side: most of the image is the floor in the mirror.
const Camera kMirrorView = Camera::look_at({3.5, 3.5, 3.5}, {-1.0, 2.0, -2.0});

// The floor seen in the mirror is filtered with its own guides (normal, path length) and
// remodulated by its albedo: the single 4-spp frame's error falls clearly below that of the
// same denoiser leaving reflections unfiltered (RenderSettings::denoise_reflections off), which
// barely beat the raw frame on the mirror.
TEST_F(RendererTest, DenoiserFiltersTheLightSeenInAMirror) {
    test::load_meshes(*m_renderer, test::mesh_world(mirror_room()));
    RenderSettings s = mirror_room_settings();
    // Reference: 32 accumulated frames of 8 samples, no filter, the plain mean (no clamp).
    const RenderImage ref8 = test::accumulated(*m_renderer, s, kMirrorView, 32, 8);
    const ImageF ref = to_float(ref8);
    test::maybe_save(ref8, "mirror_room_reference");
    s.shadow_samples = 4;
    // The mirror's pixels (its albedo in the G-buffer): the error there is printed apart.
    GBufferImage g;
    ASSERT_TRUE(m_renderer->try_render(s, kMirrorView, &g));
    std::vector<bool> mirror(g.albedo.size());
    for (size_t i = 0; i < g.albedo.size(); ++i)
        mirror[i] = std::abs(g.albedo[i].r - 0.9f) < 0.01f && g.albedo[i].a > 0.f;
    auto measure = [&](const char* what, bool denoise, bool reflections) {
        s.denoise = denoise;
        s.denoise_reflections = reflections;
        const RenderImage img = m_renderer->render(s, kMirrorView);
        test::maybe_save(img, what);
        const ImageF f = to_float(img);
        const ImageError e = compare(f, ref);
        double sum = 0;
        size_t n = 0;
        for (size_t i = 0; i < mirror.size(); ++i)
            if (mirror[i]) {
                for (int c = 0; c < 3; ++c)
                    sum += double(f.rgba[i * 4 + c] - ref.rgba[i * 4 + c]) * (f.rgba[i * 4 + c] - ref.rgba[i * 4 + c]);
                n += 3;
            }
        const double on_mirror = std::sqrt(sum / double(std::max<size_t>(n, 1)));
        std::printf("mirror room, %u spp, %s: RMSE %.4f (the mirror's %zu pixels: %.4f), SSIM %.3f\n", s.shadow_samples,
                    what, e.rmse, n / 3, on_mirror, e.ssim);
        return std::pair{e, on_mirror};
    };
    const auto [raw, raw_mirror] = measure("mirror_room_raw", false, true);
    const auto [before, before_mirror] = measure("mirror_room_denoised_unfiltered_reflections", true, false);
    const auto [after, after_mirror] = measure("mirror_room_denoised", true, true);
    s.shadow_samples = 25;
    const auto [raw25, raw25_mirror] = measure("mirror_room_raw_25spp", false, true);
    std::printf("mirror room: 4 spp denoised / 25 spp raw: RMSE %.2fx, the mirror's %.2fx\n", after.rmse / raw25.rmse,
                after_mirror / raw25_mirror);
    ASSERT_GT(std::count(mirror.begin(), mirror.end(), true), int(mirror.size() / 3)); // The view is the mirror's.
    EXPECT_LT(before.rmse, raw.rmse);
    // 2026-12-01, lavapipe: the mirror's pixels 0.0414 -> 0.0247, the image 0.0490 -> 0.0417;
    // since the first a-trous pass compares with the centre's blurred luminance (5x5 own
    // variance): the mirror's pixels 0.0382 -> 0.0224, the image 0.0412 -> 0.0335 (0.0747 raw;
    // 0.0448 before that change). 2026-12-02, with the occluder distance and the sun flag
    // guiding the primary filter (docs/render_report.md), which also filters the mirror blocks'
    // own diffuse light better in both runs: the mirror's pixels 0.0291 -> 0.0221 (0.76x; the
    // bound was 0.75x of the unfiltered run's 0.0382), the image 0.0276 -> 0.0233.
    EXPECT_LT(after_mirror, 0.78 * before_mirror);
    EXPECT_LT(after.rmse, 0.88 * before.rmse);
    EXPECT_LT(after.rmse, 0.35 * raw.rmse);
    EXPECT_GT(after.ssim, before.ssim);
    EXPECT_LT(after_mirror, 0.75 * raw_mirror);
    // Issue 18's one-frame target is 4 spp denoised at most 25 spp raw; reached (2026-12-01,
    // lavapipe): 0.0335 against 0.0192, 1.74x (2.33x before the first pass compared neighbours
    // with the blurred centre; docs/render_report.md); 2026-12-02: 0.0233, 1.21x (the occluder
    // distance and the sun flag). Not met yet: this bound holds what is.
    EXPECT_LT(after.rmse, 1.3 * raw25.rmse);
}

// Noise-free light (shadows off): filtering the mirror's part changes nothing, so the floor's
// checker stays as sharp in the mirror as traced (the light is demodulated by the reflected
// surface's albedo, and the filter's variance is 0).
TEST_F(RendererTest, DenoiserKeepsTheDetailSeenInAMirror) {
    test::load_meshes(*m_renderer, test::mesh_world(mirror_room()));
    RenderSettings s = mirror_room_settings();
    s.shadow_samples = 0;
    const ImageF plain = to_float(m_renderer->render(s, kMirrorView));
    s.denoise = true;
    const RenderImage denoised8 = m_renderer->render(s, kMirrorView);
    test::maybe_save(denoised8, "mirror_room_noise_free_denoised");
    const ImageF denoised = to_float(denoised8);
    std::printf("mirror room, noise-free, denoised: RMSE %.4f, SSIM %.4f\n", rmse(denoised, plain),
                ssim(denoised, plain));
    EXPECT_LT(rmse(denoised, plain), 0.02);
    EXPECT_GT(ssim(denoised, plain), 0.95);
}

// The denoiser's guide in the G-buffer (render/gbuffer.h, reflected a): a floor's occluder
// distance is short in the inner corner at a wall's foot (its sky rays hit the wall within a block
// or two), "none" on an open floor, and negative where the wall keeps the sun off. A raw frame's
// sky rays are occlusion rays: no distance (0), the sun's flag still in the sign.
TEST_F(RendererTest, GBufferHoldsTheOccluderDistanceAndTheSunShadow) {
    RenderSettings s;
    s.width = s.height = 8;
    s.mode = ShadingMode::Full;
    s.denoise = true; // The guide is the denoiser's.
    s.max_bounces = 0;
    s.shadow_samples = 16;
    s.sun.direction = {1.f, 1.f, 0.f}; // The wall (x in [0, 1)) shades the floor at x < 0.
    auto alphas = [&](glm::dvec3 point) {
        GBufferImage g;
        const Camera cam = Camera::look_at(point + glm::dvec3(0, 2, 0), point, {0, 0, -1}, 2.f);
        EXPECT_TRUE(m_renderer->try_render(s, cam, &g));
        std::vector<float> a;
        for (const glm::vec4& r : g.reflected)
            a.push_back(r.a);
        EXPECT_EQ(a.size(), 64u);
        std::printf("occluder distance at (%.1f, %.1f, %.1f): %.3f .. %.3f\n", point.x, point.y, point.z,
                    *std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end()));
        return a;
    };
    world::World w;
    const world::BlockId stone = test::block_id("stone");
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, stone);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    for (float a : alphas({-8.5, 1.0, 0.5})) // Nothing above the floor: no sky ray hits.
        EXPECT_EQ(a, 60000.f);
    test::fill_box(w, {0, 1, -16}, {1, 9, 16}, stone);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    for (float a : alphas({-0.1, 1.0, 0.5})) { // The shaded corner: short, negative.
        EXPECT_LT(a, -0.2f);
        EXPECT_GT(a, -1.f);
    }
    for (float a : alphas({1.1, 1.0, 0.5})) { // The sunlit corner.
        EXPECT_GT(a, 0.2f);
        EXPECT_LT(a, 1.f);
    }
    s.denoise = false;
    for (float a : alphas({-0.1, 1.0, 0.5})) { // Shaded: -0.
        EXPECT_EQ(a, 0.f);
        EXPECT_TRUE(std::signbit(a));
    }
    for (float a : alphas({1.1, 1.0, 0.5})) { // Sunlit: +0.
        EXPECT_EQ(a, 0.f);
        EXPECT_FALSE(std::signbit(a));
    }
    s.denoise = true;
    s.shadow_samples = 0; // No rays traced: unknown.
    for (float a : alphas({1.1, 1.0, 0.5}))
        EXPECT_EQ(a, 0.f);
}

// GBufferImage::display is the output before its 8-bit rounding: raw, denoised (the denoiser's
// output, not the trace's radiance) and flat frames round to the bytes render() returns, and it
// keeps what the rounding drops (the bench's equal-error metric, stop 27).
TEST_F(RendererTest, DisplayValuesAreTheOutputBeforeItsRounding) {
    test::load_meshes(*m_renderer, test::mesh_world(test::hills()));
    RenderSettings s = soft_shadow_settings();
    s.shadow_samples = 2;
    // Largest distance in 8-bit steps between display and output, the mean distance of display
    // from the nearest step, and the share of channels whose trace radiance alone would round to
    // another byte than the output's.
    struct Fit {
        double worst = 0, fraction = 0, raw_off = 0;
    };
    auto fit = [&](const RenderSettings& rs) {
        GBufferImage g;
        const Result<RenderImage> img = m_renderer->try_render(rs, kView, &g);
        EXPECT_TRUE(img);
        EXPECT_EQ(g.display.size(), size_t(rs.width) * rs.height);
        Fit f;
        size_t off = 0;
        const float exposure = gpu::vx_exposure_scale(m_renderer->last_stats().ev100);
        for (size_t i = 0; i < g.display.size(); ++i) {
            const glm::vec3 raw = rs.mode == ShadingMode::Full ? gpu::vx_display(glm::vec3(g.radiance[i]), exposure)
                                                              : glm::vec3(g.radiance[i]);
            for (int c = 0; c < 3; ++c) {
                const double v = double(g.display[i][c]) * 255.0, byte = img->rgba[i * 4 + size_t(c)];
                f.worst = std::max(f.worst, std::abs(v - byte));
                f.fraction += std::abs(v - std::round(v));
                off += std::abs(double(raw[c]) * 255.0 - byte) > 1.0;
            }
        }
        f.fraction /= 3.0 * double(g.display.size());
        f.raw_off = double(off) / (3.0 * double(g.display.size()));
        std::printf("display values, mode %d, denoise %d: worst %.3f steps from the output, mean fraction %.3f, "
                    "trace radiance off on %.3f of channels\n",
                    int(rs.mode), int(rs.denoise), f.worst, f.fraction, f.raw_off);
        return f;
    };
    // Half-float radiance (relative 2^-11) moves a value by at most a few tenths of a step.
    const Fit raw = fit(s);
    EXPECT_LT(raw.worst, 0.8);
    EXPECT_GT(raw.fraction, 0.1); // Uniform fractions would average 0.25.
    EXPECT_EQ(raw.raw_off, 0.0);  // Without the denoiser the trace's radiance is the output.
    s.denoise = true;
    const Fit denoised = fit(s);
    EXPECT_LT(denoised.worst, 0.8);
    EXPECT_GT(denoised.fraction, 0.1);
    EXPECT_GT(denoised.raw_off, 0.05); // The control: the filter moved what it read.
    s.denoise = false;
    s.mode = ShadingMode::Flat;
    const Fit flat = fit(s);
    EXPECT_LT(flat.worst, 0.8);
    // An odd pixel count (41 x 31): each section of the read-back buffer stays aligned to its
    // texel size (albedo's 4 bytes a pixel, second, left the later sections misaligned: validation
    // errors), and what is read back still rounds to the returned bytes.
    s.mode = ShadingMode::Full;
    s.denoise = true;
    s.width = 41;
    s.height = 31;
    const Fit odd = fit(s);
    EXPECT_LT(odd.worst, 0.8);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
