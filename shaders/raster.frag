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
#include "shared/optics.glsl"

layout(constant_id = 0) const bool kTransparentPass = false;
layout(push_constant) uniform Push { RasterPush pc; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Materials { Material m[]; };

layout(location = 0) in vec3 v_position;
layout(location = 1) flat in uint v_block;
layout(location = 2) flat in uint v_face;
layout(location = 3) in vec3 v_local;
layout(location = 0) out vec4 o_color;

// The length in blocks of the view ray's path through the cell whose face this fragment is (the
// ray enters the cell here, from air, bent by Snell's law as the ray tracer's walk bends it: the
// block's index from its normal-incidence reflectance r, vx_index in shared/optics.glsl):
// from the entry point in the cell's own [0, 1]^3 to the side where it leaves (slab method),
// reflected inside past the critical angle as the walk reflects it (at most 4 times), times the
// cell's size.
float chord(float r) {
    const uint axis = v_face >> 1u;
    vec3 n = vec3(0.0);
    n[axis] = (v_face & 1u) != 0u ? 1.0 : -1.0; // Outward: the ray runs against it.
    const float eta = 1.0 / vx_index(r);
    vec3 dir = normalize(refract(normalize(v_position), n, eta));
    vec3 p = clamp(fract(v_local), 0.0, 1.0);
    p[axis] = (v_face & 1u) != 0u ? 1.0 : 0.0; // A +axis face is its cell's top side.
    float length = 0.0;
    for (int bounce = 0; bounce < 5; ++bounce) {
        float t = 1e30;
        uint side = 0u;
        for (uint k = 0u; k < 3u; ++k)
            if (dir[k] != 0.0) {
                const float tk = ((dir[k] > 0.0 ? 1.0 : 0.0) - p[k]) / dir[k];
                if (tk < t) {
                    t = tk;
                    side = k;
                }
            }
        t = max(t, 0.0);
        length += t;
        p += dir * t;
        // Out into air where the side's cosine is above the critical one: 1 - (n sin)^2 > 0.
        if (1.0 - (1.0 - dir[side] * dir[side]) / (eta * eta) > 0.0)
            break;
        dir[side] = -dir[side];
    }
    return length * pc.chunk_origin.w;
}

void main() {
    const Material mat = Materials(pc.materials).m[v_block];
    const vec3 albedo = mat.albedo_reflectivity.xyz;
    const uint mode = uint(pc.light_position.w);
    if (kTransparentPass) {
        // On the face where the view ray enters the block, what its body passes along the ray's
        // bent path through the block (Beer-Lambert, as the ray tracer: albedo^chord, vx_absorb in
        // shared/rt_common.glsl), nothing where it leaves (raster.vert culls those back faces): also
        // where the block's far face is not meshed (it lies against an opaque block) and where two
        // see-through blocks touch (the second one's face is where the ray enters it). The baseline's
        // limit: a body of several blocks of one kind draws only its entry faces, so it absorbs along
        // the first block's path alone (the ray tracer: the whole path). The camera inside a block
        // sees no tint of it (the ray tracer: RenderSettings::eye_block). Full mode's target holds
        // sRGB-encoded values, so there the encoded pass: the sRGB curve is nearly a power law
        // (encode(a x) ~ encode(a) encode(x)), but the tone curve's toe is not undone (a blend
        // cannot). Visibility draws no such pass.
        const vec3 pass = pow(albedo, vec3(chord(mat.albedo_reflectivity.w)));
        o_color = vec4(mode == kModeFull ? vx_srgb_encode(pass) : pass, 1.0);
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
