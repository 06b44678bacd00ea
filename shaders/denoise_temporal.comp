#version 460
#extension GL_GOOGLE_include_directive : require
// Temporal accumulation with reprojection (SVGF, Schied et al. 2017, section 4.1): the albedo-
// demodulated diffuse illumination of this frame (colour - reflected) is blended into the history
// found by reprojecting the pixel into the previous frame; history whose normal or depth
// disagrees (disocclusion, an edited block) is dropped. The reflected part (mirror bounces,
// emission) gets the same running mean but no filter: the primary hit's guides say nothing about
// it. Writes the accumulated illumination + a variance estimate for the a-trous passes, the
// accumulated reflected part for the last pass, and the new history where a next frame reads it.
//
// History clamping (kDenoiseHistoryClamp): history that matches in normal and depth can still be
// stale (a block placed nearby now shadows the pixel; a reflection moves across a mirror while
// the mirror stays put), and SVGF would fade it out over max_history frames. A change of light
// shows sooner in a neighbourhood's mean than in any one pixel, so when this frame's mean over
// the 3x3 window (or a half of it: a pixel at a new shadow's edge has one on its side) leaves the
// history's by 4.5 standard errors, the history is dropped as on a disocclusion, the test A-SVGF
// makes with its temporal gradients (Schied et al. 2018). 4 dropped enough still pixels on noise
// alone to cost 15% of an 8-frame accumulation's RMSE (tests/render/denoise_render_test.cpp);
// 4.5 costs 9% (15% with the Sobol sampler, docs/render_report.md) and still catches a shadow's
// edge at 4 spp. The reflected part keeps its own length and is clamped to this frame's
// neighbourhood (Karis 2014). A history tap must also lie on the pixel's plane and on its side
// of a sun shadow's edge (tap_matches): bilinear taps across either mix another surface's or
// another light's history in.
//
// Mirrors (kDenoiseMirror): the first mirror bounce's diffuse lighting over its surface's albedo
// is taken out of the reflected part and accumulated like it (history clamped to the
// neighbourhood box on the same reflected surface), with a variance for the a-trous passes,
// which filter it in the reflected surface's terms. On a mirror pixel both the mirror light's and
// the reflected part's histories are reprojected through the mirror's virtual image (the point at
// the path's length along the primary ray), which is how a flat mirror's picture moves; through
// the mirror's own surface they lagged a moving camera (fly-over 4 spp: 0.0211 -> 0.0130 RMSE
// with bilinear taps, docs/render_report.md).

#include "shared/denoise_types.h"

layout(local_size_x = kDenoiseGroupSize, local_size_y = kDenoiseGroupSize) in;

layout(binding = 0, rgba16f) readonly uniform image2D u_color;        // Noisy HDR radiance.
layout(binding = 1, rgba8) readonly uniform image2D u_albedo;         // Linear albedo.
layout(binding = 2, rgba16f) readonly uniform image2D u_normal_depth; // World normal, view depth.
layout(binding = 3, rgba32f) readonly uniform image2D u_hist_in;      // rgb illumination, a frames.
layout(binding = 4, rgba16f) readonly uniform image2D u_hist_nd_in;   // normal_depth of the history.
layout(binding = 5, rgba32f) writeonly uniform image2D u_hist_out;
layout(binding = 6, rgba16f) writeonly uniform image2D u_hist_nd_out;
layout(binding = 7, rgba16f) writeonly uniform image2D u_filter_out;  // rgb illumination, a variance.
layout(binding = 8, rgba16f) writeonly uniform image2D u_result;      // Last pass: HDR radiance.
layout(binding = 9, rgba8) writeonly uniform image2D u_ldr;           // Last pass: 8-bit output.
layout(binding = 10, rgba32f) readonly uniform image2D u_moments_in;  // m1, m2, own variance; sun flag.
layout(binding = 11, rgba32f) writeonly uniform image2D u_moments_out;
layout(binding = 12, rgba16f) readonly uniform image2D u_reflected;   // Not filtered: see above.
layout(binding = 13, rgba32f) readonly uniform image2D u_hist_refl_in; // rgb, a: its frames.
layout(binding = 14, rgba32f) writeonly uniform image2D u_hist_refl_out;
layout(binding = 15, rgba16f) writeonly uniform image2D u_refl_out;   // Accumulated, for the last pass.
layout(binding = 16, rgba16f) readonly uniform image2D u_mirror;      // Mirror light, a variance.
layout(binding = 17, rgba8) readonly uniform image2D u_mirror_albedo;
layout(binding = 18, rgba16f) readonly uniform image2D u_mirror_nd;   // Its normal, path length.
layout(binding = 19, rgba32f) readonly uniform image2D u_hist_mirror_in; // rgb, a: its frames.
layout(binding = 20, rgba32f) writeonly uniform image2D u_hist_mirror_out;
layout(binding = 21, rgba16f) writeonly uniform image2D u_mirror_filter_out; // rgb, a variance.

#include "shared/denoise_common.glsl"

// This frame's inputs are read through these. A non-finite value (radiance or a variance past
// half float's 65504 where a driver stores infinity, a NaN from anywhere) reads as nothing:
// radiance 0, variance unknown. Read as it was, one such sample made the whole frame NaN (the
// a-trous taps of weight 0 still multiply: 0 * inf) and stayed in the history for good.
bool finite4(vec4 v) { return !any(isinf(v)) && !any(isnan(v)); }
vec4 color_at(ivec2 q) {
    const vec4 c = imageLoad(u_color, q);
    return finite4(c) ? c : vec4(0, 0, 0, -1);
}
vec4 reflected_at(ivec2 q) {
    const vec4 r = imageLoad(u_reflected, q);
    return finite4(r) ? r : vec4(0);
}
vec4 mirror_at(ivec2 q) {
    const vec4 m = imageLoad(u_mirror, q);
    return finite4(m) ? m : vec4(0, 0, 0, -1);
}

// Whether a surface's albedo (u_albedo, u_mirror_albedo) marks it near this frame's edits:
// a = kEditedAlpha (1: a surface, 0: none; render/gbuffer.h), stored in 8 bits.
bool edited(vec4 albedo) { return albedo.a > 0.25 && albedo.a < 0.75; }

// Bilinear history taps (history_taps()): pixel i is base + (i & 1, i >> 1), w its weight.
struct Taps {
    ivec2 base;
    vec4 w;
    ivec2 nearest;
};

ivec2 tap_pixel(Taps taps, int i) { return taps.base + ivec2(i & 1, i >> 1); }

bool mirror_inputs() { return (pc.params.w & kDenoiseMirror) != 0; }

// Whether a next frame reads the history (max_history > 1): a single-frame denoiser leaves it
// unwritten, 5 stores a pixel (issue 18's lavapipe scene at 4 spp: the pass 0.5 ms of 2.2).
bool keep_history() { return (pc.params.w & kDenoiseKeepHistory) != 0; }

// The first mirror bounce's diffuse lighting, remodulated (0 without one).
vec3 mirror_part(ivec2 p) {
    if (!mirror_inputs() || !has_surface(imageLoad(u_mirror_nd, p)))
        return vec3(0);
    return mirror_at(p).rgb * imageLoad(u_mirror_albedo, p).rgb;
}

// The diffuse part over albedo (>= 0: the half-float difference may dip below).
vec3 illumination(ivec2 p) {
    const vec3 diffuse = max(color_at(p).rgb - reflected_at(p).rgb - mirror_part(p), vec3(0));
    return diffuse / demod_albedo(imageLoad(u_albedo, p).rgb);
}

#include "shared/denoise_mirror.glsl"

// Variance of the luminance over the 3x3 neighbourhood on the same surface (same normal, depth
// within 5%; SVGF's spatial fallback): where the pixel's own estimate is unknown (1 sample).
float spatial_variance(ivec2 p, ivec2 size, vec4 nd) {
    float m1 = 0, m2 = 0, n = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            if (!same_surface(nd, imageLoad(u_normal_depth, q)))
                continue;
            const float l = luminance(illumination(q));
            m1 += l;
            m2 += l * l;
            n += 1;
        }
    m1 /= n;
    return max(m2 / n - m1 * m1, 0.0);
}

// Length of the unnormalised primary ray direction (view depth 1) through `pixel`: a distance
// along the ray divided by it is the view depth.
float ray_scale(vec2 pixel) {
    const vec2 ndc = pixel / vec2(pc.params.xy) * 2.0 - 1.0;
    return length(vec3(ndc.x * pc.camera.x * pc.camera.y, ndc.y * pc.camera.x, 1.0));
}

// What the 5x5 window around p on the same surface says, in one loop that reads each pixel's
// normal and depth once:
//  - variance: the pixels' own variances (render/gbuffer.h) averaged (SVGF prefilters its
//    variance the same way): a pixel whose few samples happened to agree says variance 0
//    although its neighbours show the noise. x: over 3x3, for the history clamp (a 5x5 mean
//    across a new shadow's edge hid the change: ghosts); y: over 5x5, for the filter (at 4 spp a
//    3x3 mean still left such pixels under-filtered, docs/render_report.md). Negative: unknown
//    (1 sample).
//  - footprint: the scale of the light at p in pixels, the a-trous passes' guide (written to
//    u_refl_out's a; shaders/denoise_atrous.comp): the occluder distance (render/gbuffer.h,
//    reflected a: the mean distance of the pixel's sky rays that hit a block) over the world size
//    of a pixel at p's view depth, d 2 tan(fov / 2) / height. Pooled over the window's 3x3 pixels
//    2 apart as a mean of inverse distances: one pixel's 4 rays are noisy, and the nearest
//    occluders decide how fast the light varies. (Its 5x5 pixels 2 apart, as to stop 66, gave
//    the same error on issue 18's scene at 4 spp and cost 16 more taps: docs/render_report.md.)
//    A sun shadow's edge is sharper than any of this: where those pixels disagree on whether the
//    sun reaches them, kSunEdge (the luminance stop stays as it was). 0: unknown (no rays);
//    kNoOccluder (shared/denoise_types.h): no ray nearby hit anything (nothing to scale by).
const float kSunEdge = 0.5; // Pixels.
struct Window {
    vec2 variance;
    float footprint;
};
Window window_stats(ivec2 p, ivec2 size, vec4 nd) {
    const bool own_known = color_at(p).a >= 0.0;
    vec2 sum = vec2(0), n = vec2(0);
    float inverse = 0, hits = 0, known = 0, sunlit = 0;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            if (!same_surface(nd, imageLoad(u_normal_depth, q)))
                continue;
            const float v = own_known ? color_at(q).a : -1.0;
            if (v >= 0.0) {
                const float inner = max(abs(dx), abs(dy)) <= 1 ? 1.0 : 0.0;
                sum += vec2(inner * v, v);
                n += vec2(inner, 1.0);
            }
            const float d = (dx & 1) == 0 && (dy & 1) == 0 ? reflected_at(q).a : 0.0;
            if (d == 0.0)
                continue;
            known += 1;
            sunlit += d > 0.0 ? 1.0 : 0.0;
            if (abs(d) < 0.5 * kNoOccluder) {
                inverse += 1.0 / abs(d);
                hits += 1;
            }
        }
    Window w = Window(own_known ? sum / n : vec2(-1.0), 0.0); // The centre always counts.
    if (known == 0.0)
        return w;
    const float pixel = nd.w / ray_scale(vec2(p) + 0.5) * 2.0 * pc.camera.x / float(size.y);
    w.footprint = sunlit > 0.0 && sunlit < known ? kSunEdge
                  : hits == 0.0                 ? kNoOccluder
                                                : min(hits / inverse / pixel, kNoOccluder);
    return w;
}

// The previous frame's view-space point (right-handed, looking down -z) at its pixel `pixel`
// (continuous, centres at +0.5) and view depth `depth`: the pinhole of reprojection_matrix().
vec3 history_view_point(vec2 pixel, float depth) {
    const vec2 ndc = pixel / vec2(pc.params.xy) * 2.0 - 1.0;
    return depth * vec3(ndc.x * pc.camera.x * pc.camera.y, -ndc.y * pc.camera.x, -1.0);
}

// World vector v in the previous frame's view space (pc.history_rotation).
vec3 to_history_view(vec3 v) {
    const vec3 q = pc.history_rotation.xyz;
    return v + 2.0 * cross(q, cross(q, v) + pc.history_rotation.w * v);
}

// Whether the history pixel q (its normal_depth hnd) shows the plane of this pixel's surface:
// the same normal and the history's point within a tenth of a block (plus what half-float
// distances lose, 1e-3 of the distance) of the plane through this pixel's point (`point`: in the
// previous view space, `normal`: there too). Voxel faces lie on planes a whole cell apart, so a
// step's lower or upper face (same normal, a distance a few percent off) is another surface,
// which a tolerance on the distance alone let in at any range over ~50 blocks: terrain history
// mixed the lit top of a step into the dark corner below it (docs/render_report.md, 2026-12-02).
bool history_on_plane(vec4 nd, vec4 hnd, ivec2 q, vec3 point, vec3 normal) {
    if (!has_surface(hnd) || dot(nd.xyz, hnd.xyz) <= 0.9)
        return false;
    const vec2 centre = vec2(q) + 0.5;
    const vec3 seen = history_view_point(centre, hnd.w / ray_scale(centre));
    return abs(dot(normal, seen - point)) <= 0.1 + 1e-3 * hnd.w;
}

// Whether the history pixel q may be a tap of this pixel (nd): with prev_depth > 0 (the
// illumination), on the pixel's plane (history_on_plane at the view depth prev_depth, `point` and
// `normal` there) and, when `sun` >= 0 (a moving camera: the taps are resampled), on the same side
// of a sun shadow's edge: its sun flag (u_moments a, from render/gbuffer.h's reflected a < 0:
// every sun ray blocked) equals `sun` (1: blocked). A lit and a shadowed pixel see different
// light, which the taps' bilinear weights smeared across the edge: pixel-sized shadowed faces on
// terrain took their lit neighbours' history (H200 1080p, 1 spp orbit median RMSE 0.0314 ->
// 0.0168, docs/render_report.md, 2026-12-02). A still camera's tap is the pixel itself, whose flag flips
// on noise in a penumbra (all of a few rays blocked by chance): there the test cost 16% of an
// 8-frame accumulation (tests/render/denoise_render_test.cpp), and the history clamp catches a
// real change. With prev_depth 0 (a mirror's virtual image), the normal alone.
bool tap_matches(ivec2 q, vec4 nd, float prev_depth, vec3 point, vec3 normal, int sun) {
    const vec4 hnd = imageLoad(u_hist_nd_in, q);
    if (prev_depth <= 0.0)
        return has_surface(hnd) && dot(nd.xyz, hnd.xyz) > 0.9;
    const bool sun_matches = sun < 0 || int(imageLoad(u_moments_in, q).w > 0.5) == sun;
    return sun_matches && history_on_plane(nd, hnd, q, point, normal);
}

// SVGF's bilinear tap of the history: the four previous pixels around `prev_pixel` (continuous,
// pixel centres at +0.5), each weighted by its bilinear weight if it shows a surface with nd's
// normal and, when prev_depth > 0, on the plane through the point at that view depth and with
// the sun flag `sun` (tap_matches). A nearest tap snaps by up to half a pixel every frame; on a
// moving camera the snaps compound into a smear of the history (fly-over, docs/render_report.md).
// w: normalised weights (all 0: no history); nearest: the matching tap of largest weight (the
// clamp's window).
Taps history_taps(vec2 prev_pixel, ivec2 size, vec4 nd, float prev_depth, int sun) {
    const vec2 f = prev_pixel - 0.5;
    Taps taps = Taps(ivec2(floor(f)), vec4(0), ivec2(-1));
    const vec2 t = f - vec2(taps.base);
    const vec3 point = history_view_point(prev_pixel, prev_depth), normal = to_history_view(nd.xyz);
    float best = 0;
    for (int i = 0; i < 4; ++i) {
        const ivec2 o = ivec2(i & 1, i >> 1);
        const ivec2 q = taps.base + o;
        const float w = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
        if (w <= 0.0 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
            continue;
        if (!tap_matches(q, nd, prev_depth, point, normal, sun))
            continue;
        taps.w[i] = w;
        if (w > best) {
            best = w;
            taps.nearest = q;
        }
    }
    const float sum = taps.w.x + taps.w.y + taps.w.z + taps.w.w;
    if (sum < 1e-3)
        return Taps(taps.base, vec4(0), ivec2(-1));
    taps.w /= sum;
    return taps;
}

// The reflected part's history clamped to the box (per channel min and max) of this frame's
// reflected values in the 3x3 neighbourhood on the same surface (Karis, "High Quality Temporal
// Supersampling", SIGGRAPH 2014): reflections move over a mirror that stays put, so history that
// matched the mirror can hold what the mirror showed before.
vec3 clamp_to_neighbourhood(vec3 history, ivec2 p, ivec2 size, vec4 nd) {
    vec3 lo = vec3(1e30), hi = vec3(-1e30);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            if (!same_surface(nd, imageLoad(u_normal_depth, q)))
                continue;
            const vec3 r = reflected_at(q).rgb;
            lo = min(lo, r);
            hi = max(hi, r);
        }
    return clamp(history, lo, hi); // The centre always counts: lo <= hi.
}

// How far this frame's illumination has moved from the history, pooled over the neighbourhood
// on the same surface (the history read around the reprojected pixel `q`): one frame's evidence
// that the light changed, pooled as A-SVGF pools its temporal gradients (Schied et al. 2018), so
// a change of a few noise deviations shows within a frame. The largest of the 3x3 window's and
// its four halves' gaps in standard errors: a pixel at the edge of a new shadow has a half on its
// side. One frame's variance is the larger of `now` (the pixel's) and the spread of this frame's
// values in the window or half (noise, detail and the jittered footprint alike: conservative);
// the history's is `before` over its `frames` frames.
float pooled_gap(ivec2 p, ivec2 q, ivec2 size, vec4 nd, float now, float before, float frames) {
    // A surface seen at a slant changes distance fast from pixel to pixel: neighbours count when
    // they continue the pixel's plane (distance within 5% plus 0.75 of the local gradient).
    const float gx = abs(imageLoad(u_normal_depth, min(p + ivec2(1, 0), size - 1)).w -
                         imageLoad(u_normal_depth, max(p - ivec2(1, 0), ivec2(0))).w);
    const float gy = abs(imageLoad(u_normal_depth, min(p + ivec2(0, 1), size - 1)).w -
                         imageLoad(u_normal_depth, max(p - ivec2(0, 1), ivec2(0))).w);
    const float tolerance = 0.05 * nd.w + 0.75 * max(gx, gy);
    // Sums of (current - history), current, current^2 and counts: the whole window, then left,
    // right, top, bottom.
    float diff[5] = float[](0, 0, 0, 0, 0), m1[5] = float[](0, 0, 0, 0, 0), m2[5] = float[](0, 0, 0, 0, 0);
    float n[5] = float[](0, 0, 0, 0, 0);
    float level = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 pp = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            const ivec2 qc = clamp(q + ivec2(dx, dy), ivec2(0), size - 1);
            const vec4 np = imageLoad(u_normal_depth, pp), nq = imageLoad(u_hist_nd_in, qc);
            if (!has_surface(np) || dot(np.xyz, nd.xyz) < 0.9 || abs(np.w - nd.w) > tolerance ||
                !has_surface(nq) || dot(nq.xyz, nd.xyz) < 0.9)
                continue;
            const float h = luminance(imageLoad(u_hist_in, qc).rgb);
            const float c = luminance(illumination(pp));
            level = max(level, h);
            const bool in_half[5] = bool[](true, dx <= 0, dx >= 0, dy <= 0, dy >= 0);
            for (int i = 0; i < 5; ++i)
                if (in_half[i]) {
                    diff[i] += c - h;
                    m1[i] += c;
                    m2[i] += c * c;
                    n[i] += 1;
                }
        }
    // The floor keeps noise-free input (variance 0) from resetting on half-float rounding.
    const float floor_ = 2e-3 * level + 1e-4;
    float z = 0;
    for (int i = 0; i < 5; ++i) { // The centre always counts (it matched): n[i] >= 1.
        if (i > 0 && n[i] < 4.0)
            continue;
        const float spread = max(m2[i] / n[i] - (m1[i] / n[i]) * (m1[i] / n[i]), 0.0);
        const float variance = max(now, spread) + before / frames;
        z = max(z, abs(diff[i] / n[i]) / (sqrt(variance / n[i]) + floor_));
    }
    return z;
}

// The most frames a moving pixel of several samples may average: the weight that minimises the
// blend's expected squared error when the history, `frames` frames of variance `own` each, is
// off by up to `bias` (in luminance) and this frame is unbiased with variance `own`: history
// weight own / (own + bias^2 + own / frames), i.e. frames (own + bias^2 + h) / (bias^2 + h) with
// h = own / frames. Bilinear resampling is off by at most f (1 - f) times the taps' range (a
// linear ramp through them: none). With a tap off the surface the renormalised taps extrapolate
// and their range bounds nothing; the gap between the history and this frame's value does, from
// above (its square's mean is the bias's plus both noises'): no history at all there had cost
// more (H200 1080p, moving p95 at 8 / 1 spp 0.0102 -> 0.0095, 4 spp 0.0134 -> 0.0118,
// docs/render_report.md, 2026-12-02). No tap (bias < 0): no history. own is the pixels' own
// variance without the stratification discount (over kStratifiedVarianceScale: an upper bound).
// Reprojected history of a moving camera had cost more than it gave (H200 terrain 1080p, 25 spp
// and 2 frames: 0.0167 RMSE against raw 0.0077; with this cap 0.0075; docs/render_report.md,
// 2026-12-02).
float moving_history_cap(float own, float frames, float bias) {
    if (bias < 0.0)
        return 1.0;
    const float variance = own / kStratifiedVarianceScale, h = variance / max(frames, 1.0);
    return max((variance + bias * bias + h) / max(bias * bias + h, 1e-20), 1.0);
}

// One pass per pixel (over 100 lines): the history's reprojection, its 2x2 taps' weights and the
// moments flow into the three outputs (illumination, reflected light, mirror light), which share
// them; apart, each step would take or return most of that state.
void main() {
    const ivec2 size = ivec2(pc.params.xy);
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size)))
        return;
    const vec4 nd = imageLoad(u_normal_depth, p);
    if (keep_history())
        imageStore(u_hist_nd_out, p, nd);
    if (!has_surface(nd)) { // Sky: nothing to filter or accumulate.
        if (keep_history()) {
            imageStore(u_hist_out, p, vec4(color_at(p).rgb, 0));
            imageStore(u_moments_out, p, vec4(0));
            imageStore(u_hist_refl_out, p, vec4(0));
            imageStore(u_hist_mirror_out, p, vec4(0));
        }
        imageStore(u_refl_out, p, vec4(0));
        imageStore(u_filter_out, p, vec4(color_at(p).rgb, 0));
        imageStore(u_mirror_filter_out, p, vec4(0));
        if ((pc.params.w & kDenoiseLastPass) != 0)
            store_result(p, color_at(p).rgb, vec3(1), false, vec3(0));
        return;
    }
    const vec3 illum = illumination(p);
    const bool sun_blocked_here = reflected_at(p).a < 0.0; // render/gbuffer.h.
    float frames = 0;
    vec3 history = vec3(0), history_reflected = vec3(0);
    vec4 moments = vec4(0);
    float reflected_frames = 0;
    ivec2 history_pixel = ivec2(-1);
    Taps mirror_taps = Taps(ivec2(0), vec4(0), ivec2(-1));
    bool moved = false;
    // The taps' luminance range and count, and the resample's largest f (1 - f): its bias bound.
    float tap_lo = 1e30, tap_hi = -1e30, tap_f = 0.0;
    int tap_count = 0;
    if ((pc.params.w & kDenoiseHistoryValid) != 0) {
        const vec2 centre = vec2(p) + 0.5;
        const float depth = nd.w / ray_scale(centre);
        const vec4 prev = pc.reproject * vec4(centre * depth, depth, 1);
        Taps taps = Taps(ivec2(0), vec4(0), ivec2(-1));
        if (prev.z > 0) {
            moved = any(greaterThan(abs(prev.xy / prev.z - centre), vec2(0.01))); // Pixels.
            taps = history_taps(prev.xy / prev.z, size, nd, prev.z, moved ? int(sun_blocked_here) : -1);
            const vec2 fr = fract(prev.xy / prev.z - 0.5);
            tap_f = max(fr.x * (1.0 - fr.x), fr.y * (1.0 - fr.y));
        }
        Taps reflected_taps = taps;
        // What a flat mirror shows moves as its virtual image does: the point at the path's
        // length along the primary ray (behind the mirror), not the mirror's surface. Its
        // history is where the previous camera saw that point on a surface of the mirror's
        // orientation.
        const vec4 mnd = mirror_inputs() ? imageLoad(u_mirror_nd, p) : vec4(0);
        if (has_surface(mnd)) {
            const float virtual_depth = mnd.w / ray_scale(centre);
            const vec4 prev_virtual = pc.reproject * vec4(centre * virtual_depth, virtual_depth, 1);
            reflected_taps = Taps(ivec2(0), vec4(0), ivec2(-1));
            if (prev_virtual.z > 0)
                reflected_taps = history_taps(prev_virtual.xy / prev_virtual.z, size, nd, 0.0, -1);
            mirror_taps = reflected_taps;
        }
        history_pixel = taps.nearest;
        for (int i = 0; i < 4; ++i) {
            if (taps.w[i] > 0.0) {
                const vec4 h = imageLoad(u_hist_in, tap_pixel(taps, i));
                const float tap_lum = luminance(h.rgb);
                tap_lo = min(tap_lo, tap_lum);
                tap_hi = max(tap_hi, tap_lum);
                ++tap_count;
                history += taps.w[i] * h.rgb;
                frames += taps.w[i] * h.a;
                moments += taps.w[i] * imageLoad(u_moments_in, tap_pixel(taps, i));
            }
            if (reflected_taps.w[i] > 0.0) {
                const vec4 hr = imageLoad(u_hist_refl_in, tap_pixel(reflected_taps, i));
                history_reflected += reflected_taps.w[i] * hr.rgb;
                reflected_frames += reflected_taps.w[i] * hr.a;
            }
        }
    }
    // Near an edit (render/edit_marks.h; the ray generation marks the hit's albedo a) the light
    // may have changed under a history that still matches in normal and depth (the contact
    // shadow beside a placed block), too little for the clamp's test, so it would fade over the
    // whole history: start again here, as after a disocclusion. A mirror whose reflected surface
    // is near one starts its reflected part and mirror light again.
    const bool edited_here = edited(imageLoad(u_albedo, p));
    if (edited_here) {
        frames = 0;
        history = vec3(0);
        moments = vec4(0);
    }
    if (edited_here || (mirror_inputs() && edited(imageLoad(u_mirror_albedo, p)))) {
        reflected_frames = 0;
        history_reflected = vec3(0);
        mirror_taps = Taps(ivec2(0), vec4(0), ivec2(-1));
    }
    const Window window = window_stats(p, size, nd);
    const vec2 owns = window.variance;
    const float own = owns.x;
    // While the camera moves, a pixel of several samples (its own variance known) weighs its
    // history by what resampling it costs (moving_history_cap); one sample keeps it: there the
    // filter alone loses (1 spp 0.0188 -> 0.0230 on the issue 18 scene, docs/render_report.md).
    float max_frames = max(pc.sigmas.w, 1.0);
    const float lum = luminance(illum);
    if (moved && own >= 0.0) {
        const float gap = abs(luminance(history) - lum);
        const float bias = tap_count == 4 ? (tap_hi - tap_lo) * tap_f : tap_count > 0 ? gap : -1.0;
        max_frames = min(max_frames, moving_history_cap(own, frames, bias));
    }
    // One frame's luminance variance for the clamp: now, the pixels' own from this frame's light
    // samples (pooled_gap also takes the window's spread); in the history, its temporal variance
    // (SVGF's moments, from 2 frames on), else the pixels' own. Unknown (1 sample): the
    // temporal one, or no clamp before 2 frames.
    const float temporal_variance = frames >= 2.0 ? max(moments.y - moments.x * moments.x, 0.0) : -1.0;
    const float variance_before = temporal_variance >= 0.0 ? temporal_variance : own;
    const float variance_now = own >= 0.0 ? own : temporal_variance;
    const float pooled = (pc.params.w & kDenoiseHistoryClamp) != 0 && frames > 0.0 && variance_now >= 0.0
                             ? pooled_gap(p, history_pixel, size, nd, variance_now, variance_before, frames)
                             : 0.0;
    if (pooled > 4.5) { // Stale: start again from this frame, as after a disocclusion.
        frames = 0;
        history = vec3(0); // mix(history, x, 1) is x only while history is finite.
        moments = vec4(0);
    }
    const vec3 accumulated = mix(history, illum, 1.0 / min(frames + 1, max_frames));
    if ((pc.params.w & kDenoiseHistoryClamp) != 0 && reflected_frames > 0.0)
        history_reflected = clamp_to_neighbourhood(history_reflected, p, size, nd);
    // While the camera moves, the reflected part and the mirror light average at most 2 frames:
    // their taps follow the virtual image but nothing tests that they saw the same reflected
    // surface (its guides are not kept), so a longer history blurs what the mirror shows. Issue
    // 18 scene, 4 spp: fly-over 0.0130 -> 0.0107 RMSE, orbit 0.0137 -> 0.0121 (4 frames: 0.0114,
    // 0.0130; 1 frame costs the 1-spp rows 12%). A still camera keeps max_frames.
    const float moving_frames = moved ? min(max_frames, 2.0) : max_frames;
    reflected_frames = min(reflected_frames + 1, moving_frames);
    const vec3 reflected = mix(history_reflected, reflected_at(p).rgb, 1.0 / reflected_frames);
    frames = min(frames + 1, max_frames);
    moments.xyz = mix(moments.xyz, vec3(lum, lum * lum, owns.y), 1.0 / frames);
    // Variance of one frame's estimate: the pixels' own from their light samples
    // (render/gbuffer.h; the sample counts are the same in every frame of the history, so it is
    // averaged over it); unknown (1 sample): from the temporal moments once 4 frames are in
    // (SVGF), else from the 3x3 neighbourhood (which also counts pixel-sized detail as noise).
    float sample_variance = moments.z;
    if (own < 0.0)
        sample_variance = frames >= 4.0 ? max(moments.y - moments.x * moments.x, 0.0)
                                        : spatial_variance(p, size, nd);
    if (keep_history()) {
        imageStore(u_hist_out, p, vec4(accumulated, frames));
        imageStore(u_moments_out, p, vec4(moments.xyz, sun_blocked_here ? 1.0 : 0.0));
        imageStore(u_hist_refl_out, p, vec4(reflected, reflected_frames));
    }
    imageStore(u_refl_out, p, vec4(reflected, window.footprint));
    imageStore(u_filter_out, p, vec4(accumulated, with_sun_flag(sample_variance / frames, sun_blocked_here)));
    const vec3 mirror = accumulate_mirror(p, size, mirror_taps, moving_frames);
    if ((pc.params.w & kDenoiseLastPass) != 0) // No a-trous pass follows.
        store_result(p, accumulated, imageLoad(u_albedo, p).rgb, true, reflected + mirror);
}
