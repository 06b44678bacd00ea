// Tone mapping from linear HDR radiance to the 8-bit output, shared by GLSL (raygen, a denoiser's
// resolve pass) and C++ (tests). Included by both: only the common subset of C++ and GLSL.
//
// The curve is the identity up to kToneKnee and an exponential shoulder above it:
//   f(x) = x                                              x <= k
//   f(x) = k + (1 - k) * (1 - exp(-(x - k) / (1 - k)))    x >  k
// It is C1 at k (slope 1), strictly increasing and below 1 for every finite x, applied per
// channel. Why this one: block albedos and the default sky are below k, so flat colours and
// the sky keep their exact values (no global darkening as with Reinhard), while lit highlights
// and emitters above 1 roll off instead of clipping (x = 1 maps to 0.926, x = 1.5 to 0.994).
// Per-channel compression desaturates colours brighter than k (acceptable for blocks).
#ifndef VX_SHADERS_TONEMAP_H
#define VX_SHADERS_TONEMAP_H

#ifdef __cplusplus
#include <cmath>
#include <glm/glm.hpp>
namespace vx::render::gpu {
#define VX_TM_FN inline
#define VX_TM_CONST inline constexpr
using tm_vec3 = glm::vec3;
using std::exp;
using std::pow;
#else
#define VX_TM_FN
#define VX_TM_CONST const
#define tm_vec3 vec3
#endif

VX_TM_CONST float kToneKnee = 0.8f;

VX_TM_FN float vx_tonemap1(float x) {
    if (x <= kToneKnee)
        return x < 0.0f ? 0.0f : x;
    return kToneKnee + (1.0f - kToneKnee) * (1.0f - exp(-(x - kToneKnee) / (1.0f - kToneKnee)));
}

VX_TM_FN tm_vec3 vx_tonemap(tm_vec3 c) { return tm_vec3(vx_tonemap1(c.x), vx_tonemap1(c.y), vx_tonemap1(c.z)); }

// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1].
VX_TM_FN float vx_srgb_encode1(float c) {
    c = c < 0.0f ? 0.0f : (c > 1.0f ? 1.0f : c);
    return c <= 0.0031308f ? c * 12.92f : 1.055f * pow(c, 1.0f / 2.4f) - 0.055f;
}

VX_TM_FN tm_vec3 vx_srgb_encode(tm_vec3 c) {
    return tm_vec3(vx_srgb_encode1(c.x), vx_srgb_encode1(c.y), vx_srgb_encode1(c.z));
}

#ifdef __cplusplus
#undef VX_TM_FN
#undef VX_TM_CONST
} // namespace vx::render::gpu
#else
#undef tm_vec3
#endif
#endif
