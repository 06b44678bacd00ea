#include "render/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "world/base/assert.h"

namespace vx::render {

ImageF to_float(const RenderImage& image) {
    ImageF out = ImageF::make(image.width, image.height);
    for (size_t i = 0; i < out.rgba.size(); ++i)
        out.rgba[i] = float(image.rgba[i]) / 255.f;
    return out;
}

ImageF display_float(const GBufferImage& gbuffer) {
    VX_ASSERT(gbuffer.display.size() == size_t(gbuffer.width) * gbuffer.height);
    ImageF out = ImageF::make(gbuffer.width, gbuffer.height);
    for (size_t i = 0; i < gbuffer.display.size(); ++i) {
        float* p = &out.rgba[i * 4];
        p[0] = gbuffer.display[i].r;
        p[1] = gbuffer.display[i].g;
        p[2] = gbuffer.display[i].b;
        p[3] = 1.f;
    }
    return out;
}

RenderImage to_rgba8(const ImageF& image) {
    RenderImage out{image.width, image.height, std::vector<uint8_t>(image.rgba.size())};
    for (size_t i = 0; i < image.rgba.size(); ++i)
        out.rgba[i] = uint8_t(std::lround(std::clamp(image.rgba[i], 0.f, 1.f) * 255.f));
    return out;
}

static void check_sizes(const ImageF& a, const ImageF& b) {
    VX_ASSERT_MSG(a.width == b.width && a.height == b.height && a.width > 0 && a.height > 0,
                  "image metrics need two images of the same, non-zero size");
    VX_ASSERT(a.rgba.size() == size_t(a.width) * a.height * 4 && b.rgba.size() == a.rgba.size());
}

double rmse(const ImageF& test, const ImageF& reference) {
    check_sizes(test, reference);
    double sum = 0;
    for (size_t p = 0; p < test.rgba.size(); p += 4)
        for (size_t c = 0; c < 3; ++c) {
            const double d = double(test.rgba[p + c]) - double(reference.rgba[p + c]);
            sum += d * d;
        }
    return std::sqrt(sum / (double(test.rgba.size() / 4) * 3.0));
}

std::vector<bool> changed_pixels(const ImageF& before, const ImageF& after, float threshold) {
    check_sizes(before, after);
    std::vector<bool> mask(size_t(before.width) * before.height, false);
    for (size_t i = 0; i < mask.size(); ++i)
        for (size_t c = 0; c < 3; ++c)
            mask[i] = mask[i] || std::abs(before.rgba[i * 4 + c] - after.rgba[i * 4 + c]) > threshold;
    return mask;
}

double masked_rmse(const ImageF& test, const ImageF& reference, const std::vector<bool>& mask) {
    check_sizes(test, reference);
    VX_ASSERT(mask.size() == size_t(test.width) * test.height);
    double sum = 0.0;
    size_t count = 0;
    for (size_t i = 0; i < mask.size(); ++i)
        if (mask[i])
            for (size_t c = 0; c < 3; ++c) {
                const double d = double(test.rgba[i * 4 + c]) - reference.rgba[i * 4 + c];
                sum += d * d;
                ++count;
            }
    return count ? std::sqrt(sum / double(count)) : 0.0;
}

double psnr(const ImageF& test, const ImageF& reference) {
    const double e = rmse(test, reference);
    return e > 0 ? 20.0 * std::log10(1.0 / e) : std::numeric_limits<double>::infinity();
}

namespace {

// One channel as doubles, and its "valid" Gaussian-weighted local means (windows that fit).
struct Plane {
    uint32_t w = 0, h = 0;
    std::vector<double> v;
};

Plane channel(const ImageF& img, uint32_t c) {
    Plane p{img.width, img.height, std::vector<double>(size_t(img.width) * img.height)};
    for (size_t i = 0; i < p.v.size(); ++i)
        p.v[i] = img.rgba[i * 4 + c];
    return p;
}

Plane product(const Plane& a, const Plane& b) {
    Plane p = a;
    for (size_t i = 0; i < p.v.size(); ++i)
        p.v[i] *= b.v[i];
    return p;
}

// Separable weighted mean over windows of size `k` (normalised weights), valid positions only.
Plane local_mean(const Plane& in, const std::vector<double>& wx, const std::vector<double>& wy) {
    const uint32_t kx = uint32_t(wx.size()), ky = uint32_t(wy.size());
    Plane row{in.w - kx + 1, in.h, {}};
    row.v.assign(size_t(row.w) * row.h, 0.0);
    for (uint32_t y = 0; y < in.h; ++y)
        for (uint32_t x = 0; x < row.w; ++x) {
            double s = 0;
            for (uint32_t i = 0; i < kx; ++i)
                s += wx[i] * in.v[size_t(y) * in.w + x + i];
            row.v[size_t(y) * row.w + x] = s;
        }
    Plane out{row.w, in.h - ky + 1, {}};
    out.v.assign(size_t(out.w) * out.h, 0.0);
    for (uint32_t y = 0; y < out.h; ++y)
        for (uint32_t x = 0; x < out.w; ++x) {
            double s = 0;
            for (uint32_t i = 0; i < ky; ++i)
                s += wy[i] * row.v[size_t(y + i) * row.w + x];
            out.v[size_t(y) * out.w + x] = s;
        }
    return out;
}

// The paper's window (11 taps, sigma 1.5), or a box over the whole extent when it is smaller.
std::vector<double> window(uint32_t extent) {
    constexpr uint32_t kTaps = 11;
    if (extent < kTaps)
        return std::vector<double>(extent, 1.0 / extent);
    std::vector<double> w(kTaps);
    double sum = 0;
    for (uint32_t i = 0; i < kTaps; ++i) {
        const double d = double(i) - 5.0;
        w[i] = std::exp(-d * d / (2.0 * 1.5 * 1.5));
        sum += w[i];
    }
    for (double& x : w)
        x /= sum;
    return w;
}

double ssim_plane(const Plane& x, const Plane& y) {
    const std::vector<double> wx = window(x.w), wy = window(x.h);
    const Plane mx = local_mean(x, wx, wy), my = local_mean(y, wx, wy);
    const Plane mxx = local_mean(product(x, x), wx, wy), myy = local_mean(product(y, y), wx, wy);
    const Plane mxy = local_mean(product(x, y), wx, wy);
    constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;
    double sum = 0;
    for (size_t i = 0; i < mx.v.size(); ++i) {
        const double ux = mx.v[i], uy = my.v[i];
        const double vx = mxx.v[i] - ux * ux, vy = myy.v[i] - uy * uy, cxy = mxy.v[i] - ux * uy;
        sum += ((2 * ux * uy + kC1) * (2 * cxy + kC2)) / ((ux * ux + uy * uy + kC1) * (vx + vy + kC2));
    }
    return sum / double(mx.v.size());
}

} // namespace

double ssim(const ImageF& test, const ImageF& reference) {
    check_sizes(test, reference);
    double sum = 0;
    for (uint32_t c = 0; c < 3; ++c)
        sum += ssim_plane(channel(test, c), channel(reference, c));
    return sum / 3.0;
}

ImageError compare(const ImageF& test, const ImageF& reference) {
    ImageError e;
    e.rmse = rmse(test, reference);
    e.psnr = e.rmse > 0 ? 20.0 * std::log10(1.0 / e.rmse) : std::numeric_limits<double>::infinity();
    e.ssim = ssim(test, reference);
    return e;
}

} // namespace vx::render
