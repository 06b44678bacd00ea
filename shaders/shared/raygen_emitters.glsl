// The raygen shader's emissive blocks (included by raygen.rgen after its light samplers, whose
// globals and trace_shadow() these use): which emitter chunks are near a point, the draw of one
// face among kEmitterCandidates by resampled importance (draw_candidates(), for finite_light()'s
// next-event estimation), and the sky term's cosine-weighted rays that also find the emitters not
// sampled (sky_and_emitters()).

// Whether `pos` lies in emitter chunk i's box (emitter_chunks[i]) widened by `reach` of its cells.
bool near_chunk(uint i, vec3 pos, float reach) {
    vec4 chunk = EmitterChunks(frame.emitter_chunks).origin[i]; // xyz: origin; w: edge, blocks.
    float range = reach * (chunk.w / kChunkCells);
    return all(greaterThanEqual(pos, chunk.xyz - range)) && all(lessThanEqual(pos, chunk.xyz + (chunk.w + range)));
}

// Whether `pos` lies within kEmitterRange cells of one of the emissive chunks near the camera
// (the CPU's list, nearest first) numbered first..end-1: only there can an emitter matter. A
// level-k chunk's cells are 2^k blocks, and so is its reach: a cell's light falls off with
// (distance / cell size)^2. The first flags.w chunks' faces are sampled (finite_light()), the
// rest are found by sky rays.
bool near_emitter(vec3 pos, uint first, uint end) {
    for (uint i = first; i < end; ++i)
        if (near_chunk(i, pos, kEmitterRange))
            return true;
    return false;
}

// The last sky_and_emitters() call's rays: how many were traced, how many hit a block and the
// sum of 1 / distance over those. A block a sky ray hits t blocks away darkens the sky term over
// about t blocks around the point (an inner corner's darkening is a block wide, the shade under
// an overhang 7 blocks up many): the primary hit's harmonic mean distance is the denoiser's
// guide to the scale of the light (render/gbuffer.h reflected a; ReBLUR and SIGMA, NVIDIA RTX
// Denoisers, steer their blur by hit and occluder distances the same way).
uint g_sky_rays = 0u, g_hits = 0u;
float g_inverse_hit_sum = 0.0;
const float kMinOccluderDistance = 0.25; // Blocks: a ray leaving a face may touch the next at ~0.

// A sky ray that hit a block t blocks away, counted in the guide.
void count_occluder(float t) {
    g_inverse_hit_sum += 1.0 / max(t, kMinOccluderDistance);
    ++g_hits;
}

// The emission a sky ray adds on hitting `block` at `hit` (its face `face`): none from a block
// in one of the first `sampled` emitter chunks, whose faces finite_light() sampled at this point.
vec3 found_emission(uint block, vec3 hit, uint face, uint sampled) {
    vec3 e = vx_material(block).emission.xyz;
    if (sampled == 0u || e == vec3(0.0))
        return e;
    vec3 inside = hit - 0.5 * face_normal(face); // Half a block into the block hit: not on a box's side.
    for (uint i = 0u; i < sampled; ++i)
        if (near_chunk(i, inside, 0.0))
            return vec3(0.0);
    return e;
}

// A cheap estimate of face q's light at `pos` (normal n), resampling's target: 0 only where the
// face cannot light the point (wholly behind its plane, or the point behind the face's), so every
// face that can is chosen with some probability and the estimate stays unbiased. Else the light
// from its centre, both cosines at least 0.05 (part of a face can be in front of a plane its
// centre is behind), the distance at least the face's size.
float emitter_target(EmitterQuad q, vec3 pos, vec3 n) {
    vec3 eu = q.edge_u.xyz, ev = q.edge_v.xyz, c0 = q.corner.xyz - pos;
    vec3 nq = cross(eu, ev) / q.corner.w; // Outward, unit.
    float front = max(max(dot(n, c0), dot(n, c0 + eu)), max(dot(n, c0 + ev), dot(n, c0 + eu + ev)));
    if (front <= 0.0 || dot(nq, c0) >= 0.0)
        return 0.0;
    vec3 c = c0 + 0.5 * (eu + ev);
    float d2 = dot(c, c), inv = inversesqrt(d2);
    float cos_s = max(dot(n, c) * inv, 0.05), cos_l = max(-dot(nq, c) * inv, 0.05);
    return q.emission.w * q.corner.w * cos_s * cos_l / max(d2, q.corner.w);
}

// Next-event estimation of the emissive faces of the nearest emissive chunks
// (FrameParams::emitter_quads, render/emitter_quads.h). A draw of candidates takes one face from
// each of kEmitterCandidates equal runs of the list (every face if there are no more); its
// weights' sum estimates the faces' unshadowed light (luminance of irradiance). Each sample draws
// its own and keeps one candidate with probability in proportion to emitter_target() over its
// run's pdf (resampled importance sampling, Talbot et al., EGSR 2005, the first step of ReSTIR
// DI, Bitterli et al., SIGGRAPH 2020; the runs are disjoint, so each face has one candidate that
// can draw it and its MIS weight is 1: Lin et al., "Generalized Resampled Importance Sampling",
// SIGGRAPH 2022), takes a point on it (the sample's stratified pair) and traces a shadow ray.
// The runs keep the nearest chunk's faces (the list's first) among the candidates every time.

// A hash's top 24 bits as a float in [0, 1) (as shared/sampling.h's points).
float unit_float(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }

// One draw from random numbers `rng` on: returns its weights' sum; `chosen` and its target: one
// candidate kept with probability in proportion to its weight (a weighted reservoir of one, so
// no candidate list is held).
float draw_candidates(vec3 pos, vec3 n, uint rng, out uint chosen, out float chosen_target) {
    EmitterQuads faces = EmitterQuads(frame.emitter_quads);
    uint count = frame.flags.z, candidates = min(kEmitterCandidates, count);
    float total = 0.0;
    chosen = 0u;
    chosen_target = 0.0;
    for (uint j = 0u; j < candidates; ++j) {
        uint lo = j * count / candidates, run = (j + 1u) * count / candidates - lo; // run >= 1.
        rng = vx_hash(rng);
        uint i = lo + min(uint(unit_float(rng) * float(run)), run - 1u);
        float target = emitter_target(faces.q[i], pos, n);
        float w = target * float(run); // Over the run's pdf, 1 / run.
        total += w;
        rng = vx_hash(rng);
        if (w > 0.0 && unit_float(rng) * total < w) {
            chosen = i;
            chosen_target = target;
        }
    }
    return total;
}

const uint kEmitterReachChunks = 8u; // emitter_reach()'s.

// Whether the faces are worth sampling at `pos` (normal n): a bound on their unshadowed light
// there (luminance of irradiance; a bound a block or more from them), deterministic (the choice
// made on it then favours no draw of samples: both ways stay unbiased). Per emitter chunk within
// reach (near_emitter()'s rule) whose faces' box is not wholly behind the point's face plane:
// their power over the squared distance to that box, at least a block. 0: none within reach.
// Only the kEmitterReachChunks nearest the camera are weighed (a lamp in a farther one is left
// to the sky rays: slower to converge, not lost).
float emitter_reach(vec3 pos, vec3 n, uint samples) {
    if (frame.flags.z == 0u || samples == 0u)
        return 0.0;
    EmitterBounds bounds = EmitterBounds(frame.emitter_bounds);
    float light = 0.0;
    for (uint i = 0u; i < min(frame.flags.w, kEmitterReachChunks); ++i) {
        if (!near_chunk(i, pos, kEmitterRange))
            continue;
        EmitterBound b = bounds.b[i];
        // The box's farthest point along n in front of the face plane, or skip.
        vec3 ahead = mix(b.lo.xyz, b.hi.xyz, greaterThan(n, vec3(0.0)));
        if (dot(n, ahead - pos) <= 0.0)
            continue;
        vec3 d = max(max(b.lo.xyz - pos, pos - b.hi.xyz), vec3(0.0));
        light += b.lo.w / max(dot(d, d), 1.0);
    }
    return light;
}

// A draw of candidates' estimate of the faces' light at `pos` (normal n), from random numbers of
// its own (independent of the samples that follow, so a choice made on it favours none of them).
float emitter_estimate(vec3 pos, vec3 n, uint seed) {
    uint unused_face;
    float unused_target;
    return draw_candidates(pos, n, vx_hash(seed ^ vx_hash(g_pixel.x + vx_hash(g_pixel.y ^ 0x68bc21ebu))), unused_face,
                           unused_target);
}

// Under water (index > 1) the sky comes in through Snell's window alone, the cone of half-angle
// asin(1 / index) about +y under a level surface, where cosine-weighted rays about a wall's normal
// seldom go. So a share kWindowShare of the sky rays there is drawn in that cone by the cosine to
// +y (a level floor's light in it goes nearly as that cosine), the rest by the cosine to the
// normal, combined by one-sample MIS with the balance heuristic (Veach 1997, 9.2.4): each ray
// weighs p_cos / p_mix. The cosine part covers the whole hemisphere, so any other way out (a wall
// of water against air) is still found: unbiased. With 4 rays the stratified pairs split 2 : 2.
// Lavapipe, one frame at 4 rays (SkyRaysUnderWaterFindSnellsWindowInOneFrame): RMS relative error
// 1.16 -> 0.80 on a wall, 0.23 -> 0.18 on the floor (a share of 0.75: 0.54, 0.21).
const float kWindowShare = 0.5;

// The direction of cosine-weighted sample (u, phi) about n (t, b: n's tangents): sin^2 of its
// angle to n is u, phi its azimuth.
vec3 cosine_dir(float u, float phi, vec3 n, vec3 t, vec3 b) {
    return normalize((cos(phi) * t + sin(phi) * b) * sqrt(u) + n * sqrt(max(1.0 - u, 0.0)));
}

// A sky ray's direction under water (index > 1) from the stratified pair uv, and its weight
// p_cos / p_mix (0: below the horizon of n, not traced).
vec3 window_or_cosine(vec2 uv, vec3 n, vec3 t, vec3 b, float index, out float weight) {
    float phi = 2.0 * kPi * uv.y, sin2_window = 1.0 / (index * index);
    vec3 d;
    if (uv.x < kWindowShare) {
        float s2 = (uv.x / kWindowShare) * sin2_window, s = sqrt(s2);
        d = vec3(s * cos(phi), sqrt(1.0 - s2), s * sin(phi));
    } else {
        d = cosine_dir((uv.x - kWindowShare) / (1.0 - kWindowShare), phi, n, t, b);
    }
    float p_cos = max(dot(n, d), 0.0) / kPi;
    float p_win = d.y * d.y >= 1.0 - sin2_window && d.y > 0.0 ? d.y / (kPi * sin2_window) : 0.0;
    weight = p_cos == 0.0 ? 0.0 : p_cos / ((1.0 - kWindowShare) * p_cos + kWindowShare * p_win);
    return d;
}

// Mean radiance arriving at `pos` over cosine-weighted directions around n: the sky where a ray
// escapes, an emissive block's emission where it hits one (tinted by transparent blocks on the
// way). A diffuse surface reflects albedo times this (the cosine pdf cancels the 1/pi).
// `occluders`: the rays' hit distances are wanted (the primary hit's: the denoiser's guide).
// Where neither they nor an emitter chunk within reach are, a ray only asks whether the sky is in
// sight: an occlusion ray (trace_shadow()), which stops at the first opaque face it finds instead
// of searching on for the nearest; where only the distances are, it stops there too and tells
// that face's distance (the walk follows where that face is see-through). The image is the same,
// but where a ray crosses more than kMaxTransparentLayers transparent blocks: they tint it as
// they tint the sun's rays, all of them.
// Under water the directions come from window_or_cosine(), weighted to the same mean.
vec3 sky_and_emitters(vec3 pos, vec3 n, uint samples, uint seed, bool faces_sampled, bool occluders) {
    bool sky = frame.flags.x != 0u && dot(frame.sky_light.xyz, vec3(1.0)) > 0.0;
    uint first = faces_sampled ? frame.flags.w : 0u; // The emitter chunks sky rays look for.
    bool emitters = frame.flags.y > first && near_emitter(pos, first, frame.flags.y);
    g_m1 = g_m2 = 0.0;
    g_sky_rays = g_hits = 0u;
    g_inverse_hit_sum = 0.0;
    if (!sky && !emitters)
        return vec3(0.0);
    if (samples == 0u) // Shadows off: the unoccluded sky.
        return sky ? frame.sky_light.xyz : vec3(0.0);
    vec3 t, b;
    basis(n, t, b);
    vec3 sum = vec3(0.0);
    g_sky_rays = samples;
    // From inside a block that bends light the rays bend where they leave it: the sky comes in
    // through Snell's window alone (48.8 degrees about a water surface's normal), n^2 brighter, and
    // a ray past the critical angle mirrors back inside (kWalkSky). A horizontal floor under flat
    // water takes the irradiance straight rays give it; a wall under water takes less. The rays
    // there sample the window too (window_or_cosine).
    float index = hit_index();
    bool bends = index != 1.0;
    for (uint s = 0u; s < samples; ++s) {
        vec2 uv = sample2(s, samples, seed);
        vec3 d;
        float weight = 1.0;
        if (bends) {
            d = window_or_cosine(uv, n, t, b, index, weight);
            if (weight == 0.0) {
                add_sample(vec3(0.0));
                continue;
            }
        } else {
            d = cosine_dir(uv.x, 2.0 * kPi * uv.y, n, t, b);
        }
        if (!emitters && !occluders && !bends) {
            vec3 x = trace_shadow(pos, d, kTMax, g_hit_inside) * frame.sky_light.xyz; // sky is on: else no rays.
            sum += x;
            add_sample(x);
            continue;
        }
        // The occluder guide wants a distance, not the nearest hit's: the ray stops at the first
        // face its traversal finds, as an occlusion ray does, and that face's distance counts (at
        // least the nearest's; the same error, 7% less frame time on issue 18's lavapipe view:
        // docs/render_report.md, stop 68). An opaque face there shuts the sky out whatever lies
        // nearer; a see-through one needs the walk. So a ray that meets no see-through face gets
        // the same light and distance in both pipeline variants (the see-through check's
        // premise), and a marking pass marks one that finds such a face.
        if (!emitters && !bends && g_hit_inside == 0u) {
            traceRayEXT(tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT, 0xFFu, 0u, 1u, kPrimaryMiss,
                        pos, 0.0, d, kTMax, kPrimaryPayload);
            bool walk = payload.t >= 0.0 && vx_transparent(vx_material(payload.block));
            if (walk && !kSeeThrough && g_check) // The check's marking pass: traced again.
                g_met = true;
            if (!walk || !kSeeThrough) {
                vec3 x = payload.t < 0.0 ? frame.sky_light.xyz : vec3(0.0);
                if (payload.t >= 0.0)
                    count_occluder(payload.t);
                sum += x;
                add_sample(x);
                continue;
            }
        }
        vec3 tint = trace_through(pos, d, g_hit_inside, bends ? kWalkSky : kWalkLight) * weight;
        if (payload.t >= 0.0)
            count_occluder(payload.t);
        vec3 x = payload.t < 0.0 ? (sky ? tint * frame.sky_light.xyz : vec3(0.0))
                                 : tint * found_emission(payload.block, payload.position, payload.face, first);
        sum += x;
        add_sample(x);
    }
    return sum / float(samples);
}
