#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// A game's 2D UI (render/ui_pass.h): vertices pulled from the frame's vertex buffer by index
// (5 words each, shared/ui_types.h), framebuffer pixels to clip space (Vulkan: y down).

#include "shared/ui_types.h"

layout(push_constant) uniform Push { UiPush pc; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Words { uint w[]; };

layout(location = 0) out vec2 v_uv;
layout(location = 1) out vec4 v_colour;

void main() {
    const uint base = uint(gl_VertexIndex) * 5u;
    Words words = Words(pc.vertices);
    const vec2 pos = vec2(uintBitsToFloat(words.w[base]), uintBitsToFloat(words.w[base + 1u]));
    v_uv = vec2(uintBitsToFloat(words.w[base + 2u]), uintBitsToFloat(words.w[base + 3u]));
    v_colour = unpackUnorm4x8(words.w[base + 4u]);
    gl_Position = vec4(pos * pc.pixel_to_clip - 1.0, 0.0, 1.0);
}
