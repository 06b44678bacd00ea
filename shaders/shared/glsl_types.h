// Lets one header declare a struct for GLSL and C++ alike (render_types.h, denoise_types.h,
// raster_types.h, ui_types.h): in C++ the GLSL type names are glm's inside vx::render::gpu
// (VX_GPU_BEGIN / VX_GPU_END) and constants are inline constexpr; in GLSL those expand to
// nothing and to const. Layouts use 16-byte vectors and 8-byte addresses so std140/std430 and
// C++ agree; each C++ user checks sizes and offsets with static_assert.
#ifndef VX_SHADERS_GLSL_TYPES_H
#define VX_SHADERS_GLSL_TYPES_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace vx::render::gpu {
using vec2 = glm::vec2;
using uvec2 = glm::uvec2;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = uint32_t;
} // namespace vx::render::gpu
#define VX_GPU_BEGIN namespace vx::render::gpu {
#define VX_GPU_END }
#define VX_CONST inline constexpr
#else
#define VX_GPU_BEGIN
#define VX_GPU_END
#define VX_CONST const
#endif

#endif
