// Push constants of the UI pass (ui.vert, ui.frag), shared with render/ui_pass.cpp (which checks
// the size and offsets).
#ifndef VX_SHADERS_UI_TYPES_H
#define VX_SHADERS_UI_TYPES_H

#include "glsl_types.h"
VX_GPU_BEGIN

// Vertices are 5 words each (render::UiVertex): pos.x, pos.y (framebuffer pixels, y down), uv.x,
// uv.y (0..1 over the texture), colour (RGBA8, R in the low byte).
struct UiPush {
    uint64_t vertices;   // Address of the frame's UiVertex[].
    uint64_t texture;    // Address of the texture's RGBA8 texels, row 0 at the top.
    vec2 pixel_to_clip;  // 2 / framebuffer width, 2 / framebuffer height.
    uvec2 texture_size;  // Texels.
};

VX_GPU_END
#endif
