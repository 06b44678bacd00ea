// The light cache, GLSL side (render/light_cache.h has the C++ side).
//
// Within one frame every opaque hit of a path (the primary hit and mirror bounces up to
// FrameParams cache.y) adds its estimate of the light that reaches it (per unit albedo: the area
// light and emitter faces' irradiance over pi plus the sky term; not the sun) to a cell of a hash
// table keyed by the surface it lies on: the face's plane and direction, and a square of that
// plane about cache.z pixels wide at the hit's distance from the camera (the ray generation
// records the cell's key; the gather pass, shaders/light_cache_gather.comp, adds the hits to
// their cells). The resolve pass (shaders/light_cache.comp) then moves each hit's own estimate
// towards its cell's mean (weighted by samples) as far as the cell's spread and noise say that
// lowers the error. Pixels that see the same patch of a face, directly or through any mirror, so
// share their shadow rays and sky rays: path space filtering (Keller et al., "Path Space
// Filtering", MCQMC 2014) with a hash of cells sized by distance (Binder, Fricke and Keller,
// "Fast Path Space Filtering by Jittered Spatial Hashing", SIGGRAPH 2018 talk; NVIDIA's SHaRC
// does the same across frames). Sizing by the camera distance, not the path's length, puts a
// point seen directly and in a mirror into the same cell. Their jittered lookups measured no
// better here than plain cells (docs/render_report.md), so cells are plain. The sun stays each
// hit's own: its shadows are sharp and its few rays are exact outside a penumbra, and a cell
// would blur its edges (which measured worse than no cache).
//
// The estimate is consistent (cells shrink with the pixels) but biased by the light's change
// across a cell, which the resolve's weights bound; docs/render_report.md measures it against
// the noise it removes.
//
// Needs GL_EXT_shader_atomic_float (shaderBufferFloat32AtomicAdd, render/device_probe.h) and
// GL_EXT_buffer_reference, sampling.h (vx_hash), tonemap.h (vx_luminance); include after the
// FrameParams block.

#extension GL_EXT_shader_atomic_float : require

layout(buffer_reference, std430, buffer_reference_align = 4) buffer CacheKeys { uint key[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer CacheValues { vec4 value[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer CacheStats { vec4 stat[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer CacheRecords { uvec4 record[]; };

bool cache_on() { return frame.cache.x != 0u; }

// The table's values: vec4(sum of light x samples, samples) per cell, after its keys.
CacheValues cache_values() { return CacheValues(frame.cache_table + uint64_t(frame.cache.x) * 4ul); }
// Then its spread and noise: vec4(sum of samples x luminance^2, sum of samples x v, sum of
// samples^2 x v, hits whose v is known) with v the variance of a hit's luminance (as a mean).
CacheStats cache_stats() { return CacheStats(frame.cache_table + uint64_t(frame.cache.x) * 20ul); }

// The light samples of a hit at `bounce` (0: the primary hit) as the frame sets them:
// size_samples.z at the primary hit, mode_seed.w at mirror bounces (before samples by weight,
// FrameParams sampling.x, which raygen.rgen applies per hit).
uint frame_samples(uint bounce) { return bounce == 0u ? frame.size_samples.z : frame.mode_seed.w; }

// Record `bounce` (0: the primary hit .. frame.cache.y) of pixel px: two uvec4 from this index.
uint cache_record_index(uvec2 px, uint bounce) {
    return ((px.y * frame.size_samples.x + px.x) * (frame.cache.y + 1u) + bounce) * 2u;
}

// The key of the cell of the hit at `pos` (origin-relative blocks) on the face with the
// axis-aligned unit normal n: its hash, below the records' markers kCacheOwn and kCacheNoSlot.
// The gather pass (shaders/light_cache_gather.comp) finds or claims its cell (cache_claim()).
uint cache_key(vec3 pos, vec3 n) {
    uint axis = n.x != 0.0 ? 0u : n.y != 0.0 ? 1u : 2u;
    uint face = axis * 2u + (n[axis] > 0.0 ? 1u : 0u);
    // cache.z pixels at the hit's distance (the pinhole's angle per pixel), rounded up to a power
    // of two blocks: 1/16 to 64.
    float pixel = 2.0 * frame.camera_origin.w / float(frame.size_samples.y);
    float width = max(distance(pos, frame.camera_origin.xyz) * pixel * uintBitsToFloat(frame.cache.z), 1e-6);
    int level = clamp(int(ceil(log2(width))), -4, 6);
    ivec3 cell = ivec3(floor(pos / exp2(float(level))));
    cell[axis] = int(round(pos[axis])); // The face's plane itself, never a neighbour's.
    uint h = vx_hash(uint(cell.x) ^ vx_hash(uint(cell.y) ^ vx_hash(uint(cell.z) ^ vx_hash(face | (uint(level + 8) << 3u)))));
    return min(h, kCacheOwn - 1u);
}

// The table index of the cell of key h, claimed if new, or kCacheOwn when kCacheProbes cells in
// a row belong to other keys. A key once set never changes, so a plain read that finds it (or
// another) is final; only an empty one needs the atomic claim.
uint cache_claim(uint h) {
    uint check = vx_hash(h ^ 0x9e3779b9u) | 1u; // Never 0: 0 marks an empty cell.
    uint mask = frame.cache.x - 1u;
    CacheKeys keys = CacheKeys(frame.cache_table);
    for (uint probe = 0u, i = h & mask; probe < kCacheProbes; ++probe, i = (i + 1u) & mask) {
        uint seen = keys.key[i];
        if (seen == 0u)
            seen = atomicCompSwap(keys.key[i], 0u, check);
        if (seen == 0u || seen == check)
            return i;
    }
    return kCacheOwn;
}

// A hit's share of its cell's sums: vec4(light x n, n) and vec4(n x luminance^2, n x v,
// n^2 x v, 1), the last three 0 where v (the variance of the hit's luminance, as a mean of its
// `samples` samples) is unknown (< 0: one sample). The cell's mean weighs each hit by its samples.
void cache_share(vec3 light, uint samples, float v, out vec4 value, out vec4 stat) {
    float n = float(max(samples, 1u)), l = vx_luminance(light);
    value = vec4(light * n, n);
    stat = v >= 0.0 ? vec4(n * l * l, n * v, n * n * v, 1.0) : vec4(n * l * l, 0.0, 0.0, 0.0);
}

// Adds hits' summed shares (cache_share()) to cell i.
void cache_add(uint i, vec4 value, vec4 stat) {
    CacheValues v = cache_values();
    atomicAdd(v.value[i].x, value.x);
    atomicAdd(v.value[i].y, value.y);
    atomicAdd(v.value[i].z, value.z);
    atomicAdd(v.value[i].w, value.w);
    CacheStats s = cache_stats();
    atomicAdd(s.stat[i].x, stat.x);
    if (stat.w > 0.0) {
        atomicAdd(s.stat[i].y, stat.y);
        atomicAdd(s.stat[i].z, stat.z);
        atomicAdd(s.stat[i].w, stat.w);
    }
}

// A record's second half: the hit's own estimate of the shared light, and the variance of its
// luminance (< 0: unknown) whose 12 low mantissa bits (a relative 2^-11 of it) hold its samples
// (at most 4095; only read where they vary by hit: FrameParams sampling.x).
uvec4 cache_own(vec3 light, float variance, uint samples) {
    return uvec4(floatBitsToUint(light), (floatBitsToUint(variance) & ~0xfffu) | min(samples, 0xfffu));
}
float own_variance(uvec4 r) { return uintBitsToFloat(r.w & ~0xfffu); }
uint own_samples(uvec4 r) { return r.w & 0xfffu; }

// A record: the cell's key (which the gather pass replaces with the cell's index), and the
// weights that turn its mean light into radiance: weight (the path's throughput times the diffuse
// share, 1 - reflectivity) and weight x the surface's albedo, in half floats (their 11-bit
// mantissas are far below an 8-bit output's step).
uvec4 cache_record(uint cell, vec3 weight, vec3 albedo) {
    vec3 wa = weight * albedo;
    return uvec4(cell, packHalf2x16(wa.xy), packHalf2x16(vec2(wa.z, weight.x)), packHalf2x16(weight.yz));
}
vec3 record_weight_albedo(uvec4 r) { return vec3(unpackHalf2x16(r.y), unpackHalf2x16(r.z).x); }
vec3 record_weight(uvec4 r) { return vec3(unpackHalf2x16(r.z).y, unpackHalf2x16(r.w)); }
