// Sampling a rectangular light by solid angle: Ureña, Fajardo and King, "An Area-Preserving
// Parametrization for Spherical Rectangles", EGSR 2013. Uniform points (u, v) in [0, 1)^2 map to
// points of the rectangle whose directions from the shading point are uniform over the solid
// angle S the rectangle subtends, so an estimate of irradiance is S * L * mean(V cos) and the
// light's 1/d^2 and cosine at the light (the area estimator's extra noise) drop out. Shared by
// GLSL (shaders/raygen.rgen) and C++ (the test oracle: tests/render/rect_light_test.cpp). Units:
// blocks, any frame whose origin is the caller's; the rectangle is two-sided.
//
// Where the method's arithmetic fails it says so (valid false) and the caller samples by area:
// the rectangle's edges not orthogonal (a parallelogram), the shading point in or next to the
// light's plane, or S under kRectMinSolidAngle. S is g0 + g1 + g2 + g3 - 2 pi, a difference of
// numbers near 2 pi: in float its error is about 1e-6 sr, and over so small a light (a cone of
// about 1 degree) the geometric term hardly varies, so area sampling loses nothing there.
#ifndef VX_SHADERS_RECT_LIGHT_H
#define VX_SHADERS_RECT_LIGHT_H

#ifdef __cplusplus
#include <cmath>
#include <glm/glm.hpp>
namespace vx::render::gpu {
#define VX_R_FN inline
using r_vec3 = glm::vec3;
using glm::clamp;
using glm::cross;
using glm::dot;
using glm::length;
using glm::normalize;
using std::acos;
using std::abs;
using std::cos;
using std::sin;
using std::sqrt;
#else
#define VX_R_FN
#define r_vec3 vec3
#endif

// kRectSpreadFrom: the caller samples by solid angle where area sampling's weight, the light's
// cos / d^2, varies over the light by at least this factor (vx_rect_spread). Under it solid-angle
// sampling removes little noise and its arithmetic costs more: on the H200, sampling the thesis
// scene's light (128 blocks wide, 256 above; spread up to 2.83) always by solid angle took 57.3 ->
// 65.2 ms at 25 spp for 2-8% less error. A light 4 blocks above a roof lost 30% of its error at 4
// spp on lavapipe with a threshold of 2, 3 or 4 alike (docs/render_report.md, stop 21).
#ifdef __cplusplus
inline constexpr float kRectMinSolidAngle = 1e-3f; // sr
inline constexpr float kRectSpreadFrom = 4.0f;
inline constexpr float kRectPi = 3.14159265358979f;
#else
const float kRectMinSolidAngle = 1e-3;
const float kRectSpreadFrom = 4.0;
const float kRectPi = 3.14159265358979;
#endif

// How much area sampling's weight |cos at the light| / d^2 varies over the rectangle corner +
// [0, 1] eu + [0, 1] ev seen from `origin`: that weight is h / d^3 with h the point's distance
// from the light's plane, so its largest over its smallest is (d_far / d_near)^3, d_near the
// distance to the rectangle's nearest point, d_far to its farthest corner. 0 for a point in the
// plane. Cheap: no trigonometry.
VX_R_FN float vx_rect_spread(r_vec3 origin, r_vec3 corner, r_vec3 eu, r_vec3 ev) {
    const r_vec3 p = origin - corner;
    const float s = clamp(dot(p, eu) / dot(eu, eu), 0.0f, 1.0f), t = clamp(dot(p, ev) / dot(ev, ev), 0.0f, 1.0f);
    const r_vec3 near_offset = p - s * eu - t * ev;
    const float near2 = dot(near_offset, near_offset);
    if (near2 <= 0.0f)
        return 0.0f;
    float far2 = 0.0f;
    for (int i = 0; i < 4; ++i) {
        const r_vec3 c = p - ((i & 1) != 0 ? eu : r_vec3(0.0f)) - ((i & 2) != 0 ? ev : r_vec3(0.0f));
        const float d2 = dot(c, c);
        far2 = d2 > far2 ? d2 : far2;
    }
    const float ratio = sqrt(far2 / near2);
    return ratio * ratio * ratio;
}

// The rectangle as seen from one shading point (the paper's local frame: x, y along the edges,
// z towards the point's side, the point at the origin).
struct RectView {
    r_vec3 x, y, z;      // Unit frame vectors (world orientation).
    float x0, y0, z0;    // The corner in that frame (z0 < 0).
    float x1, y1;        // The opposite corner's x, y.
    float b0, b1, k;     // The paper's constants of the inversion.
    float solid_angle;   // S, sr.
    bool valid;          // False: sample by area instead.
};

// The view of the rectangle corner + [0, 1] eu + [0, 1] ev from `origin`.
VX_R_FN RectView vx_rect_view(r_vec3 origin, r_vec3 corner, r_vec3 eu, r_vec3 ev) {
    RectView r;
    r.valid = false;
    r.solid_angle = 0.0f;
    const float lu = length(eu), lv = length(ev);
    r.x = eu / lu;
    r.y = ev / lv;
    r.z = cross(r.x, r.y);
    const r_vec3 d = corner - origin;
    r.x0 = dot(d, r.x);
    r.y0 = dot(d, r.y);
    r.z0 = dot(d, r.z);
    if (r.z0 > 0.0f) { // The point on the other side: face it (two-sided light).
        r.z0 = -r.z0;
        r.z = -r.z;
    }
    r.x1 = r.x0 + lu;
    r.y1 = r.y0 + lv;
    r.b0 = 0.0f;
    r.b1 = 0.0f;
    r.k = 0.0f;
    // Not a rectangle, or the point (nearly) in its plane: the normals below degenerate.
    if (abs(dot(r.x, r.y)) > 1e-4f || -r.z0 < 1e-4f * (lu + lv))
        return r;
    const r_vec3 n0 = normalize(r_vec3(0.0f, r.z0, -r.y0));
    const r_vec3 n1 = normalize(r_vec3(-r.z0, 0.0f, r.x1));
    const r_vec3 n2 = normalize(r_vec3(0.0f, -r.z0, r.y1));
    const r_vec3 n3 = normalize(r_vec3(r.z0, 0.0f, -r.x0));
    const float g0 = acos(clamp(-n0.z * n1.z, -1.0f, 1.0f));
    const float g1 = acos(clamp(-n1.z * n2.z, -1.0f, 1.0f));
    const float g2 = acos(clamp(-n2.z * n3.z, -1.0f, 1.0f));
    const float g3 = acos(clamp(-n3.z * n0.z, -1.0f, 1.0f));
    r.b0 = n0.z;
    r.b1 = n2.z;
    r.k = 2.0f * kRectPi - g2 - g3;
    r.solid_angle = g0 + g1 - r.k;
    r.valid = r.solid_angle >= kRectMinSolidAngle;
    return r;
}

// The point of the rectangle (relative to the shading point, world orientation) for (u, v) in
// [0, 1)^2; uniform in solid angle (pdf 1 / r.solid_angle). Needs r.valid.
VX_R_FN r_vec3 vx_rect_sample(RectView r, float u, float v) {
    const float au = u * r.solid_angle + r.k;
    const float fu = (cos(au) * r.b0 - r.b1) / sin(au);
    float cu = (fu > 0.0f ? 1.0f : -1.0f) / sqrt(fu * fu + r.b0 * r.b0);
    cu = clamp(cu, -1.0f, 1.0f);
    float xu = -(cu * r.z0) / sqrt(1.0f - cu * cu);
    xu = clamp(xu, r.x0, r.x1);
    const float dd = sqrt(xu * xu + r.z0 * r.z0);
    const float h0 = r.y0 / sqrt(dd * dd + r.y0 * r.y0);
    const float h1 = r.y1 / sqrt(dd * dd + r.y1 * r.y1);
    const float hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    const float yv = hv2 < 1.0f - 1e-6f ? (hv * dd) / sqrt(1.0f - hv2) : (hv < 0.0f ? r.y0 : r.y1);
    return xu * r.x + clamp(yv, r.y0, r.y1) * r.y + r.z0 * r.z;
}

#ifdef __cplusplus
#undef VX_R_FN
} // namespace vx::render::gpu
#else
#undef r_vec3
#endif
#endif
