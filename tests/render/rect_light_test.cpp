// Solid-angle sampling of the rectangular area light (shaders/shared/rect_light.h), tested through
// the C++ side of the header the ray-generation shader includes: the solid angle against its
// closed form, samples uniform in solid angle (each quarter of the light gets its share), the
// irradiance estimate against Lambert's polygon formula, and the cases where the method's
// arithmetic breaks down, which must hand over to area sampling rather than return NaN.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "shaders/shared/rect_light.h"

namespace vx::render {
namespace {

using gpu::RectView;
using gpu::vx_rect_sample;
using gpu::vx_rect_view;

constexpr double kPi = 3.14159265358979323846;

// Solid angle of an a x b rectangle centred on the axis at distance h (closed form).
double on_axis_solid_angle(double a, double b, double h) {
    return 4.0 * std::asin(a * b / std::sqrt((a * a + 4 * h * h) * (b * b + 4 * h * h)));
}

// Irradiance at the origin (normal n, facing the polygon) from a unit-radiance polygon, by
// Lambert's formula: E = 1/2 sum over edges of angle(v_i, v_i+1) * n . unit(v_i x v_i+1), in the
// winding whose cross products point away from the polygon's visible side.
double lambert_irradiance(const std::vector<glm::dvec3>& poly, glm::dvec3 n) {
    double e = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3 a = glm::normalize(poly[i]), b = glm::normalize(poly[(i + 1) % poly.size()]);
        const glm::dvec3 c = glm::cross(a, b);
        e += std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, glm::normalize(c));
    }
    return std::abs(0.5 * e);
}

// Stratified (u, v) points: an m x m grid of cell centres.
std::vector<glm::vec2> grid(int m) {
    std::vector<glm::vec2> p;
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i)
            p.push_back({(float(i) + 0.5f) / float(m), (float(j) + 0.5f) / float(m)});
    return p;
}

TEST(RectLight, SolidAngleMatchesTheClosedFormOnAxis) {
    for (const glm::vec3 abh : {glm::vec3(16, 16, 32), glm::vec3(128, 128, 256), glm::vec3(2, 8, 1), glm::vec3(4, 4, 0.5f)}) {
        const glm::vec3 corner(-abh.x / 2, abh.z, -abh.y / 2);
        for (const float side : {1.f, -1.f}) { // Below the light, then above it (two-sided).
            const RectView r = vx_rect_view({0, 0, 0}, corner * glm::vec3(1, side, 1), {abh.x, 0, 0}, {0, 0, abh.y});
            ASSERT_TRUE(r.valid);
            const double want = on_axis_solid_angle(abh.x, abh.y, abh.z);
            EXPECT_NEAR(r.solid_angle, want, 2e-6 + 1e-5 * want) << abh.x << "x" << abh.y << " at " << abh.z;
        }
    }
}

// The spread of area sampling's weight that decides whether to sample by solid angle, against
// a brute-force scan of h / d^3 over the light.
TEST(RectLight, SpreadOfTheAreaWeight) {
    const glm::vec3 corner(-64, 288, -64), eu(128, 0, 0), ev(0, 0, 128); // The thesis scene's light.
    for (const glm::vec3 o : {glm::vec3(0, 32, 0), glm::vec3(-512, 0, -512), glm::vec3(40, 0, -300), glm::vec3(0, 280, 0),
                              glm::vec3(300, 287, 10)}) {
        float lo = 1e30f, hi = 0;
        for (int j = 0; j <= 64; ++j)
            for (int i = 0; i <= 64; ++i) {
                const glm::vec3 c = corner + eu * (float(i) / 64) + ev * (float(j) / 64) - o;
                const float g = std::abs(c.y) / std::pow(glm::length(c), 3.f);
                lo = std::min(lo, g);
                hi = std::max(hi, g);
            }
        EXPECT_NEAR(gpu::vx_rect_spread(o, corner, eu, ev), hi / lo, 0.01f * hi / lo) << o.x << "," << o.y << "," << o.z;
    }
    EXPECT_LT(gpu::vx_rect_spread({0, 32, 0}, corner, eu, ev), 1.25f);     // Under the light: area sampling.
    EXPECT_GT(gpu::vx_rect_spread({0, 280, 0}, corner, eu, ev), 1000.f);   // Just under it: by solid angle.
    EXPECT_EQ(gpu::vx_rect_spread({0, 288, 0}, corner, eu, ev), 0.f);      // In its plane.
}

// Each quarter of the light receives the fraction of samples that its own solid angle is of
// the whole: the map is area-preserving on the sphere. A point off to one side and low, where
// area sampling's density differs most from the solid angle's.
TEST(RectLight, SamplesAreUniformInSolidAngle) {
    const glm::vec3 origin(-20, 0, 3), corner(0, 6, 0), eu(16, 0, 0), ev(0, 0, 12);
    const RectView r = vx_rect_view(origin, corner, eu, ev);
    ASSERT_TRUE(r.valid);
    int counts[2][2] = {{0, 0}, {0, 0}};
    const std::vector<glm::vec2> uv = grid(128);
    for (const glm::vec2 p : uv) {
        const glm::vec3 q = origin + vx_rect_sample(r, p.x, p.y) - corner; // On the light.
        const float s = glm::dot(q, eu) / glm::dot(eu, eu), t = glm::dot(q, ev) / glm::dot(ev, ev);
        ASSERT_GE(s, -1e-4f);
        ASSERT_LE(s, 1 + 1e-4f);
        ASSERT_GE(t, -1e-4f);
        ASSERT_LE(t, 1 + 1e-4f);
        ASSERT_NEAR(glm::dot(q, glm::cross(eu, ev)), 0.f, 1e-2f); // In the light's plane.
        ++counts[s >= 0.5f][t >= 0.5f];
    }
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            const RectView quarter = vx_rect_view(origin, corner + 0.5f * float(i) * eu + 0.5f * float(j) * ev, 0.5f * eu, 0.5f * ev);
            const double want = quarter.solid_angle / r.solid_angle;
            EXPECT_NEAR(double(counts[i][j]) / double(uv.size()), want, 0.01) << i << j;
        }
}

// The estimate S * mean(cos) converges to the irradiance of Lambert's formula, and with fewer
// samples than area sampling needs for the same error: a light near the point, seen at a slant.
TEST(RectLight, IrradianceEstimateBeatsAreaSampling) {
    const glm::vec3 origin(0, 0, 0), n(0, 1, 0), corner(-3, 2, 1), eu(10, 0, 0), ev(0, 3, 6);
    const RectView r = vx_rect_view(origin, corner, eu, ev);
    ASSERT_TRUE(r.valid);
    const glm::dvec3 c(corner), u(eu), v(ev);
    const double want = lambert_irradiance({c, c + u, c + u + v, c + v}, glm::dvec3(n));
    const glm::vec3 ln = glm::normalize(glm::cross(eu, ev));
    const float area = glm::length(glm::cross(eu, ev));
    double angle_sum = 0, area_sum = 0;
    const std::vector<glm::vec2> uv = grid(64);
    double angle_sq = 0, area_sq = 0; // For the per-sample variances.
    for (const glm::vec2 p : uv) {
        const glm::vec3 d = glm::normalize(vx_rect_sample(r, p.x, p.y));
        const double a = r.solid_angle * std::max(0.f, glm::dot(n, d));
        const glm::vec3 q = corner + p.x * eu + p.y * ev;
        const glm::vec3 l = glm::normalize(q);
        const double b = std::max(0.f, glm::dot(n, l)) * std::abs(glm::dot(ln, l)) * area / glm::dot(q, q);
        angle_sum += a;
        area_sum += b;
        angle_sq += a * a;
        area_sq += b * b;
    }
    const double m = double(uv.size());
    EXPECT_NEAR(angle_sum / m, want, 1e-3 * want);
    EXPECT_NEAR(area_sum / m, want, 1e-2 * want); // The control: same integral.
    const double angle_var = angle_sq / m - (angle_sum / m) * (angle_sum / m);
    const double area_var = area_sq / m - (area_sum / m) * (area_sum / m);
    std::printf("irradiance %.5f; per-sample variance by solid angle %.3g, by area %.3g\n", want, angle_var, area_var);
    EXPECT_LT(angle_var, 0.5 * area_var);
}

// Where the arithmetic breaks down the view says so and the caller samples by area; valid
// views never give NaN or points off the light, even at u, v = 0 and just under 1.
TEST(RectLight, DegenerateViewsHandOverToAreaSampling) {
    const glm::vec3 eu(16, 0, 0), ev(0, 0, 16), corner(-8, 0, -8);
    EXPECT_FALSE(vx_rect_view({0, 0, 0}, corner, eu, ev).valid);                   // In the light's plane.
    EXPECT_FALSE(vx_rect_view({100, 1e-5f, 0}, corner, eu, ev).valid);             // Beside it, in its plane.
    EXPECT_FALSE(vx_rect_view({0, -5e5f, 0}, corner, eu, ev).valid);               // Tiny solid angle.
    EXPECT_FALSE(vx_rect_view({0, -10, 0}, corner, eu, glm::vec3(4, 0, 16)).valid); // A parallelogram.
    const std::vector<glm::vec3> origins = {{0, -1e-2f, 0}, {8, -0.5f, 8}, {-8, -3, -8}, {500, -20, 0},
                                            {0, -800, 0}, {30, 0.2f, 3}};
    for (const glm::vec3 o : origins) {
        const RectView r = vx_rect_view(o, corner, eu, ev);
        if (!r.valid)
            continue;
        EXPECT_GT(r.solid_angle, 0.f);
        EXPECT_LT(r.solid_angle, float(2 * kPi));
        for (const float u : {0.f, 0.25f, 0.5f, 0.9999999f})
            for (const float v : {0.f, 0.5f, 0.9999999f}) {
                const glm::vec3 q = o + vx_rect_sample(r, u, v);
                ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) << o.x << "," << o.y;
                EXPECT_NEAR(q.y, 0.f, 1e-2f + 1e-5f * std::abs(o.y));
                EXPECT_GE(q.x, -8.01f);
                EXPECT_LE(q.x, 8.01f);
                EXPECT_GE(q.z, -8.01f);
                EXPECT_LE(q.z, 8.01f);
            }
    }
}

} // namespace
} // namespace vx::render
