#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The raster baseline's shading: Flat mode writes the block albedo (linear, unencoded, as the ray
// tracer's Flat mode); Full mode is Phong with one point light and no shadows (the thesis's
// baseline), exposed, tone-mapped and sRGB encoded as the ray tracer's (shared/tonemap.h);
// Visibility mode has no shadows to show: every surface is lit (1). The transparent pass
// (kTransparentPass) writes each face's tint instead, which the blend multiplies into what lies
// behind (render/raster_pipeline.h).

#include "shared/raster_types.h"
#include "shared/render_types.h"
#include "shared/tonemap.h"

layout(constant_id = 0) const bool kTransparentPass = false;
layout(push_constant) uniform Push { RasterPush pc; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Materials { Material m[]; };

layout(location = 0) in vec3 v_position;
layout(location = 1) flat in uint v_block;
layout(location = 2) flat in uint v_face;
layout(location = 0) out vec4 o_color;

void main() {
    const Material mat = Materials(pc.materials).m[v_block];
    const vec3 albedo = mat.albedo_reflectivity.xyz;
    const uint mode = uint(pc.light_position.w);
    if (kTransparentPass) {
        // The whole albedo on the face where the view ray enters the block, nothing where it
        // leaves (raster.vert culls those back faces): one albedo per block crossed, as
        // trace_through tints linear radiance, also where the block's far face is not meshed (it
        // lies against an opaque block: the walk's g_inside, shared/raygen_common.glsl) and where
        // two see-through blocks touch (the second one's face is where the ray enters it). Half
        // the fragments of tinting both faces by sqrt(albedo). The camera inside a block sees no
        // tint of it (the ray tracer: RenderSettings::eye_block). Full mode's target holds sRGB-encoded
        // values, so there the encoded albedo: the sRGB curve is nearly a power law
        // (encode(a x) ~ encode(a) encode(x)), but the tone curve's toe is not undone (a blend
        // cannot). Visibility draws no such pass.
        o_color = vec4(mode == kModeFull ? vx_srgb_encode(albedo) : albedo, 1.0);
        return;
    }
    if (mode == kModeFlat) {
        o_color = vec4(albedo, 1.0);
        return;
    }
    if (mode == kModeVisibility) {
        o_color = vec4(1.0);
        return;
    }
    vec3 n = vec3(0);
    n[v_face >> 1u] = (v_face & 1u) != 0u ? 1.0 : -1.0;
    const vec3 to_light = pc.light_position.xyz - v_position;
    const float d2 = max(dot(to_light, to_light), 1e-4);
    const vec3 l = to_light * inversesqrt(d2);
    const vec3 v = normalize(-v_position);
    const vec3 irradiance = pc.light_power.xyz * max(dot(n, l), 0.0) / d2;
    const float shininess = 64.0;
    const float specular = mat.albedo_reflectivity.w * (shininess + 8.0) / 8.0 *
                           pow(max(dot(n, normalize(l + v)), 0.0), shininess);
    const vec3 radiance = (albedo + vec3(specular)) / 3.14159265 * irradiance + mat.emission.xyz;
    o_color = vec4(vx_display(radiance, pc.light_power.w), 1.0);
}
