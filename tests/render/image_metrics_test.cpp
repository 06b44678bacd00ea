// Image metrics on images with known answers (CPU only, no device).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "render/image_metrics.h"

namespace vx::render {
namespace {

ImageF constant(uint32_t w, uint32_t h, float v) {
    ImageF img = ImageF::make(w, h);
    for (size_t i = 0; i < img.rgba.size(); ++i)
        img.rgba[i] = (i % 4 == 3) ? 1.f : v;
    return img;
}

ImageF gradient(uint32_t w, uint32_t h) {
    ImageF img = ImageF::make(w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float* p = img.at(x, y);
            p[0] = float(x) / float(w);
            p[1] = float(y) / float(h);
            p[2] = float((x * 7 + y * 3) % 11) / 10.f;
            p[3] = 1.f;
        }
    return img;
}

TEST(ImageMetrics, IdenticalImagesHaveZeroErrorAndSsimOne) {
    const ImageF a = gradient(32, 24);
    const ImageError e = compare(a, a);
    EXPECT_EQ(e.rmse, 0.0);
    EXPECT_TRUE(std::isinf(e.psnr) && e.psnr > 0);
    EXPECT_NEAR(e.ssim, 1.0, 1e-12);
}

TEST(ImageMetrics, CheckerboardNoiseGivesKnownRmseAndPsnr) {
    // +d / -d on alternate pixels, every channel: every squared error is d^2, so RMSE = d and
    // PSNR = 20 log10(1 / d) = 20 dB for d = 0.1.
    const float d = 0.1f;
    const ImageF ref = constant(16, 16, 0.5f);
    ImageF noisy = ref;
    for (uint32_t y = 0; y < 16; ++y)
        for (uint32_t x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c)
                noisy.at(x, y)[c] += ((x + y) % 2 ? d : -d);
    EXPECT_NEAR(rmse(noisy, ref), d, 1e-6);
    EXPECT_NEAR(psnr(noisy, ref), 20.0, 1e-4);
    EXPECT_LT(ssim(noisy, ref), 0.9); // Structure lost: variance 0.01 against none.
}

TEST(ImageMetrics, SsimOfAConstantShiftIsTheLuminanceTerm) {
    // Constant images 0.5 and 0.6: no variance, so SSIM = (2*0.5*0.6 + C1) / (0.25 + 0.36 + C1)
    // with C1 = 1e-4: 0.6001 / 0.6101.
    const ImageF a = constant(20, 14, 0.5f), b = constant(20, 14, 0.6f);
    EXPECT_NEAR(ssim(a, b), 0.6001 / 0.6101, 1e-6);
    EXPECT_NEAR(rmse(a, b), 0.1, 1e-6);
}

TEST(ImageMetrics, SsimIsSymmetricAndBelowOneForBlur) {
    const ImageF a = gradient(40, 30);
    ImageF blurred = a;
    for (uint32_t y = 0; y < 30; ++y)
        for (uint32_t x = 1; x + 1 < 40; ++x)
            for (int c = 0; c < 3; ++c)
                blurred.at(x, y)[c] = (a.at(x - 1, y)[c] + a.at(x, y)[c] + a.at(x + 1, y)[c]) / 3.f;
    const double s = ssim(blurred, a);
    EXPECT_LT(s, 0.999);
    EXPECT_GT(s, 0.3);
    EXPECT_NEAR(s, ssim(a, blurred), 1e-12);
}

// What an edit changed and the error there (the bench's edit path, the edit history test): only
// a change above the threshold in some colour channel counts (alpha never); the masked RMSE is
// over those pixels' R, G, B alone.
TEST(ImageMetrics, ChangedPixelsAndMaskedRmse) {
    const ImageF before = constant(4, 2, 0.5f);
    ImageF after = before;
    after.at(1, 0)[2] = 0.7f;  // Changed: 0.2 > 0.1.
    after.at(2, 1)[0] = 0.55f; // Below the threshold.
    after.at(3, 1)[3] = 0.f;   // Alpha only.
    const std::vector<bool> mask = changed_pixels(before, after);
    EXPECT_EQ(mask, std::vector<bool>({false, true, false, false, false, false, false, false}));
    EXPECT_EQ(changed_pixels(before, after, 0.01f)[6], true);
    // Pixel (1, 0): one channel off by 0.2, two exact: sqrt(0.04 / 3).
    EXPECT_NEAR(masked_rmse(after, before, mask), std::sqrt(0.04 / 3.0), 1e-6);
    EXPECT_EQ(masked_rmse(after, before, std::vector<bool>(8, false)), 0.0);
}

TEST(ImageMetrics, Rgba8RoundTrip) {
    RenderImage img{2, 1, {0, 128, 255, 255, 10, 20, 30, 255}};
    const ImageF f = to_float(img);
    EXPECT_FLOAT_EQ(f.rgba[2], 1.f);
    EXPECT_EQ(to_rgba8(f).rgba, img.rgba);
}

} // namespace
} // namespace vx::render
