#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The light cache's resolve pass (shared/light_cache.glsl, render/light_cache.h): after the trace
// and the gather pass (light_cache_gather.comp), each pixel adds the mean light of the cells its
// hits fell in, times their records' weights, where raygen.rgen left those hits' shared light
// out: to the radiance, and also to the G-buffer part the denoiser takes it from
// (render/gbuffer.h): the primary hit's diffuse lighting (radiance minus the rest), the first
// mirror bounce's mirror light, deeper bounces' reflected part. The variances the denoiser weighs
// (radiance a, mirror light a) stay the hit's own: what error the blend leaves is shared by a
// patch of pixels, which the filter should still average over, not keep as detail (lavapipe
// hills, 4 spp denoised: 0.0253 with the blend's variance, 0.0237 with the own, 0.0242 without
// the cache; docs/render_report.md). Then it meters and tone-maps the pixel as the ray generation
// would have. Same descriptor set as the trace (render/rt_pipeline.h).

#include "shared/render_types.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 2, std140) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D out_image;
layout(set = 0, binding = 3, rgba16f) uniform image2D radiance_image;
layout(set = 0, binding = 6, rgba16f) uniform image2D reflected_image;
layout(set = 0, binding = 7, rgba16f) uniform image2D mirror_light_image;

#include "shared/sampling.h"
#include "shared/tonemap.h"
#include "shared/meter.glsl"
#include "shared/light_cache.glsl"

// A hit's light: its own estimate `own` (of `samples` samples) moved towards its cell's mean as
// far as that lowers the expected squared error (a shrinkage estimator; James and Stein 1961):
// weight w = v / (v + S + m) on the mean, with v the variance of the hit's own estimate, m the
// mean's, S the spread of the true light over the cell (its hits' spread less their noise): the
// mean's error at this hit. So a cell of smooth light replaces a noisy estimate, and a cell
// across a shadow's edge, or a hit of many samples, keeps its own. v comes from the cell's hits
// pooled (one hit's few samples say little); where no hit of the cell knows its variance (all of
// one sample) it is unknown and w is 1.
vec3 shrink(vec3 own, uint samples, uint cell_index) {
    vec4 cell = cache_values().value[cell_index];
    vec4 stats = cache_stats().stat[cell_index];
    float n = cell.w; // > 0: this hit added itself.
    vec3 mean = cell.xyz / n;
    float l = vx_luminance(mean);
    float noise = stats.y / n; // Known hits' noise in the spread (unknown: counted as spread).
    float spread = max(stats.x / n - l * l - noise, 0.0);
    float mean_var = stats.z / (n * n);
    float v = stats.w > 0.0 ? stats.y / stats.w / float(max(samples, 1u)) : -1.0;
    float w = v < 0.0 ? 1.0 : v / max(v + spread + mean_var, 1e-30);
    return mix(own, mean, w);
}

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size_samples.x || px.y >= frame.size_samples.y)
        return;
    ivec2 p = ivec2(px);
    vec4 radiance = imageLoad(radiance_image, p);
    vec3 reflected = vec3(0.0), mirror = vec3(0.0);
    CacheRecords records = CacheRecords(frame.cache_records);
    for (uint b = 0u; b <= frame.cache.y; ++b) {
        uint at = cache_record_index(px, b);
        uvec4 r = records.record[at];
        if (r.x == kCacheNoSlot)
            continue;
        vec3 own = uintBitsToFloat(records.record[at + 1u].xyz);
        uint samples = frame_samples(b);
        // kCacheOwn: the table was full.
        vec3 light = r.x == kCacheOwn ? own : shrink(own, samples, r.x);
        radiance.rgb += record_weight_albedo(r) * light;
        if (b == 1u)
            mirror = record_weight(r) * light;
        else if (b > 1u)
            reflected += record_weight_albedo(r) * light;
    }
    imageStore(radiance_image, p, radiance);
    if (reflected != vec3(0.0)) {
        vec4 refl = imageLoad(reflected_image, p);
        imageStore(reflected_image, p, vec4(refl.rgb + reflected, refl.a));
    }
    if (mirror != vec3(0.0)) {
        vec4 light = imageLoad(mirror_light_image, p);
        imageStore(mirror_light_image, p, vec4(light.rgb + mirror, light.a));
    }
    // Only Full-mode frames cache (render/renderer_impl.h cache_active): raygen.rgen main()'s Full-mode step.
    finish_full_pixel(p, radiance.rgb);
}
