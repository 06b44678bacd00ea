// The temporal pass's first-mirror-bounce light (included by denoise_temporal.comp after its
// image bindings, Taps and mirror_at()): filtered in the reflected surface's own terms, its
// history matched by the reflected surface, clamped to the 3x3 neighbourhood on that surface.

// Whether q's mirror surface continues p's: the same normal and a path length within 1% plus 0.3
// blocks. In a field of small mirrors, neighbours' reflected rays end on different blocks a block
// or so apart, which 5% of the path let in (their light differs: detail, not noise).
bool same_mirror_surface(vec4 mnd, ivec2 q) {
    const vec4 o = imageLoad(u_mirror_nd, q);
    return has_surface(o) && dot(o.xyz, mnd.xyz) >= 0.9 && abs(o.w - mnd.w) <= 0.01 * mnd.w + 0.3;
}

// The cap on the mirror light's variance: kMirrorOwnCap times the pixels' own (discounted)
// variance. Against plain-mean references (docs/render_report.md, stop 20; the mirror room of
// tests/render/denoise_render_test.cpp at 4 spp, the mirror field of convergence_test.cpp at 4 /
// 16 spp): 16 (no discount) 0.0212 / 0.0317 / 0.0154, 8 0.0217 / 0.0289 / 0.0132 with the
// tighter surface test, 4 0.0231 / 0.0277 / 0.0127, 1 0.0284 / 0.0269 / 0.0126; raw 16 spp 0.0123.
const float kMirrorOwnCap = 8.0;

// Variance of one frame's mirror light at p: the spread of the values over the 3x3 neighbourhood
// on the same reflected surface (the light is over the reflected surface's albedo, so the spread
// is noise or light detail), at most kMirrorOwnCap times the pixels' own there, so detail is not
// taken for noise once samples are many. The pixels' own alone left a flat mirror noisy (the room:
// 0.0284 against 0.0212); the spread alone blurs a field of small mirrors.
float mirror_variance(ivec2 p, ivec2 size, vec4 mnd) {
    float m1 = 0, m2 = 0, n = 0, own = 0, n_own = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            if (!same_mirror_surface(mnd, q))
                continue;
            const vec4 m = mirror_at(q);
            const float l = luminance(m.rgb);
            m1 += l;
            m2 += l * l;
            n += 1;
            if (m.a >= 0.0) {
                own += m.a;
                n_own += 1;
            }
        }
    m1 /= n; // The centre always counts.
    const float spread = max(m2 / n - m1 * m1, 0.0);
    return n_own > 0.0 ? min(spread, kMirrorOwnCap * own / n_own) : spread;
}

// The mirror light's history clamped to this frame's box on the same reflected surface.
vec3 clamp_mirror(vec3 history, ivec2 p, ivec2 size, vec4 mnd) {
    vec3 lo = vec3(1e30), hi = vec3(-1e30);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            if (!same_mirror_surface(mnd, q))
                continue;
            const vec3 m = mirror_at(q).rgb;
            lo = min(lo, m);
            hi = max(hi, m);
        }
    return clamp(history, lo, hi);
}

// Accumulates the mirror light into its history (read at `taps`: its virtual image's) and writes
// it with its variance for the a-trous passes; returns it remodulated.
vec3 accumulate_mirror(ivec2 p, ivec2 size, Taps taps, float max_frames) {
    // No mirror input this frame: the history is still written (no frames), so a later frame
    // with mirror inputs never reads an unwritten one.
    const vec4 mnd = mirror_inputs() ? imageLoad(u_mirror_nd, p) : vec4(0);
    if (!has_surface(mnd)) {
        if (keep_history())
            imageStore(u_hist_mirror_out, p, vec4(0));
        imageStore(u_mirror_filter_out, p, vec4(0));
        return vec3(0);
    }
    vec3 history = vec3(0);
    float frames = 0;
    float weight = 0; // Over the taps that had a mirror (frames > 0).
    for (int i = 0; i < 4; ++i)
        if (taps.w[i] > 0.0) {
            const vec4 h = imageLoad(u_hist_mirror_in, tap_pixel(taps, i));
            const float w = h.a > 0.0 ? taps.w[i] : 0.0;
            history += w * h.rgb;
            frames += w * h.a;
            weight += w;
        }
    if (weight > 1e-3) {
        history /= weight;
        frames /= weight;
    }
    if ((pc.params.w & kDenoiseHistoryClamp) != 0 && frames > 0.0)
        history = clamp_mirror(history, p, size, mnd);
    frames = min(frames + 1, max_frames);
    const vec3 accumulated = mix(history, mirror_at(p).rgb, 1.0 / frames);
    if (keep_history())
        imageStore(u_hist_mirror_out, p, vec4(accumulated, frames));
    imageStore(u_mirror_filter_out, p, vec4(accumulated, mirror_variance(p, size, mnd) / frames));
    return accumulated * imageLoad(u_mirror_albedo, p).rgb;
}
