// The shaders' sample pattern and tone curve, tested through the C++ side of the headers the
// GLSL includes (shaders/shared/sampling.h, tonemap.h: one source for both).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "shaders/shared/sampling.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using gpu::vx_cmj;

constexpr uint32_t kPatterns = 4096; // Per N: pixels x seeds, each its own pattern as in raygen.

// Pattern p of pixel (x, y) and seed, exactly as raygen.rgen derives it.
uint32_t pattern_of(uint32_t i) { return gpu::vx_hash(i % 64 + gpu::vx_hash(i / 64 + gpu::vx_hash(1 + i / 4096))); }

// The variant raygen used before (grid m x ceil(N/m), last row partly empty), kept as the
// control that shows this test can fail: it is biased when N is not a product of the grid.
glm::vec2 old_cmj(uint32_t s, uint32_t n, uint32_t p) {
    const uint32_t m = std::max(uint32_t(std::sqrt(float(n))), 1u), rows = (n + m - 1) / m;
    const uint32_t sx = gpu::vx_permute(s % m, m, p * 0xa511e9b3u);
    const uint32_t sy = gpu::vx_permute(s / m, rows, p * 0x63d83595u);
    const float jx = gpu::vx_randfloat(s, p * 0xa399d265u), jy = gpu::vx_randfloat(s, p * 0x711ad6a5u);
    return {(float(s % m) + (float(sy) + jx) / float(rows)) / float(m),
            (float(s / m) + (float(sx) + jy) / float(m)) / float(rows)};
}

struct MeanTest {
    glm::dvec2 mean{0.0};
    glm::dvec2 tolerance{0.0};
};

// Mean sample position over kPatterns patterns of n samples, and a tolerance of 5 standard
// errors of that mean, from the spread of the per-pattern means (plus 1e-4 for float rounding
// of the positions): an unbiased pattern passes with probability above 1 - 6e-7 per axis.
template <class Cmj>
MeanTest mean_position(uint32_t n, Cmj cmj) {
    std::vector<glm::dvec2> means(kPatterns);
    glm::dvec2 sum(0.0);
    for (uint32_t i = 0; i < kPatterns; ++i) {
        glm::dvec2 m(0.0);
        for (uint32_t s = 0; s < n; ++s)
            m += glm::dvec2(cmj(s, n, pattern_of(i)));
        means[i] = m / double(n);
        sum += means[i];
    }
    MeanTest t;
    t.mean = sum / double(kPatterns);
    glm::dvec2 var(0.0);
    for (const glm::dvec2& m : means)
        var += (m - t.mean) * (m - t.mean);
    var /= double(kPatterns - 1);
    t.tolerance = 5.0 * glm::sqrt(var / double(kPatterns)) + 1e-4;
    return t;
}

TEST(Sampling, CmjMeanIsCentredForEveryCount) {
    for (uint32_t n = 1; n <= 64; ++n) {
        const MeanTest t = mean_position(n, [](uint32_t s, uint32_t c, uint32_t p) { return vx_cmj(s, c, p); });
        EXPECT_NEAR(t.mean.x, 0.5, t.tolerance.x) << "N = " << n;
        EXPECT_NEAR(t.mean.y, 0.5, t.tolerance.y) << "N = " << n;
    }
}

TEST(Sampling, OldGridVariantIsCaughtAsBiased) {
    // The figures: (0.467, 0.425) for N = 10, (0.464, 0.447) for N = 7.
    for (uint32_t n : {7u, 10u}) {
        const MeanTest t = mean_position(n, old_cmj);
        EXPECT_GT(std::abs(t.mean.x - 0.5), t.tolerance.x) << "N = " << n;
        EXPECT_GT(std::abs(t.mean.y - 0.5), t.tolerance.y) << "N = " << n;
    }
}

TEST(Sampling, CmjIsStratifiedAndInRange) {
    // Kensler's y = (permuted s + jitter) / N: every pattern puts one sample in each of N rows
    // of height 1/N; and every sample lies in [0, 1)^2.
    for (uint32_t n = 1; n <= 64; ++n)
        for (uint32_t i = 0; i < 64; ++i) {
            std::vector<int> per_row(n, 0);
            for (uint32_t s = 0; s < n; ++s) {
                const glm::vec2 u = vx_cmj(s, n, pattern_of(i));
                ASSERT_TRUE(u.x >= 0.f && u.x < 1.f && u.y >= 0.f && u.y < 1.f) << "N = " << n;
                ++per_row[std::min(uint32_t(u.y * float(n)), n - 1)];
            }
            for (uint32_t r = 0; r < n; ++r)
                ASSERT_EQ(per_row[r], 1) << "N = " << n << " row " << r;
        }
}

// vx_cmj2 with a coarse and a fine pattern of their own: each point is uniform (its mean
// centred, as Kensler's one-pattern form) and each pattern pair stratified in y.
TEST(Sampling, SplitCmjIsCentredAndStratified) {
    auto split = [](uint32_t s, uint32_t c, uint32_t p) { return gpu::vx_cmj2(s, c, p, gpu::vx_hash(p ^ 0x2545f491u)); };
    for (uint32_t n = 1; n <= 64; ++n) {
        const MeanTest t = mean_position(n, split);
        EXPECT_NEAR(t.mean.x, 0.5, t.tolerance.x) << "N = " << n;
        EXPECT_NEAR(t.mean.y, 0.5, t.tolerance.y) << "N = " << n;
        for (uint32_t i = 0; i < 64; ++i) {
            std::vector<int> per_row(n, 0);
            for (uint32_t s = 0; s < n; ++s)
                ++per_row[std::min(uint32_t(split(s, n, pattern_of(i)).y * float(n)), n - 1)];
            ASSERT_EQ(std::count(per_row.begin(), per_row.end(), 1), int(n)) << "N = " << n;
        }
    }
}

// Where sample s of pixel (x, y) lies at the coarse scale: its y stratum (1/n) and its column
// of the grid (1/m, m = floor(sqrt(n))).
glm::uvec2 coarse_cell(glm::vec2 u, uint32_t n) {
    const uint32_t m = std::max(uint32_t(std::sqrt(float(n))), 1u);
    return {std::min(uint32_t(u.x * float(m)), m - 1), std::min(uint32_t(u.y * float(n)), n - 1)};
}

// Whether u lies in that cell, or within float rounding of it (x = (column + offset) / m can
// round up to the next column's edge).
bool in_cell(glm::vec2 u, glm::uvec2 cell, uint32_t n) {
    const uint32_t m = std::max(uint32_t(std::sqrt(float(n))), 1u);
    const float eps = 1e-6f;
    return u.x >= float(cell.x) / float(m) - eps && u.x <= float(cell.x + 1) / float(m) + eps &&
           u.y >= float(cell.y) / float(n) - eps && u.y <= float(cell.y + 1) / float(n) + eps;
}

// How many (tile, sample) pairs of a 32 x 32 pixel area find all of the tile's pixels in one
// coarse cell, and how many samples of any tile repeat a point of another pixel of the tile.
struct TileShare {
    int shared = 0, total = 0, repeated = 0;
};
template <class Sample>
TileShare tile_share(uint32_t n, Sample sample) {
    constexpr uint32_t kTile = 1u << gpu::kSampleTileShift;
    TileShare t;
    for (uint32_t ty = 0; ty < 32; ty += kTile)
        for (uint32_t tx = 0; tx < 32; tx += kTile)
            for (uint32_t s = 0; s < n; ++s) {
                std::vector<glm::vec2> points;
                bool same = true;
                for (uint32_t y = ty; y < ty + kTile; ++y)
                    for (uint32_t x = tx; x < tx + kTile; ++x) {
                        const glm::vec2 u = sample(s, n, x, y);
                        same = same && (points.empty() || in_cell(u, coarse_cell(points[0], n), n));
                        t.repeated += std::count(points.begin(), points.end(), u) > 0;
                        points.push_back(u);
                    }
                t.shared += same;
                ++t.total;
            }
    return t;
}

// vx_pixel_sample with n not a power of two: at every step s the pixels of a tile lie in one
// coarse cell (their rays head for the same part of a light), no two of them at the same
// point; each pixel's n points are still one per y stratum. Tiles differ (not all 15 others
// like the first: for n = 3 each matches it with probability 1/6). Control: the
// per-pixel patterns used before share a cell in almost no (tile, step) pair.
TEST(Sampling, PixelSamplesShareCoarseCellsInTiles) {
    for (uint32_t n : {3u, 5u, 6u, 9u, 12u, 25u, 49u})
        for (uint32_t seed : {1u, gpu::vx_hash(7u), 0xffffffffu}) {
            auto sample = [seed](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                return gpu::vx_pixel_sample(s, c, x, y, seed);
            };
            const TileShare t = tile_share(n, sample);
            EXPECT_EQ(t.shared, t.total) << "N = " << n;
            EXPECT_EQ(t.repeated, 0) << "N = " << n;
            for (uint32_t y = 0; y < 32; y += 5)
                for (uint32_t x = 0; x < 32; x += 3) {
                    std::vector<int> per_row(n, 0);
                    for (uint32_t s = 0; s < n; ++s)
                        ++per_row[coarse_cell(sample(s, n, x, y), n).y];
                    ASSERT_EQ(std::count(per_row.begin(), per_row.end(), 1), int(n)) << "N = " << n;
                }
            int differ = 0; // Tiles that put some step in another cell than tile (0, 0) does.
            for (uint32_t ty = 0; ty < 32; ty += 8)
                for (uint32_t tx = 0; tx < 32; tx += 8) {
                    bool other = false;
                    for (uint32_t s = 0; s < n; ++s)
                        other = other || !in_cell(sample(s, n, tx, ty), coarse_cell(sample(s, n, 0, 0), n), n);
                    differ += other;
                }
            EXPECT_GT(differ, 0) << "N = " << n;
            auto old = [seed](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                return vx_cmj(s, c, gpu::vx_hash(x + gpu::vx_hash(y + seed)));
            };
            EXPECT_LT(tile_share(n, old).shared, 2) << "N = " << n;
        }
}

// Whether `points` (count 2^m) form a (0, m, 2)-net: exactly one point in each elementary
// interval [i / 2^a, (i + 1) / 2^a) x [j / 2^b, (j + 1) / 2^b) with a + b = m.
bool is_net(const std::vector<glm::vec2>& points) {
    uint32_t m = 0;
    while ((1u << m) < points.size())
        ++m;
    if ((1u << m) != points.size())
        return false;
    for (uint32_t a = 0; a <= m; ++a) {
        std::vector<int> count(points.size(), 0);
        for (const glm::vec2& p : points) {
            const uint32_t i = uint32_t(p.x * float(1u << a)), j = uint32_t(p.y * float(1u << (m - a)));
            if (++count[(i << (m - a)) + j] > 1)
                return false;
        }
    }
    return true;
}

// The points of pixels [x0, x0 + side) x [y0, y0 + side), n each, from `sample`.
template <class Sample>
std::vector<glm::vec2> block_points(uint32_t x0, uint32_t y0, uint32_t side, uint32_t n, Sample sample) {
    std::vector<glm::vec2> p;
    for (uint32_t y = y0; y < y0 + side; ++y)
        for (uint32_t x = x0; x < x0 + side; ++x)
            for (uint32_t s = 0; s < n; ++s)
                p.push_back(sample(s, n, x, y));
    return p;
}

// vx_pixel_sample with n a power of two: every pixel's n points are a (0, log2 n, 2)-net, and so
// are the 4n points of each aligned 2x2 block and the 16n of each aligned 4x4 block (the
// neighbours' samples fill each other's gaps); all in [0, 1)^2. Control: the per-pixel patterns
// raygen used before (correlated multi-jittered, stratified within a pixel only) make no
// 2x2 block a net.
TEST(Sampling, PixelSamplesAreNetsInEachPixelAndBlock) {
    for (uint32_t n : {1u, 2u, 4u, 8u, 16u, 64u})
        for (uint32_t seed : {1u, gpu::vx_hash(7u), 0xffffffffu}) {
            auto sample = [seed](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                return gpu::vx_pixel_sample(s, c, x, y, seed);
            };
            for (uint32_t side : {1u, 2u, 4u})
                for (uint32_t y = 0; y < 16; y += side)
                    for (uint32_t x = 0; x < 16; x += side) {
                        const std::vector<glm::vec2> p = block_points(x, y, side, n, sample);
                        for (const glm::vec2& u : p)
                            ASSERT_TRUE(u.x >= 0.f && u.x < 1.f && u.y >= 0.f && u.y < 1.f);
                        ASSERT_TRUE(is_net(p)) << "N = " << n << ", block " << side << " at " << x << ","
                                               << y;
                    }
            if (n >= 2) {
                auto old = [seed](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                    return vx_cmj(s, c, gpu::vx_hash(x + gpu::vx_hash(y + seed)));
                };
                int nets = 0;
                for (uint32_t y = 0; y < 16; y += 2)
                    for (uint32_t x = 0; x < 16; x += 2)
                        nets += is_net(block_points(x, y, 2, n, old));
                EXPECT_EQ(nets, 0) << "N = " << n;
            }
        }
}

// Irradiance from a square light of side 2a and radiance L, parallel to a plane at height h and
// centred over the point: four rectangles with a corner over it, each of form factor
// F = (1 / 2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + (X <-> Y)], X = Y = a / h, and
// E = pi L F_total (Lambertian emitter). For a = 8, h = 4: E = 2.61075 L.
double square_light_irradiance(double a, double h, double radiance) {
    const double x = a / h, q = x / std::sqrt(1.0 + x * x);
    return radiance * 4.0 * q * std::atan(q);
}

// The shaders' area-light estimator (shared/finite_light.glsl, finite_light: L A / N sum cos_s cos_l / d^2 at
// points drawn uniformly on the light) with vx_pixel_sample's points: a 16 x 16 pixel block, all
// seeing the same point 4 below the centre of a 16 x 16 light, where cos_s cos_l / d^2 varies
// 80-fold over the light. The mean over the pixels is within 1% of the analytic irradiance for
// each sample count and frame (the block's points are one net; 25, no power of two, is the
// per-pixel correlated multi-jittered pattern). Control: those per-pixel patterns at 1, 2 and 4
// samples, unbiased too but not spread between pixels, miss by more than 2%.
TEST(Sampling, AreaLightEstimateMatchesAnalyticIrradiance) {
    const double h = 4.0, side = 16.0, radiance = 3.0;
    const double expected = square_light_irradiance(side / 2.0, h, radiance);
    EXPECT_NEAR(expected, 2.61075 * radiance, 1e-4);
    auto estimate = [&](glm::vec2 u) {
        const double lx = side * (double(u.x) - 0.5), lz = side * (double(u.y) - 0.5);
        const double d2 = lx * lx + lz * lz + h * h, c = h / std::sqrt(d2);
        return radiance * side * side * c * c / d2;
    };
    auto mean = [&](uint32_t n, auto sample) {
        double sum = 0.0;
        for (uint32_t y = 0; y < 16; ++y)
            for (uint32_t x = 0; x < 16; ++x)
                for (uint32_t s = 0; s < n; ++s)
                    sum += estimate(sample(s, n, x, y));
        return sum / (256.0 * n);
    };
    double worst_old = 0.0;
    for (uint32_t frame : {1u, 2u, 3u, 100u}) {
        const uint32_t seed = gpu::vx_hash(frame ^ gpu::vx_hash(0u)); // raygen.rgen's estimator(0).
        for (uint32_t n : {1u, 2u, 4u, 8u, 16u, 25u, 64u})
            EXPECT_NEAR(mean(n, [seed](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                            return gpu::vx_pixel_sample(s, c, x, y, seed);
                        }),
                        expected, 0.01 * expected)
                << "N = " << n << ", frame " << frame;
        for (uint32_t n : {1u, 2u, 4u}) {
            const double old = mean(n, [frame](uint32_t s, uint32_t c, uint32_t x, uint32_t y) {
                return vx_cmj(s, c, gpu::vx_hash(x + gpu::vx_hash(y + gpu::vx_hash(frame))));
            });
            worst_old = std::max(worst_old, std::abs(old / expected - 1.0));
        }
    }
    EXPECT_GT(worst_old, 0.02);
}

// The tone curve (tonemap.h, Narkowicz's ACES fit): 0 maps to 0 (black stays black, negatives
// too), strictly increasing up to its shoulder, never above 1; kMidGreyInput lands at mid-grey.
TEST(ToneMap, MapsZeroToZeroRisesMonotonicallyAndRollsOff) {
    EXPECT_EQ(gpu::vx_tonemap1(0.f), 0.f);
    EXPECT_EQ(gpu::vx_tonemap1(-1.f), 0.f);
    // Below x = 7.24 (where the fit reaches 1) strictly increasing; beyond, clamped at 1.
    float prev = 0.f;
    for (float x = 1e-3f; x < 7.2f; x *= 1.01f) {
        const float y = gpu::vx_tonemap1(x);
        EXPECT_GT(y, prev) << x;
        EXPECT_LT(y, 1.f) << x;
        prev = y;
    }
    for (float x : {7.3f, 100.f, 1e30f})
        EXPECT_EQ(gpu::vx_tonemap1(x), 1.f) << x;
    auto byte = [](float x) { return int(std::lround(gpu::vx_srgb_encode1(gpu::vx_tonemap1(x)) * 255.f)); };
    // Mid-grey: sRGB 118 is linear 0.1812, the value of the curve at kMidGreyInput.
    EXPECT_NEAR(gpu::vx_tonemap1(gpu::kMidGreyInput), 0.1812f, 1e-3f);
    EXPECT_EQ(byte(gpu::kMidGreyInput), 118);
    // The shoulder: 8-bit output (sRGB encoded, rounded) 1.0 -> 232, 1.25 -> 237, 3 -> 250:
    // distinct and below 255 (the old curve's 1.0 was 246, its 1.25 252).
    EXPECT_LT(byte(1.f), byte(1.25f));
    EXPECT_LT(byte(1.25f), byte(3.f));
    EXPECT_LT(byte(3.f), 255);
}

// Exposure (tonemap.h): L_max = 1.2 * 2^EV100 cd/m^2 saturates; one EV more halves the scale.
// EV100 15 (sunny 16) takes 10^4 / (1.2 * 32768) = 0.2543 of a radiance unit (10^4 cd/m^2).
TEST(ToneMap, ExposureScaleFollowsEv100) {
    EXPECT_NEAR(gpu::vx_exposure_scale(15.f), 0.2543f, 1e-4f);
    for (float ev : {-2.f, 0.f, 9.5f, 14.7f}) {
        const float scale = gpu::vx_exposure_scale(ev);
        EXPECT_NEAR(gpu::vx_exposure_scale(ev + 1.f) * 2.f, scale, 1e-6f * scale);
    }
}

} // namespace
} // namespace vx::render
