// The guided denoiser's history over frames: accumulation lowers the error, stale history leaves no ghost.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/glm.hpp>

#include "denoiser_test_util.h"
#include "render/denoiser.h"
#include "render_test_util.h"

namespace vx::render {
namespace {

using test::GBuffer;
using test::kH;
using test::kSkyRows;
using test::kW;
using test::make_scene;
using test::noisy;

using DenoiserTest = test::RenderTest;

TEST_F(DenoiserTest, AccumulationOfAStillCameraLowersTheErrorFurther) {
    const GBuffer g = make_scene();
    for (bool clamp : {false, true}) {
        Denoiser denoiser(*m_ctx, kW, kH);
        DenoiseSettings s;
        s.max_history = 16;
        s.history_clamp = clamp;
        const ImageF first = denoise_on_host(*m_ctx, denoiser, noisy(g, 1, 100), g.albedo, g.normal_depth, s);
        ImageF last = first;
        for (uint32_t frame = 1; frame < 8; ++frame)
            last = denoise_on_host(*m_ctx, denoiser, noisy(g, 1, 100 + frame), g.albedo, g.normal_depth, s);
        std::printf("denoiser 1 spp, still camera, history clamp %s: RMSE frame 1 %.4f, frame 8 %.4f\n",
                    clamp ? "on" : "off", rmse(first, g.reference), rmse(last, g.reference));
        EXPECT_LT(rmse(last, g.reference), 0.7 * rmse(first, g.reference)) << "history clamp " << clamp;
    }
}

// One non-finite input (radiance or a variance past half float's 65504 where a driver stores
// infinity, a distance past it, a NaN) costs at most its own pixel in its own frame. It made the
// whole frame NaN (the a-trous taps of weight 0 still multiplied: 0 * inf) and stayed in the
// history for every frame after; a moving camera dragged it into a streak.
TEST_F(DenoiserTest, ANonFiniteInputCostsOnePixelOneFrame) {
    const GBuffer g = make_scene();
    const float inf = INFINITY, nan = std::nanf("");
    struct Case {
        const char* what;
        int channel; // Of the colour; -1: the distance of a patch.
        float value;
    };
    const Case cases[] = {{"radiance inf", 0, inf}, {"variance inf", 3, inf}, {"radiance nan", 1, nan},
                          {"distance inf", -1, inf}};
    auto non_finite = [](const ImageF& img) {
        int n = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                n += !std::isfinite(img.at(x, y)[0]) || !std::isfinite(img.at(x, y)[1]) || !std::isfinite(img.at(x, y)[2]);
        return n;
    };
    for (const Case& c : cases)
        for (const float move : {0.f, 0.5f}) {
            Denoiser denoiser(*m_ctx, kW, kH);
            DenoiseSettings s;
            s.max_history = 16;
            glm::mat4 reproject(1.f);
            reproject[2][0] = move; // The history pixel is this one + move in x: a moving camera.
            for (uint32_t frame = 0; frame < 12; ++frame) {
                ImageF in = noisy(g, 4, 700 + frame);
                ImageF nd = g.normal_depth;
                if (frame == 0 && c.channel >= 0)
                    in.at(20, 20)[c.channel] = c.value;
                if (frame == 0 && c.channel < 0)
                    for (uint32_t y = 16; y < 20; ++y)
                        for (uint32_t x = 4; x < 10; ++x)
                            nd.at(x, y)[3] = c.value;
                const ImageF out = denoise_on_host(*m_ctx, denoiser, in, g.albedo, nd, s, reproject);
                EXPECT_LE(non_finite(out), frame == 0 ? (c.channel < 0 ? 24 : 1) : 0)
                    << c.what << ", move " << move << ", frame " << frame;
            }
        }
}

TEST_F(DenoiserTest, ChangedBlocksDropTheirHistory) {
    // Accumulate a noise-free scene, then move the wall's edge 8 columns left: those pixels turn
    // from floor (normal +y) to wall (+z), so their history must be rejected and the next frame
    // show the new image, not a blend with the old one.
    const GBuffer before = make_scene(24), after = make_scene(16);
    Denoiser denoiser(*m_ctx, kW, kH);
    DenoiseSettings s;
    s.max_history = 16;
    for (int frame = 0; frame < 4; ++frame)
        denoise_on_host(*m_ctx, denoiser, before.reference, before.albedo, before.normal_depth, s);
    const ImageF out = denoise_on_host(*m_ctx, denoiser, after.reference, after.albedo, after.normal_depth, s);
    EXPECT_LT(rmse(out, after.reference), 0.01);
    // Without rejection the changed columns would average old and new illumination (floor ~1.0,
    // wall ~0.4): an error of about 0.1 there.
    double worst = 0;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 16; x < 24; ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, double(std::abs(out.at(x, y)[c] - after.reference.at(x, y)[c])));
    EXPECT_LT(worst, 0.03);
}

// RMSE over columns [x0, x1) of the surface rows.
double region_rmse(const ImageF& a, const ImageF& b, uint32_t x0, uint32_t x1) {
    double sum = 0;
    size_t n = 0;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c, ++n)
                sum += std::pow(double(a.at(x, y)[c]) - double(b.at(x, y)[c]), 2.0);
    return std::sqrt(sum / double(n));
}

// An edit that shadows part of the floor changes its light but not its normal or depth, so the
// history matches and only the clamp can tell it is stale. Ghost: the frames after the change
// whose error in the shadowed part exceeds 1.25x that of a denoiser that never saw the old light
// (the same noisy frames from a fresh start), the best any history can do.
TEST_F(DenoiserTest, ChangedLightLeavesNoGhostWithTheHistoryClamp) {
    const GBuffer before = make_scene();
    GBuffer after = before;
    constexpr uint32_t kShadowTo = 16; // Floor columns 0..15 fall into shadow: a quarter of the light.
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kShadowTo; ++x)
            for (int c = 0; c < 3; ++c) {
                after.reference.at(x, y)[c] *= 0.25f;
                after.illumination.at(x, y)[c] *= 0.25f;
            }
    constexpr int kWarm = 16, kAfter = 10;
    auto run_after = [&](Denoiser& d, const DenoiseSettings& s) {
        std::vector<double> errors;
        for (int k = 0; k < kAfter; ++k) {
            const ImageF out = denoise_on_host(*m_ctx, d, noisy(after, 4, 5000 + k), after.albedo, after.normal_depth, s);
            errors.push_back(region_rmse(out, after.reference, 0, kShadowTo));
        }
        return errors;
    };
    DenoiseSettings s;
    Denoiser fresh_denoiser(*m_ctx, kW, kH);
    const std::vector<double> fresh = run_after(fresh_denoiser, s);
    double still_error[2] = {};
    int ghost[2] = {};
    for (bool clamp : {false, true}) {
        s.history_clamp = clamp;
        Denoiser d(*m_ctx, kW, kH);
        ImageF still;
        for (int f = 0; f < kWarm; ++f)
            still = denoise_on_host(*m_ctx, d, noisy(before, 4, 100 + f), before.albedo, before.normal_depth, s);
        still_error[clamp] = rmse(still, before.reference);
        const std::vector<double> errors = run_after(d, s);
        int last_bad = -1;
        for (int k = 0; k < kAfter; ++k)
            if (errors[size_t(k)] > 1.25 * fresh[size_t(k)] + 0.002)
                last_bad = k;
        ghost[clamp] = last_bad + 1;
        std::printf("history clamp %s: still RMSE %.4f; shadowed part after the change:", clamp ? "on " : "off",
                    still_error[clamp]);
        for (int k = 0; k < kAfter; ++k)
            std::printf(" %.4f/%.4f", errors[size_t(k)], fresh[size_t(k)]);
        std::printf(" (ours/fresh); ghost %d frames\n", ghost[clamp]);
    }
    EXPECT_GT(ghost[0], 4) << "without the clamp the old light should linger (else this test shows nothing)";
    EXPECT_LE(ghost[1], 4);
    // Still camera: the clamp costs little of accumulation's gain.
    EXPECT_LT(still_error[1], 1.15 * still_error[0]);
}

// A reflection moves over a mirror that stays put (the camera or the reflected block moved): the
// mirror's history matches, so without the clamp the old reflection fades over max_history frames.
TEST_F(DenoiserTest, MovedReflectionLeavesNoGhostWithTheHistoryClamp) {
    const GBuffer g = make_scene();
    auto stripe = [&](uint32_t from) { // A bright reflected stripe 3 columns wide, on the floor.
        ImageF r = ImageF::make(kW, kH);
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c)
                    r.at(x, y)[c] = x >= from && x < from + 3 ? 1.f : 0.1f;
        return r;
    };
    const ImageF before = stripe(4), after = stripe(12);
    auto with = [&](const ImageF& reflected) {
        ImageF in = g.reference;
        for (size_t i = 0; i < in.rgba.size(); ++i)
            if (i % 4 != 3)
                in.rgba[i] += reflected.rgba[i];
        return in;
    };
    double stale[2] = {};
    for (bool clamp : {false, true}) {
        DenoiseSettings s;
        s.history_clamp = clamp;
        Denoiser d(*m_ctx, kW, kH);
        for (int f = 0; f < 12; ++f)
            denoise_on_host(*m_ctx, d, with(before), g.albedo, g.normal_depth, s, glm::mat4(1.f), 60.f, &before);
        const ImageF out = denoise_on_host(*m_ctx, d, with(after), g.albedo, g.normal_depth, s, glm::mat4(1.f), 60.f,
                                           &after);
        ImageF expected = with(after);
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 4; x < 7; ++x) // Where the stripe was.
                for (int c = 0; c < 3; ++c)
                    stale[clamp] = std::max(stale[clamp], double(std::abs(out.at(x, y)[c] - expected.at(x, y)[c])));
        std::printf("moved reflection, history clamp %s: largest error where it was %.4f\n", clamp ? "on" : "off",
                    stale[clamp]);
    }
    EXPECT_GT(stale[0], 0.5) << "without the clamp the old reflection should remain (else this shows nothing)";
    EXPECT_LT(stale[1], 0.03);
}

// The same with the reflection in the mirror light (filtered in the reflected surface's terms):
// its own history is clamped too, so the moved stripe leaves no ghost.
TEST_F(DenoiserTest, MovedMirrorLightLeavesNoGhost) {
    const GBuffer g = make_scene();
    ImageF white = ImageF::make(kW, kH), mirror_nd = g.normal_depth;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            for (int c = 0; c < 4; ++c)
                white.at(x, y)[c] = 1.f;
            mirror_nd.at(x, y)[3] += 5.f;
        }
    auto stripe = [&](uint32_t from) { // Noise-free mirror light (variance 0): a bright stripe.
        ImageF r = ImageF::make(kW, kH);
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c)
                    r.at(x, y)[c] = x >= from && x < from + 3 ? 1.f : 0.1f;
        return r;
    };
    const ImageF before = stripe(4), after = stripe(12), zero = ImageF::make(kW, kH);
    auto with = [&](const ImageF& light) {
        ImageF in = g.reference;
        for (size_t i = 0; i < in.rgba.size(); ++i)
            if (i % 4 != 3)
                in.rgba[i] += light.rgba[i];
        return in;
    };
    Denoiser d(*m_ctx, kW, kH);
    const MirrorImagesF mirror_before{before, white, mirror_nd}, mirror_after{after, white, mirror_nd};
    for (int f = 0; f < 12; ++f)
        denoise_on_host(*m_ctx, d, with(before), g.albedo, g.normal_depth, {}, glm::mat4(1.f), 60.f, &zero,
                        &mirror_before);
    const ImageF out = denoise_on_host(*m_ctx, d, with(after), g.albedo, g.normal_depth, {}, glm::mat4(1.f), 60.f,
                                       &zero, &mirror_after);
    const ImageF expected = with(after);
    double stale = 0;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 4; x < 7; ++x) // Where the stripe was.
            for (int c = 0; c < 3; ++c)
                stale = std::max(stale, double(std::abs(out.at(x, y)[c] - expected.at(x, y)[c])));
    // The same light as the unfiltered reflected part: the box clamp's known lag at the new
    // stripe's edges (a neighbourhood box that holds both levels keeps the history) is shared.
    Denoiser plain(*m_ctx, kW, kH);
    for (int f = 0; f < 12; ++f)
        denoise_on_host(*m_ctx, plain, with(before), g.albedo, g.normal_depth, {}, glm::mat4(1.f), 60.f, &before);
    const ImageF out_plain = denoise_on_host(*m_ctx, plain, with(after), g.albedo, g.normal_depth, {}, glm::mat4(1.f),
                                             60.f, &after);
    std::printf("moved mirror light: largest error where it was %.4f, RMSE %.4f (as the reflected part: %.4f)\n",
                stale, rmse(out, expected), rmse(out_plain, expected));
    EXPECT_LT(stale, 0.03);
    EXPECT_LT(rmse(out, expected), 1.1 * rmse(out_plain, expected) + 0.005);
    // Mirror inputs after frames without them: the mirror history starts empty (no stale or
    // unwritten history), so the noise-free frame comes out as it went in.
    const ImageF switched = denoise_on_host(*m_ctx, plain, with(after), g.albedo, g.normal_depth, {}, glm::mat4(1.f),
                                            60.f, &zero, &mirror_after);
    std::printf("mirror inputs after frames without: RMSE %.4f\n", rmse(switched, expected));
    EXPECT_LT(rmse(switched, expected), 0.01);
}

// A single-frame denoiser (max_history 1) writes no history (kDenoiseKeepHistory), so the frame
// after it must read none, whatever it asks: it equals a new denoiser's first frame. The control,
// the same frames without the single one, reads the history and differs.
TEST_F(DenoiserTest, AFrameAfterASingleFrameReadsNoHistory) {
    const GBuffer g = make_scene();
    DenoiseSettings s;
    s.history_clamp = false;
    auto after_history = [&](Denoiser& denoiser, bool single_frame_between) {
        s.max_history = 16;
        for (uint32_t frame = 0; frame < 3; ++frame)
            denoise_on_host(*m_ctx, denoiser, noisy(g, 1, 300 + frame), g.albedo, g.normal_depth, s);
        if (single_frame_between) {
            s.max_history = 1;
            denoise_on_host(*m_ctx, denoiser, noisy(g, 1, 303), g.albedo, g.normal_depth, s);
            s.max_history = 16;
        }
        return denoise_on_host(*m_ctx, denoiser, noisy(g, 1, 304), g.albedo, g.normal_depth, s);
    };
    Denoiser with_single(*m_ctx, kW, kH), control(*m_ctx, kW, kH), fresh(*m_ctx, kW, kH);
    s.max_history = 16;
    const ImageF first = denoise_on_host(*m_ctx, fresh, noisy(g, 1, 304), g.albedo, g.normal_depth, s);
    const ImageF after_single = after_history(with_single, true);
    const ImageF after_control = after_history(control, false);
    EXPECT_GT(rmse(after_control, first), 1e-3) << "the control read no history: the test would see nothing";
    EXPECT_EQ(after_single.rgba, first.rgba);
}

} // namespace
} // namespace vx::render
