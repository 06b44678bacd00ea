// Push constants of the UI pass (ui.vert, ui.frag), shared with render/ui_pass.cpp (which checks
// the size and offsets).
#ifndef VX_SHADERS_UI_TYPES_H
#define VX_SHADERS_UI_TYPES_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace vx::render::gpu {
using vec2 = glm::vec2;
using uvec2 = glm::uvec2;
#endif

// Vertices are 5 words each (render::UiVertex): pos.x, pos.y (framebuffer pixels, y down), uv.x,
// uv.y (0..1 over the texture), colour (RGBA8, R in the low byte).
struct UiPush {
    uint64_t vertices;   // Address of the frame's UiVertex[].
    uint64_t texture;    // Address of the texture's RGBA8 texels, row 0 at the top.
    vec2 pixel_to_clip;  // 2 / framebuffer width, 2 / framebuffer height.
    uvec2 texture_size;  // Texels.
};

#ifdef __cplusplus
} // namespace vx::render::gpu
#endif
#endif
