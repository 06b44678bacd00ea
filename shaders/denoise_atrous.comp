#version 460
#extension GL_GOOGLE_include_directive : require
// One iteration of the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) with SVGF's
// edge-stopping functions (Schied et al. 2017, section 4.2): a 5x5 B3-spline kernel with holes
// (step 1, 2, 4, ...) weighted by normal, depth (against the local depth gradient) and luminance
// (against the filtered variance; the first pass compares with the centre's 3x3-blurred luminance,
// see prefiltered_luminance()). It filters albedo-demodulated illumination, so block colours
// stay sharp; the last pass multiplies the albedo back in and adds the (unfiltered) reflected part.
// With kDenoiseMirror the same pass filters the first mirror bounce's demodulated light guided by
// the reflected surface's normal and path length, remodulated by its albedo in the last pass.
//
// Two guides from the ray tracer's own rays steer the primary illumination's filter (render/
// gbuffer.h, reflected a; docs/render_report.md, 2026-12-02), as ReBLUR and SIGMA (NVIDIA RTX
// Denoisers) steer theirs by hit and occluder distances: the scale of the light (the temporal
// pass's footprint: how many pixels the sky term needs to change, from the distance of the
// blocks the sky rays hit) relaxes the luminance stop where the light is smooth, and whether the
// sun reaches a pixel (exact, not sampled noise) stops taps at sun shadows' edges.

#include "shared/denoise_types.h"

layout(local_size_x = kDenoiseGroupSize, local_size_y = kDenoiseGroupSize) in;

layout(binding = 0, rgba16f) readonly uniform image2D u_in;           // rgb illumination, a variance.
layout(binding = 1, rgba8) readonly uniform image2D u_albedo;
layout(binding = 2, rgba16f) readonly uniform image2D u_normal_depth;
layout(binding = 3, rgba16f) writeonly uniform image2D u_out;         // Next iteration's input.
layout(binding = 4, rgba16f) writeonly uniform image2D u_result;      // Last pass: HDR radiance.
layout(binding = 5, rgba8) writeonly uniform image2D u_ldr;           // Last pass: 8-bit output.
layout(binding = 6, rgba16f) readonly uniform image2D u_reflected;    // The temporal pass's.
layout(binding = 7, rgba16f) readonly uniform image2D u_mirror_in;    // rgb mirror light, a variance.
layout(binding = 8, rgba16f) readonly uniform image2D u_mirror_nd;    // Its surface's normal, path length.
layout(binding = 9, rgba16f) writeonly uniform image2D u_mirror_out;
layout(binding = 10, rgba8) readonly uniform image2D u_mirror_albedo;

#include "shared/denoise_common.glsl"

const float kKernel[3] = float[](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
const float kLog2e = 1.4426950408889634;

// The channel's images: the primary hit's illumination and guides, or the mirror bounce's.
vec4 load_in(bool mirror, ivec2 q) { return mirror ? imageLoad(u_mirror_in, q) : imageLoad(u_in, q); }
vec4 load_nd(bool mirror, ivec2 q) { return mirror ? imageLoad(u_mirror_nd, q) : imageLoad(u_normal_depth, q); }

float depth_at(bool mirror, ivec2 q, ivec2 size) { return load_nd(mirror, clamp(q, ivec2(0), size - 1)).w; }

// The primary illumination's luminance at p blurred over the 3x3 neighbourhood on the same
// surface (weights 1-2-1): what the first pass compares its neighbours with. At a few samples a
// pixel's own value is often an outlier (a shadow sample that got through), and against it every
// neighbour looks like an edge, so the outlier stayed; the blurred value is near the truth there.
// Only the first pass: later ones see filtered values. Not for the mirror light: at 16 spp the
// blur cost the mirror field's reflections more than it gained (docs/render_report.md). Not from
// kDenoiseManySamples (DenoisePush camera.w): there a pixel's own light is rarely an outlier,
// and the blur drew penumbrae's light across their gradients (lavapipe, stop 40: terrain at 16 spp
// 0.984 -> 0.925 of the raw error; the thesis's light at 25 spp 1.16 -> 1.08).
float prefiltered_luminance(ivec2 p, ivec2 size, vec4 nd) {
    float sum = 0.0, weight = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            const float w = same_surface(nd, imageLoad(u_normal_depth, q)) ? float((2 - abs(dx)) * (2 - abs(dy))) : 0.0;
            sum += w * luminance(imageLoad(u_in, q).rgb);
            weight += w;
        }
    return sum / weight; // The centre always counts.
}

// The scale of the light (the temporal pass's footprint, u_reflected's a: pixels; 0: unknown;
// kNoOccluder: no occluder near) decides how far the luminance stop trusts the pixels'
// own variance. At 4 samples a pixel whose few sky rays happened to agree says variance ~0
// although the light under an overhang 7 blocks up is smooth over many pixels: there the passes
// of step <= kRelaxLastStep compare with a luminance scale kRelax times wider (ramped in from
// kRelaxFrom to kRelaxFull pixels), and every pass compares with the blurred centre (below
// kDenoiseManySamples). Where the scale is a pixel or two (an inner corner's darkening, a
// contact shadow: the hills' detail) the filter is as before. Measured on lavapipe
// (docs/render_report.md): a wider scale (x8) or relaxing the wider passes too blurred light
// across sun shadows and the 16-spp mirror field.
const float kRelaxFrom = 2.0;
const float kRelaxFull = 8.0;
const float kRelax = 6.0;
const int kRelaxLastStep = 2;

// One a-trous step of a channel at p (no surface: unchanged).
vec4 filter_at(bool mirror, ivec2 p, ivec2 size, int step) {
    const vec4 centre = load_in(mirror, p);
    const vec4 nd = load_nd(mirror, p);
    if (!has_surface(nd))
        return centre;
    // Screen-space depth gradient (central differences, same-surface neighbours only).
    const float d = nd.w;
    vec2 grad = vec2(depth_at(mirror, p + ivec2(1, 0), size) - depth_at(mirror, p - ivec2(1, 0), size),
                     depth_at(mirror, p + ivec2(0, 1), size) - depth_at(mirror, p - ivec2(0, 1), size)) * 0.5;
    grad = clamp(grad, vec2(-d), vec2(d));
    const float footprint = mirror ? 0.0 : imageLoad(u_reflected, p).a;
    const bool blocked = sun_blocked(centre.a);
    const bool wide = footprint >= kRelaxFull && footprint < kNoOccluder;
    const float relax = step <= kRelaxLastStep && footprint > 0.0 && footprint < kNoOccluder
                            ? mix(1.0, kRelax, smoothstep(kRelaxFrom, kRelaxFull, footprint))
                            : 1.0;
    const bool prefiltered = (step == 1 || wide) && !mirror && pc.camera.w < kDenoiseManySamples;
    const float lum = prefiltered ? prefiltered_luminance(p, size, nd) : luminance(centre.rgb);
    const float lum_scale = relax * pc.sigmas.z * sqrt(abs(centre.a)) + 1e-4;
    vec3 sum = vec3(0);
    float var_sum = 0, w_sum = 0;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            const ivec2 q = p + ivec2(dx, dy) * step;
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
                continue;
            const vec4 ndq = load_nd(mirror, q);
            const float cosine = dot(nd.xyz, ndq.xyz);
            if (!has_surface(ndq) || cosine <= 0.0) // w_normal 0.
                continue;
            const vec4 cq = load_in(mirror, q);
            // Sun shadow edges are sharp: never across one (the sun reaches the pixel or not in
            // the reference too; the primary ray is the pixel's centre).
            if (sun_blocked(cq.a) != blocked)
                continue;
            // w_normal * w_depth * w_lum = cosine^sigma_n * e^-(depth stop + luminance stop), in
            // one exp2: a tap's weight was four transcendentals, now two (pow is exp2 of log2).
            const float expected = abs(dot(grad, vec2(ivec2(dx, dy) * step)));
            const float depth_stop = abs(d - ndq.w) / (pc.sigmas.y * expected + 1e-3 * d + 1e-4);
            // The centre keeps weight 1 also against a prefiltered luminance far from its own.
            const float lum_stop = (dx == 0 && dy == 0) ? 0.0 : abs(lum - luminance(cq.rgb)) / lum_scale;
            const float w = kKernel[abs(dx)] * kKernel[abs(dy)] *
                            exp2(pc.sigmas.x * log2(cosine) - kLog2e * (depth_stop + lum_stop));
            sum += w * cq.rgb;
            var_sum += w * w * abs(cq.a);
            w_sum += w;
        }
    // The centre tap always has weight kKernel[0]^2 > 0.
    return vec4(sum / w_sum, with_sun_flag(var_sum / (w_sum * w_sum), blocked));
}

void main() {
    const ivec2 size = ivec2(pc.params.xy);
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size)))
        return;
    const int step = int(pc.params.z);
    // The last pass's filtered light goes only into the outputs: no pass reads u_out after it.
    const bool last = (pc.params.w & kDenoiseLastPass) != 0;
    const vec4 result = filter_at(false, p, size, step);
    if (!last)
        imageStore(u_out, p, result);
    vec3 mirror = vec3(0);
    if ((pc.params.w & kDenoiseMirror) != 0) {
        const vec4 m = filter_at(true, p, size, step);
        if (!last)
            imageStore(u_mirror_out, p, m);
        if (has_surface(imageLoad(u_mirror_nd, p)))
            mirror = m.rgb * imageLoad(u_mirror_albedo, p).rgb;
    }
    if (last)
        store_result(p, result.rgb, imageLoad(u_albedo, p).rgb, has_surface(imageLoad(u_normal_depth, p)),
                     imageLoad(u_reflected, p).rgb + mirror);
}
