#pragma once
// Helpers shared by the denoiser tests on a synthetic G-buffer (denoiser_test.cpp,
// denoiser_accumulation_test.cpp): the scene with its noise-free image, and its noisy renders.

#include <cstdint>
#include <random>

#include <glm/glm.hpp>

#include "render/image_metrics.h"

namespace vx::render::test {

constexpr uint32_t kW = 48, kH = 32, kSkyRows = 6;

struct GBuffer {
    ImageF reference, albedo, normal_depth, illumination;
};

// `wall_from_x`: columns from here on are the wall (moving it changes the blocks).
inline GBuffer make_scene(uint32_t wall_from_x = 24) {
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
inline ImageF noisy(const GBuffer& g, uint32_t spp, uint32_t seed) {
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

} // namespace vx::render::test
