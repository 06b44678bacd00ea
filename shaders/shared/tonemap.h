// From linear HDR radiance to the 8-bit output: exposure, a filmic tone curve, the sRGB encoding.
// Shared by GLSL (raygen, the denoiser's last pass, the raster baseline) and C++ (the renderer,
// tests). Included by both: only the common subset of C++ and GLSL.
//
// Units. The renderer's radiance (sky, area light, block emission) is linear RGB in units of
// kNitsPerUnit cd/m^2, irradiance (the sun) in kNitsPerUnit lux. With 10^4 the default lights
// are a clear day: sky 0.55..0.95 is 5.5..9.5 kcd/m^2 (a clear sky measures 2..10), and flat
// ground receives about 7.5 units = 75 klux from sun, sky and area light (daylight: 30..100).
//
// Exposure: the physical camera of Filament ("Physically Based Rendering in Filament",
// "Physically based camera") and Frostbite (Lagarde & de Rousiers, "Moving Frostbite to PBR",
// 2014, camera exposure), with the saturation-based sensitivity (ISO 12232 SBS, q = 0.65):
// the luminance that saturates the sensor at EV100 is L_max = 1.2 * 2^EV100 cd/m^2, and the
// exposed value is L / L_max. One EV100 more halves the exposed value; sunny-16 daylight is
// EV100 15. The default, 14.7 (render/renderer.h), puts flat ground of albedo 0.18 under the
// default lights at mid-grey (kMidGreyInput).
//
// Tone curve: Narkowicz's fit of the ACES RRT + sRGB ODT ("ACES Filmic Tone Mapping Curve",
// 2016: (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]), per channel. It
// maps 0 to 0, is strictly increasing for x >= 0 (its derivative's numerator is
// 1.408 x^2 + 0.7028 x + 0.0042), has a toe (contrast below mid-grey) and a shoulder that
// reaches 1 at x = 7.24: highlights and emitters roll off instead of clipping. Per channel it
// saturates bright colours a little (Narkowicz's note); block colours are far below the shoulder.
#ifndef VX_SHADERS_TONEMAP_H
#define VX_SHADERS_TONEMAP_H

#ifdef __cplusplus
#include <cmath>
#include <glm/glm.hpp>
namespace vx::render::gpu {
#define VX_TM_FN inline
#define VX_TM_CONST inline constexpr
using tm_vec3 = glm::vec3;
using glm::dot;
using std::exp2;
using std::pow;
#else
#define VX_TM_FN
#define VX_TM_CONST const
#define tm_vec3 vec3
#endif

VX_TM_CONST float kNitsPerUnit = 10000.0f; // cd/m^2 per unit of the renderer's radiance.

// The value vx_tonemap1 maps to 0.1812, the linear value of sRGB 118 (photographic mid-grey,
// 18% reflectance): (2.51 - 0.1812 * 2.43) x^2 + (0.03 - 0.1812 * 0.59) x - 0.1812 * 0.14 = 0.
// Auto exposure puts a frame's log-average luminance here (key 0.18).
VX_TM_CONST float kMidGreyInput = 0.1308f;

// Luminance of linear RGB (Rec. 709 primaries, the renderer's): the weight of light in noise
// estimates, exposure metering and light selection.
VX_TM_FN float vx_luminance(tm_vec3 c) { return dot(c, tm_vec3(0.2126f, 0.7152f, 0.0722f)); }

// Scale from the renderer's radiance to the tone curve's input at exposure value `ev100`:
// kNitsPerUnit / L_max (see Exposure above).
VX_TM_FN float vx_exposure_scale(float ev100) { return kNitsPerUnit / (1.2f * exp2(ev100)); }

VX_TM_FN float vx_tonemap1(float x) {
    // Past 8 the curve is 1 (clamped below); capping there keeps x * x finite (inf / inf: NaN).
    x = x < 0.0f ? 0.0f : (x > 8.0f ? 8.0f : x);
    float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return y > 1.0f ? 1.0f : y;
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

// The whole output transform of Full shading: radiance at exposure scale `exposure`
// (vx_exposure_scale) to the sRGB-encoded value in [0, 1].
VX_TM_FN tm_vec3 vx_display(tm_vec3 radiance, float exposure) {
    return vx_srgb_encode(vx_tonemap(radiance * exposure));
}

#ifdef __cplusplus
#undef VX_TM_FN
#undef VX_TM_CONST
} // namespace vx::render::gpu
#else
#undef tm_vec3
#endif
#endif
