#version 460
#extension GL_GOOGLE_include_directive : require
// Temporal accumulation with reprojection (SVGF, Schied et al. 2017, section 4.1): the albedo-
// demodulated diffuse illumination of this frame (colour - reflected) is blended into the history
// found by reprojecting the pixel into the previous frame; history whose normal or depth
// disagrees (disocclusion, an edited block) is dropped. The reflected part (mirror bounces,
// emission) gets the same running mean but no filter: the primary hit's guides say nothing about
// it. Writes the accumulated illumination + a variance estimate for the a-trous passes, the
// accumulated reflected part for the last pass, and the new history.

#include "shared/denoise_types.h"

layout(local_size_x = kDenoiseGroupSize, local_size_y = kDenoiseGroupSize) in;

layout(binding = 0, rgba16f) readonly uniform image2D u_color;        // Noisy HDR radiance.
layout(binding = 1, rgba8) readonly uniform image2D u_albedo;         // Linear albedo.
layout(binding = 2, rgba16f) readonly uniform image2D u_normal_depth; // World normal, view depth.
layout(binding = 3, rgba16f) readonly uniform image2D u_hist_in;      // rgb illumination, a frames.
layout(binding = 4, rgba16f) readonly uniform image2D u_hist_nd_in;   // normal_depth of the history.
layout(binding = 5, rgba16f) writeonly uniform image2D u_hist_out;
layout(binding = 6, rgba16f) writeonly uniform image2D u_hist_nd_out;
layout(binding = 7, rgba16f) writeonly uniform image2D u_filter_out;  // rgb illumination, a variance.
layout(binding = 8, rgba16f) writeonly uniform image2D u_result;      // Last pass: HDR radiance.
layout(binding = 9, rgba8) writeonly uniform image2D u_ldr;           // Last pass: 8-bit output.
layout(binding = 10, rgba16f) readonly uniform image2D u_moments_in;  // Luminance m1, m2, own variance.
layout(binding = 11, rgba16f) writeonly uniform image2D u_moments_out;
layout(binding = 12, rgba16f) readonly uniform image2D u_reflected;   // Not filtered: see above.
layout(binding = 13, rgba16f) readonly uniform image2D u_hist_refl_in;
layout(binding = 14, rgba16f) writeonly uniform image2D u_hist_refl_out;
layout(binding = 15, rgba16f) writeonly uniform image2D u_refl_out;   // Accumulated, for the last pass.

#include "shared/denoise_common.glsl"

// The diffuse part over albedo (>= 0: the half-float difference may dip below).
vec3 illumination(ivec2 p) {
    const vec3 diffuse = max(imageLoad(u_color, p).rgb - imageLoad(u_reflected, p).rgb, vec3(0));
    return diffuse / demod_albedo(imageLoad(u_albedo, p).rgb);
}

// Variance of the luminance over the 3x3 neighbourhood on the same surface (same normal, depth
// within 5%; SVGF's spatial fallback): where the pixel's own estimate is unknown (1 sample).
float spatial_variance(ivec2 p, ivec2 size, vec4 nd) {
    float m1 = 0, m2 = 0, n = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            const vec4 nq = imageLoad(u_normal_depth, q);
            if (!has_surface(nq) || dot(nq.xyz, nd.xyz) < 0.9 || abs(nq.w - nd.w) > 0.05 * nd.w)
                continue;
            const float l = luminance(illumination(q));
            m1 += l;
            m2 += l * l;
            n += 1;
        }
    m1 /= n;
    return max(m2 / n - m1 * m1, 0.0);
}

// The pixels' own variances (render/gbuffer.h) averaged over the 3x3 neighbourhood on the same
// surface (SVGF prefilters its variance the same way): a pixel whose few samples happened to
// agree says variance 0 although its neighbours show the noise. Negative: unknown (1 sample).
float own_variance(ivec2 p, ivec2 size, vec4 nd) {
    if (imageLoad(u_color, p).a < 0.0)
        return -1.0;
    float sum = 0, n = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            const vec4 nq = imageLoad(u_normal_depth, q);
            const float v = imageLoad(u_color, q).a;
            if (v < 0.0 || !has_surface(nq) || dot(nq.xyz, nd.xyz) < 0.9 || abs(nq.w - nd.w) > 0.05 * nd.w)
                continue;
            sum += v;
            n += 1;
        }
    return sum / n; // The centre always counts.
}

// Length of the unnormalised primary ray direction (view depth 1) through `pixel`: a distance
// along the ray divided by it is the view depth.
float ray_scale(vec2 pixel) {
    const vec2 ndc = pixel / vec2(pc.params.xy) * 2.0 - 1.0;
    return length(vec3(ndc.x * pc.camera.x * pc.camera.y, ndc.y * pc.camera.x, 1.0));
}

// expected_distance: along the previous frame's primary ray.
bool history_matches(vec4 nd, vec4 hist_nd, float expected_distance) {
    return has_surface(hist_nd) && dot(nd.xyz, hist_nd.xyz) > 0.9 &&
           abs(hist_nd.w - expected_distance) <= 0.02 * expected_distance + 1e-3;
}

void main() {
    const ivec2 size = ivec2(pc.params.xy);
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size)))
        return;
    const vec4 nd = imageLoad(u_normal_depth, p);
    imageStore(u_hist_nd_out, p, nd);
    if (!has_surface(nd)) { // Sky: nothing to filter or accumulate.
        imageStore(u_hist_out, p, vec4(imageLoad(u_color, p).rgb, 0));
        imageStore(u_moments_out, p, vec4(0));
        imageStore(u_hist_refl_out, p, vec4(0));
        imageStore(u_refl_out, p, vec4(0));
        imageStore(u_filter_out, p, vec4(imageLoad(u_color, p).rgb, 0));
        if ((pc.params.w & kDenoiseLastPass) != 0)
            store_result(p, imageLoad(u_color, p).rgb, vec3(1), false, vec3(0));
        return;
    }
    const vec3 illum = illumination(p);
    float frames = 0;
    vec3 history = vec3(0), history_reflected = vec3(0);
    vec3 moments = vec3(0);
    if ((pc.params.w & kDenoiseHistoryValid) != 0) {
        const vec2 centre = vec2(p) + 0.5;
        const float depth = nd.w / ray_scale(centre);
        const vec4 prev = pc.reproject * vec4(centre * depth, depth, 1);
        if (prev.z > 0) {
            const vec2 prev_pixel = prev.xy / prev.z;
            const ivec2 q = ivec2(floor(prev_pixel));
            if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)) &&
                history_matches(nd, imageLoad(u_hist_nd_in, q), prev.z * ray_scale(prev_pixel))) {
                const vec4 h = imageLoad(u_hist_in, q);
                history = h.rgb;
                frames = h.a;
                moments = imageLoad(u_moments_in, q).xyz;
                history_reflected = imageLoad(u_hist_refl_in, q).rgb;
            }
        }
    }
    frames = min(frames + 1, max(pc.sigmas.w, 1.0));
    const vec3 accumulated = mix(history, illum, 1.0 / frames);
    const float lum = luminance(illum);
    const float own = own_variance(p, size, nd);
    moments = mix(moments, vec3(lum, lum * lum, own), 1.0 / frames);
    const vec3 reflected = mix(history_reflected, imageLoad(u_reflected, p).rgb, 1.0 / frames);
    // Variance of one frame's estimate: the pixels' own from their light samples
    // (render/gbuffer.h; the sample counts are the same in every frame of the history, so it is
    // averaged over it); unknown (1 sample): from the temporal moments once 4 frames are in
    // (SVGF), else from the 3x3 neighbourhood (which also counts pixel-sized detail as noise).
    float sample_variance = moments.z;
    if (own < 0.0)
        sample_variance = frames >= 4.0 ? max(moments.y - moments.x * moments.x, 0.0)
                                        : spatial_variance(p, size, nd);
    imageStore(u_hist_out, p, vec4(accumulated, frames));
    imageStore(u_moments_out, p, vec4(moments, 0));
    imageStore(u_hist_refl_out, p, vec4(reflected, 0));
    imageStore(u_refl_out, p, vec4(reflected, 0));
    imageStore(u_filter_out, p, vec4(accumulated, sample_variance / frames));
    if ((pc.params.w & kDenoiseLastPass) != 0) // No a-trous pass follows.
        store_result(p, accumulated, imageLoad(u_albedo, p).rgb, true, reflected);
}
