#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// A game's 2D UI: vertex colour times the texture, bilinear with clamp to edge (the texture is
// a buffer of RGBA8 texels, so no sampler or descriptor set). Straight alpha: the blend state
// mixes the output over the frame by its alpha. Bytes are what the screen shows (sRGB encoded),
// blended as they are, as Dear ImGui expects.

#include "shared/ui_types.h"

layout(push_constant) uniform Push { UiPush pc; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Texels { uint t[]; };

layout(location = 0) in vec2 v_uv;
layout(location = 1) in vec4 v_colour;
layout(location = 0) out vec4 o_colour;

vec4 texel(ivec2 p) {
    const ivec2 size = ivec2(pc.texture_size);
    p = clamp(p, ivec2(0), size - 1);
    return unpackUnorm4x8(Texels(pc.texture).t[p.y * size.x + p.x]);
}

void main() {
    const vec2 p = v_uv * vec2(pc.texture_size) - 0.5;
    const ivec2 i = ivec2(floor(p));
    const vec2 f = p - floor(p);
    const vec4 t = mix(mix(texel(i), texel(i + ivec2(1, 0)), f.x), mix(texel(i + ivec2(0, 1)), texel(i + ivec2(1, 1)), f.x), f.y);
    o_colour = v_colour * t;
}
