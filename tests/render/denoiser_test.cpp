// The guided denoiser on a synthetic G-buffer with a known noise-free image: two surfaces (a
// floor seen at a slant and a wall), 4x4-pixel albedo tiles, sky rows, smooth illumination.
// Monte Carlo noise is imitated by visibility samples of 0 or 2 (mean 1, variance 1 per sample),
// so n samples per pixel have relative standard deviation 1/sqrt(n). The colour's alpha is the
// pixel's variance as the ray tracer writes it (render/gbuffer.h): 0 noise-free, -1 at 1 sample.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "render/denoiser.h"
#include "render_test_util.h"

namespace vx::render {
namespace {

constexpr uint32_t kW = 48, kH = 32, kSkyRows = 6;

struct GBuffer {
    ImageF reference, albedo, normal_depth, illumination;
};

// `wall_from_x`: columns from here on are the wall (moving it changes the blocks).
GBuffer make_scene(uint32_t wall_from_x = 24) {
    static const glm::vec3 kPalette[5] = {
        {0.8f, 0.2f, 0.2f}, {0.2f, 0.7f, 0.3f}, {0.3f, 0.3f, 0.9f}, {0.9f, 0.8f, 0.3f}, {0.6f, 0.6f, 0.6f}};
    GBuffer g{ImageF::make(kW, kH), ImageF::make(kW, kH), ImageF::make(kW, kH), ImageF::make(kW, kH)};
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            float *ref = g.reference.at(x, y), *alb = g.albedo.at(x, y), *nd = g.normal_depth.at(x, y);
            float* ill = g.illumination.at(x, y);
            if (y < kSkyRows) {
                const glm::vec3 sky{0.5f, 0.7f, 0.9f};
                for (int c = 0; c < 3; ++c)
                    ref[c] = ill[c] = sky[c];
                continue; // Albedo 0, depth 0: a miss.
            }
            const bool wall = x >= wall_from_x;
            const glm::vec3 a = kPalette[((x / 4) * 3 + (y / 4) * 7) % 5];
            const float light = wall ? 0.3f + 0.2f * float(y) / kH : 0.8f + 0.4f * float(x) / kW;
            const glm::vec3 n = wall ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
            const float depth = wall ? 6.f : 2.f + 20.f * float(kH - y) / kH;
            for (int c = 0; c < 3; ++c) {
                alb[c] = a[c];
                ill[c] = light;
                ref[c] = a[c] * light;
                nd[c] = n[c];
            }
            alb[3] = 1.f;
            nd[3] = depth;
            ref[3] = 0.f; // Noise-free.
        }
    return g;
}

// The reference with `spp` visibility samples of 0 or 2 per surface pixel (sky stays exact).
ImageF noisy(const GBuffer& g, uint32_t spp, uint32_t seed) {
    std::mt19937 rng(seed);
    std::bernoulli_distribution visible(0.5);
    ImageF out = g.reference;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            uint32_t hits = 0;
            for (uint32_t s = 0; s < spp; ++s)
                hits += visible(rng);
            const float v = 2.f * float(hits) / float(spp);
            for (int c = 0; c < 3; ++c)
                out.at(x, y)[c] *= v;
            // Variance of the mean illumination: light^2 per sample over spp; unknown at 1 sample.
            const float light = g.illumination.at(x, y)[0];
            out.at(x, y)[3] = spp > 1 ? light * light / float(spp) : -1.f;
        }
    return out;
}

DenoiseSettings spatial_only() {
    DenoiseSettings s;
    s.max_history = 1;
    return s;
}

using DenoiserTest = test::RenderTest;

TEST_F(DenoiserTest, LeavesANoiseFreeImageUnchanged) {
    const GBuffer g = make_scene();
    Denoiser denoiser(*m_ctx, kW, kH);
    const ImageF out = denoise_on_host(*m_ctx, denoiser, g.reference, g.albedo, g.normal_depth, spatial_only());
    // Half floats (11-bit mantissa) and 8-bit albedo bound the round trip at about 0.004.
    EXPECT_LT(rmse(out, g.reference), 0.01);
    EXPECT_GT(ssim(out, g.reference), 0.99);
}

TEST_F(DenoiserTest, LowersTheErrorAt1And4Spp) {
    const GBuffer g = make_scene();
    Denoiser denoiser(*m_ctx, kW, kH);
    for (uint32_t spp : {1u, 4u}) {
        const ImageF in = noisy(g, spp, 7 + spp);
        denoiser.reset_history();
        const ImageF out = denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, spatial_only());
        const double before = rmse(in, g.reference), after = rmse(out, g.reference);
        std::printf("denoiser %u spp: RMSE %.4f -> %.4f, SSIM %.3f -> %.3f\n", spp, before, after,
                    ssim(in, g.reference), ssim(out, g.reference));
        EXPECT_LT(after, 0.5 * before) << spp << " spp: RMSE " << before << " -> " << after;
        EXPECT_GT(ssim(out, g.reference), ssim(in, g.reference)) << spp << " spp";
    }
}

// Pixel-sized detail that the pixel's own variance (0) says is no noise survives; the 3x3
// spatial estimate (variance unknown, -1) takes it for noise and blurs it.
TEST_F(DenoiserTest, KnownNoiseFreeDetailIsKept) {
    GBuffer g = make_scene();
    ImageF unknown = g.reference;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float f = (x + y) % 2 ? 0.5f : 1.5f; // A one-pixel checkerboard of light.
            for (int c = 0; c < 3; ++c)
                g.reference.at(x, y)[c] *= f;
            for (int c = 0; c < 4; ++c)
                unknown.at(x, y)[c] = c < 3 ? g.reference.at(x, y)[c] : -1.f;
        }
    Denoiser denoiser(*m_ctx, kW, kH);
    const DenoiseSettings s = spatial_only();
    const ImageF known = denoise_on_host(*m_ctx, denoiser, g.reference, g.albedo, g.normal_depth, s);
    denoiser.reset_history();
    const ImageF spatial = denoise_on_host(*m_ctx, denoiser, unknown, g.albedo, g.normal_depth, s);
    const double known_error = rmse(known, g.reference), spatial_error = rmse(spatial, g.reference);
    std::printf("checkerboard detail: RMSE %.4f (variance 0), %.4f (spatial estimate)\n", known_error,
                spatial_error);
    EXPECT_LT(known_error, 0.01);
    EXPECT_GT(spatial_error, 0.05);
}

// A shadow one pixel wide (a fence post's, a tenth of the light) in well-sampled light: each
// floor pixel's own standard deviation is 5% of its light. Below 16 samples the first pass
// compares the neighbours with the centre's 3x3 blur, which lies halfway to the lit side, and
// the line takes their light; from 16 samples (prefiltered_luminance(), shaders/
// denoise_atrous.comp) its own light is trusted and the line stays dark.
TEST_F(DenoiserTest, ManySamplesKeepAOnePixelShadow) {
    GBuffer g = make_scene();
    constexpr uint32_t kLine = 10;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            float* ref = g.reference.at(x, y);
            const float light = g.illumination.at(x, y)[0] * (x == kLine ? 0.1f : 1.f);
            for (int c = 0; c < 3; ++c)
                ref[c] = g.albedo.at(x, y)[c] * light;
            ref[3] = (0.05f * light) * (0.05f * light);
        }
    Denoiser denoiser(*m_ctx, kW, kH);
    auto line_gain = [&](uint32_t samples) {
        denoiser.reset_history();
        const ImageF out = denoise_on_host(*m_ctx, denoiser, g.reference, g.albedo, g.normal_depth, spatial_only(),
                                           glm::mat4(1.f), 60.f, nullptr, nullptr, glm::quat(1.f, 0.f, 0.f, 0.f),
                                           samples);
        double sum_out = 0, sum_ref = 0;
        for (uint32_t y = kSkyRows + 2; y < kH - 2; ++y)
            for (int c = 0; c < 3; ++c) {
                sum_out += out.at(kLine, y)[c];
                sum_ref += g.reference.at(kLine, y)[c];
            }
        return sum_out / sum_ref;
    };
    const double few = line_gain(4), unknown = line_gain(0), many = line_gain(16);
    std::printf("one-pixel shadow, its light over the true light: %.3f (4 samples), %.3f (unknown), %.3f (16)\n",
                few, unknown, many);
    EXPECT_GT(few, 1.5) << "the prefilter no longer draws the lit side's light in at a few samples";
    EXPECT_EQ(few, unknown);
    EXPECT_LT(many, 1.15);
}

// Light detail a block or two wide (a random fill's faces, each in its own share of shadow, as
// the thesis-lit glazed volume and terrain show): every 2x2-pixel cell's light is its surface's
// times 0.7-1.3, under well-measured noise (a standard deviation of 8% of the light, the
// variance given exactly), as 16 stratified samples leave it. From kDenoiseManySamples the
// luminance stop narrows (DenoiseSettings::sigma_luminance_many): SVGF's wider stop, made for
// variances from a sample or two, took cells a few deviations apart for noise and blurred them
// together. Over 6 noise seeds the error must fall against the wide stop (left at 4 samples) and
// stay below the raw frame's.
TEST_F(DenoiserTest, ManySamplesKeepBlockSizedLightDetail) {
    GBuffer g = make_scene();
    std::mt19937 cells(5);
    std::uniform_real_distribution<float> share(0.7f, 1.3f);
    std::vector<float> cell(size_t(kW / 2) * (kH / 2));
    for (float& c : cell)
        c = share(cells);
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x)
            for (int c = 0; c < 3; ++c) {
                g.reference.at(x, y)[c] *= cell[(y / 2) * (kW / 2) + x / 2];
                g.illumination.at(x, y)[c] *= cell[(y / 2) * (kW / 2) + x / 2];
            }
    Denoiser denoiser(*m_ctx, kW, kH);
    DenoiseSettings wide = spatial_only();
    wide.sigma_luminance_many = wide.sigma_luminance;
    double raw_sq = 0, narrow_sq = 0, wide_sq = 0;
    for (uint32_t seed = 0; seed < 6; ++seed) {
        std::mt19937 rng(100 + seed);
        std::normal_distribution<float> noise(0.f, 0.08f);
        ImageF in = g.reference;
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const float light = g.illumination.at(x, y)[0], f = 1.f + noise(rng);
                for (int c = 0; c < 3; ++c)
                    in.at(x, y)[c] *= f;
                in.at(x, y)[3] = (0.08f * light) * (0.08f * light);
            }
        auto run = [&](const DenoiseSettings& s) {
            denoiser.reset_history();
            const ImageF out = denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, s, glm::mat4(1.f),
                                               60.f, nullptr, nullptr, glm::quat(1.f, 0.f, 0.f, 0.f), 16);
            const double e = rmse(out, g.reference);
            return e * e;
        };
        const double r = rmse(in, g.reference);
        raw_sq += r * r;
        narrow_sq += run(spatial_only());
        wide_sq += run(wide);
    }
    const double raw = std::sqrt(raw_sq / 6), narrow = std::sqrt(narrow_sq / 6), wide_e = std::sqrt(wide_sq / 6);
    std::printf("block-sized light at 16 samples: RMSE raw %.5f, wide stop %.5f, narrow stop %.5f\n", raw, wide_e,
                narrow);
    EXPECT_LT(narrow, wide_e);
    EXPECT_LT(narrow, raw);
}

// The light's guide (render/gbuffer.h, reflected a), on the floor whose columns 12-23 lie in a
// sun shadow (a fifth of the light): with the sun flag (negative a in the shadow) no tap crosses
// the shadow's edge, so the shadowed pixels next to it take no light from the lit side; with
// "no occluder" (60000) nothing else changes. Where the occluders are far (20 blocks: many
// pixels), the luminance stop relaxes and the smooth light is filtered harder; an occluder a
// third of a block away (under a pixel) leaves the result as without a guide.
TEST_F(DenoiserTest, SunShadowEdgeStaysSharpAndFarOccludersSmoothMore) {
    GBuffer g = make_scene();
    auto shadowed = [](uint32_t x, uint32_t y) { return y >= kSkyRows && x >= 12 && x < 24; };
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x)
            if (shadowed(x, y))
                for (int c = 0; c < 3; ++c) {
                    g.reference.at(x, y)[c] *= 0.2f;
                    g.illumination.at(x, y)[c] *= 0.2f;
                }
    const ImageF in = noisy(g, 4, 21);
    auto guide = [&](float lit, float shade) {
        ImageF r = ImageF::make(kW, kH);
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                r.at(x, y)[3] = shadowed(x, y) ? shade : lit;
        return r;
    };
    // RMSE over columns [x0, x1) of the surface rows.
    auto error = [&](const ImageF& out, uint32_t x0, uint32_t x1) {
        double sum = 0.0, n = 0.0;
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c, n += 1.0)
                    sum += std::pow(double(out.at(x, y)[c] - g.reference.at(x, y)[c]), 2.0);
        return std::sqrt(sum / n);
    };
    Denoiser denoiser(*m_ctx, kW, kH);
    auto run = [&](const ImageF& reflected) {
        denoiser.reset_history();
        return denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, spatial_only(), glm::mat4(1.f),
                               60.f, &reflected);
    };
    const ImageF none = run(ImageF::make(kW, kH)), flagged = run(guide(60000.f, -60000.f));
    const double edge_none = error(none, 12, 15), edge_flagged = error(flagged, 12, 15);
    std::printf("sun shadow's first 3 columns: RMSE %.4f unguided, %.4f with the sun flag\n", edge_none, edge_flagged);
    EXPECT_LT(edge_flagged, 0.8 * edge_none);
    // The smooth light alone (no shadow), its variance as the ray tracer writes it: each pixel's
    // own from its 4 samples, scaled by 1/16 for their stratification (shaders/raygen.rgen), so
    // pixels whose samples agreed say 0.
    const GBuffer plain = make_scene();
    ImageF own = noisy(plain, 4, 22);
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float light = plain.illumination.at(x, y)[0];
            const float v = own.at(x, y)[1] / plain.reference.at(x, y)[1]; // Visible fraction x 2.
            own.at(x, y)[3] = light * light * v * (2.f - v) / 3.f / 16.f;
        }
    auto run_plain = [&](float distance) {
        ImageF r = ImageF::make(kW, kH);
        for (uint32_t y = kSkyRows; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                r.at(x, y)[3] = distance;
        denoiser.reset_history();
        return denoise_on_host(*m_ctx, denoiser, own, plain.albedo, plain.normal_depth, spatial_only(),
                               glm::mat4(1.f), 60.f, &r);
    };
    auto plain_error = [&](const ImageF& out) { return rmse(out, plain.reference); };
    const ImageF unguided = run_plain(0.f), far = run_plain(20.f), near = run_plain(0.05f);
    std::printf("smooth light, own variance: RMSE %.4f unguided, %.4f with occluders 20 blocks away, %.4f "
                "0.05 blocks\n", plain_error(unguided), plain_error(far), plain_error(near));
    EXPECT_LT(plain_error(far), 0.9 * plain_error(unguided));
    EXPECT_EQ(near.rgba, unguided.rgba);
}

// The reflected part (mirror bounces) is added back unfiltered: a pixel-sized pattern in it stays
// sharp while the noisy diffuse part around it is filtered.
TEST_F(DenoiserTest, ReflectedPartIsNotBlurred) {
    const GBuffer g = make_scene();
    ImageF reflected = ImageF::make(kW, kH), reference = g.reference;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float r = (x + 2 * y) % 3 == 0 ? 0.8f : 0.1f;
            for (int c = 0; c < 3; ++c) {
                reflected.at(x, y)[c] = r;
                reference.at(x, y)[c] += r;
            }
        }
    ImageF in = noisy(g, 4, 21);
    for (size_t i = 0; i < in.rgba.size(); ++i)
        if (i % 4 != 3)
            in.rgba[i] += reflected.rgba[i];
    Denoiser denoiser(*m_ctx, kW, kH);
    const ImageF out = denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, spatial_only(),
                                       glm::mat4(1.f), 60.f, &reflected);
    const double before = rmse(in, reference), after = rmse(out, reference);
    std::printf("with a reflected pattern, 4 spp: RMSE %.4f -> %.4f\n", before, after);
    EXPECT_LT(after, 0.5 * before);
}

// The whole floor and wall are mirrors showing another such scene (the wall from column 16, its
// own albedo tiles, 5 blocks further along the path): its diffuse light, noisy at 4 samples, is
// filtered with the reflected surface's guides and remodulated by its albedo, so the tiles seen
// in the mirror stay sharp while the noise goes. Without the mirror images (old callers) the
// same light is only added back, as before.
TEST_F(DenoiserTest, MirrorLightIsFilteredInTheReflectedSurfacesTerms) {
    const GBuffer g = make_scene(), seen = make_scene(16);
    ImageF mirror_light = noisy(seen, 4, 31), mirror_albedo = seen.albedo, mirror_nd = seen.normal_depth;
    ImageF in = noisy(g, 4, 32), reference = g.reference, reflected = ImageF::make(kW, kH);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            float *light = mirror_light.at(x, y), *nd = mirror_nd.at(x, y);
            if (y < kSkyRows) { // The primary ray missed: no mirror.
                for (int c = 0; c < 4; ++c)
                    light[c] = nd[c] = 0.f;
                continue;
            }
            nd[3] += 5.f;
            for (int c = 0; c < 3; ++c) {
                light[c] = seen.illumination.at(x, y)[c] * light[c] / seen.reference.at(x, y)[c]; // Demodulated.
                in.at(x, y)[c] += light[c] * mirror_albedo.at(x, y)[c];
                reflected.at(x, y)[c] = light[c] * mirror_albedo.at(x, y)[c];
                reference.at(x, y)[c] += seen.reference.at(x, y)[c];
            }
        }
    Denoiser denoiser(*m_ctx, kW, kH);
    const ImageF unfiltered = denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, spatial_only(),
                                              glm::mat4(1.f), 60.f, &reflected);
    const MirrorImagesF mirror{mirror_light, mirror_albedo, mirror_nd};
    const ImageF zero = ImageF::make(kW, kH);
    const ImageF filtered = denoise_on_host(*m_ctx, denoiser, in, g.albedo, g.normal_depth, spatial_only(),
                                            glm::mat4(1.f), 60.f, &zero, &mirror);
    const double raw = rmse(in, reference), before = rmse(unfiltered, reference), after = rmse(filtered, reference);
    std::printf("mirror light, 4 spp: RMSE raw %.4f, reflections unfiltered %.4f, filtered %.4f\n", raw, before, after);
    EXPECT_LT(before, raw);
    EXPECT_LT(after, 0.4 * before); // 2026-12-01: 0.1588 -> 0.0348.
    // Noise-free mirror light passes through (the tiles seen in the mirror are not blurred).
    ImageF exact_light = mirror_light, exact_in = g.reference;
    for (uint32_t y = kSkyRows; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            for (int c = 0; c < 3; ++c) {
                exact_light.at(x, y)[c] = seen.illumination.at(x, y)[c];
                exact_in.at(x, y)[c] += seen.reference.at(x, y)[c];
            }
            exact_light.at(x, y)[3] = 0.f;
        }
    const MirrorImagesF exact{exact_light, mirror_albedo, mirror_nd};
    const ImageF kept = denoise_on_host(*m_ctx, denoiser, exact_in, g.albedo, g.normal_depth, spatial_only(),
                                        glm::mat4(1.f), 60.f, &zero, &exact);
    std::printf("noise-free mirror light: RMSE %.4f\n", rmse(kept, reference));
    EXPECT_LT(rmse(kept, reference), 0.01);
}

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

} // namespace
} // namespace vx::render
