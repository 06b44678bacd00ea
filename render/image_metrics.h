#pragma once
// Image error metrics for the renderer's speed-against-error study: RMSE, PSNR and SSIM of a test
// image against a reference. CPU code on linear float RGBA images (alpha ignored); 8-bit images
// convert with to_float(). Thread-safe (pure functions).

#include <cstdint>
#include <vector>

#include "render/renderer.h"

namespace vx::render {

// Float RGBA pixels, row 0 at the top, 4 floats per pixel. Values are in the caller's units
// (0..1 for display images; HDR radiance may exceed 1).
struct ImageF {
    uint32_t width = 0, height = 0;
    std::vector<float> rgba;
    static ImageF make(uint32_t width, uint32_t height) { return {width, height, std::vector<float>(size_t(width) * height * 4, 0.f)}; }
    float* at(uint32_t x, uint32_t y) { return &rgba[(size_t(y) * width + x) * 4]; }
    const float* at(uint32_t x, uint32_t y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

// 8-bit channels / 255 (no sRGB decoding: the metrics compare what is displayed).
ImageF to_float(const RenderImage& image);
// The frame's output before its 8-bit rounding (GBufferImage::display), alpha 1. Preconditions:
// render() filled `gbuffer`. The metric for errors near or under an 8-bit step (1/255), where
// rounding hides some differences and magnifies others.
ImageF display_float(const GBufferImage& gbuffer);
// Rounds to 8 bits, clamped to 0..1.
RenderImage to_rgba8(const ImageF& image);

struct ImageError {
    double rmse = 0; // Root mean square difference over R, G, B of every pixel.
    double psnr = 0; // 20 log10(peak / rmse) dB, peak 1; +infinity for identical images.
    double ssim = 1; // Mean SSIM (Wang et al. 2004) of R, G, B; 1 for identical images.
};

// Preconditions: same, non-zero size. RMSE and PSNR over R, G, B; SSIM with the paper's 11x11
// Gaussian window (sigma 1.5, windows inside the image; the whole image when it is smaller),
// C1 = (0.01 L)^2, C2 = (0.03 L)^2 with dynamic range L = 1.
double rmse(const ImageF& test, const ImageF& reference);
double psnr(const ImageF& test, const ImageF& reference);
double ssim(const ImageF& test, const ImageF& reference);
ImageError compare(const ImageF& test, const ImageF& reference);

// The pixels where any of R, G, B differs between `before` and `after` by more than `threshold`
// (default: a tenth of the display range; what an edit changed). Same, non-zero size.
std::vector<bool> changed_pixels(const ImageF& before, const ImageF& after, float threshold = 0.1f);
// RMSE over R, G, B of the pixels `mask` marks (one entry per pixel); 0 when it marks none.
double masked_rmse(const ImageF& test, const ImageF& reference, const std::vector<bool>& mask);

} // namespace vx::render
