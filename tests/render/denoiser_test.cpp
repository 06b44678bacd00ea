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

} // namespace
} // namespace vx::render
