// What both ray-generation shaders (raygen.rgen: full shading; raygen_flat.rgen: Flat) share:
// the descriptor bindings (render/rt_pipeline.h), the primary payload, the primary ray through a
// pixel's centre and the walk through transparent blocks. Include after rt_common.glsl.

layout(set = 0, binding = 0) uniform accelerationStructureEXT tlas;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D out_image;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D radiance_image;
layout(set = 0, binding = 4, rgba8) uniform writeonly image2D albedo_image;
layout(set = 0, binding = 5, rgba16f) uniform writeonly image2D normal_depth_image;
layout(set = 0, binding = 6, rgba16f) uniform writeonly image2D reflected_image;
layout(set = 0, binding = 7, rgba16f) uniform writeonly image2D mirror_light_image;
layout(set = 0, binding = 8, rgba8) uniform writeonly image2D mirror_albedo_image;
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D mirror_normal_depth_image;

layout(location = 0) rayPayloadEXT HitPayload payload;
const float kTMax = 1.0e7;

vec3 face_normal(uint face) {
    vec3 n = vec3(0.0);
    n[face >> 1u] = (face & 1u) != 0u ? 1.0 : -1.0;
    return n;
}

vec3 primary_dir(uvec2 px) {
    vec2 ndc = (vec2(px) + 0.5) / vec2(frame.size_samples.xy) * 2.0 - 1.0;
    float th = frame.camera_origin.w, aspect = frame.camera_forward.w;
    return normalize(frame.camera_forward.xyz + ndc.x * th * aspect * frame.camera_right.xyz -
                     ndc.y * th * frame.camera_up.xyz);
}

// Traces to the first opaque hit, passing through up to kMaxTransparentLayers transparent faces
// (each tints by sqrt(albedo): one albedo per block crossed). payload holds that hit (t < 0: a
// miss), with t the whole distance from `origin`. Returns the tint.
vec3 trace_through(vec3 origin, vec3 dir) {
    vec3 tint = vec3(1.0);
    float travelled = 0.0;
    for (uint layer = 0u;; ++layer) {
        traceRayEXT(tlas, gl_RayFlagsOpaqueEXT, 0xFFu, 0u, 1u, kPrimaryMiss, origin, 0.0, dir, kTMax, kPrimaryPayload);
        if (payload.t < 0.0)
            return tint;
        travelled += payload.t;
        Material m = vx_material(payload.block);
        if (!vx_transparent(m) || layer >= kMaxTransparentLayers) {
            payload.t = travelled;
            return tint;
        }
        tint *= sqrt(m.albedo_reflectivity.xyz);
        origin = payload.through;
    }
}
