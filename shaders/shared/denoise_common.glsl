// Helpers of the denoiser's compute shaders.
#ifndef VX_DENOISE_COMMON_GLSL
#define VX_DENOISE_COMMON_GLSL

#include "shared/denoise_types.h"
#include "shared/tonemap.h"

layout(push_constant) uniform Push { DenoisePush pc; };

float luminance(vec3 c) { return vx_luminance(c); }

// Albedo used to demodulate: black albedo (sky, emitters without a colour) divides by 1.
vec3 demod_albedo(vec3 albedo) { return max(albedo, vec3(1e-3)); }

// A pixel with geometry: distance > 0 (render/gbuffer.h: a miss stores 0) and finite (past
// half float's 65504 a driver may store infinity: read as a miss, not divided by).
bool has_surface(vec4 normal_depth) { return normal_depth.w > 0.0 && !isinf(normal_depth.w); }

// Whether `q` (normal + distance) continues the surface of `p`: a hit, the same normal, the
// distance within 5% (SVGF's neighbourhood test for variance and history clamping).
bool same_surface(vec4 p, vec4 q) {
    return has_surface(q) && dot(q.xyz, p.xyz) >= 0.9 && abs(q.w - p.w) <= 0.05 * p.w;
}

// Whether the sun reaches a pixel is known exactly (its primary ray is the pixel's centre, in
// every frame and in a converged image alike; render/gbuffer.h, reflected a), so the a-trous
// taps never cross a sun shadow's edge. The flag (true: the sun's rays were traced and all were
// blocked) travels in the sign bit of the filtered illumination's variance (>= 0; -0 for 0), which
// every pass reads anyway: no image read per tap.
float with_sun_flag(float variance, bool blocked) { return blocked ? -variance : variance; }
bool sun_blocked(float flagged_variance) { return (floatBitsToUint(flagged_variance) & 0x80000000u) != 0u; }

// The last pass's outputs: HDR radiance (the remodulated illumination plus the unfiltered
// reflected part), and the 8-bit image as the ray tracer writes it (render/gbuffer.h: exposed,
// tone-mapped, sRGB encoded).
void store_result(ivec2 p, vec3 illumination, vec3 albedo, bool surface, vec3 reflected) {
    const vec3 radiance = illumination * (surface ? demod_albedo(albedo) : vec3(1)) + reflected;
    imageStore(u_result, p, vec4(radiance, 1));
    imageStore(u_ldr, p, vec4(vx_display(radiance, pc.camera.z), 1));
}

#endif
