#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The light cache's gather pass (shared/light_cache.glsl, render/light_cache.h): between the
// trace and the resolve, each pixel's records (their cell keys and own estimates, which
// raygen.rgen wrote) go into the table: the hits of a subgroup that share a cell sum their
// shares first, and one of them claims the cell and adds the sums. The ray generation did this
// per hit, eight float atomics each (on lavapipe a locked compare-and-swap loop per lane):
// neighbouring pixels mostly share a cell, so here a subgroup of 8 pixels in a row adds a few
// cells' sums. Each record's key becomes its cell's index (kCacheOwn: the table was full), which
// the resolve pass reads. Same descriptor set as the trace (render/rt_pipeline.h).

#include "shared/render_types.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 2, std140) uniform FrameBlock { FrameParams frame; };

#include "shared/sampling.h"
#include "shared/tonemap.h"
#include "shared/light_cache.glsl"

// Adds the record at `at`, whose key is `key` (not a marker), with its subgroup's others of the
// same key, and replaces its key with the cell. Called by every invocation whose record has a key.
void add_record(uint at, uint key, uint bounce) {
    CacheRecords records = CacheRecords(frame.cache_records);
    uvec4 own = records.record[at + 1u];
    // A hit's samples: FrameParams sampling.x makes them vary by hit (the record holds them).
    uint samples = frame.sampling.x != 0u ? own_samples(own) : frame_samples(bounce);
    vec4 value, stat;
    cache_share(uintBitsToFloat(own.xyz), samples, own_variance(own), value, stat);
    // One key per round: the first active invocation's; those holding it leave the loop.
    for (;;) {
        if (subgroupBroadcastFirst(key) != key)
            continue;
        vec4 values = subgroupAdd(value), stats = subgroupAdd(stat);
        uint cell = kCacheOwn;
        if (subgroupElect()) {
            cell = cache_claim(key);
            if (cell != kCacheOwn)
                cache_add(cell, values, stats);
        }
        records.record[at].x = subgroupBroadcastFirst(cell);
        return;
    }
}

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size_samples.x || px.y >= frame.size_samples.y)
        return;
    CacheRecords records = CacheRecords(frame.cache_records);
    for (uint b = 0u; b <= frame.cache.y; ++b) {
        uint at = cache_record_index(px, b);
        uint key = records.record[at].x;
        if (key < kCacheOwn)
            add_record(at, key, b);
    }
}
