#pragma once
// Shader modules (every pipeline), compute pipelines, and what the small graphics pipelines share
// (render/raster_pipeline.h, render/ui_pass.h): a push-constant-only layout, and a pipeline for
// dynamic rendering into one colour attachment with dynamic viewport and scissor and no vertex
// input (vertex shaders pull their data through buffer device addresses). Main thread.

#include <span>

#include "render/context.h"

namespace vx::render {

// Each returns VK_NULL_HANDLE when the device refuses it (out of memory: logged, named by
// Context::last_create_failure), and a pipeline given a null layout is null too.

// A shader module with a debug name; the caller destroys it once the pipeline exists.
VkShaderModule make_shader_module(Context& ctx, std::span<const uint32_t> spirv, const char* name);

// A compute pipeline of `code` (SPIR-V) with `layout`, named `name` (its module's too).
VkPipeline make_compute_pipeline(Context& ctx, VkPipelineLayout layout, std::span<const uint32_t> code,
                                 const char* name);

// A pipeline layout with one push-constant range of `bytes` for the vertex and fragment stages.
VkPipelineLayout make_push_constant_layout(Context& ctx, uint32_t bytes, const char* name);

// How fragments combine with the colour attachment; every kind keeps the attachment's alpha.
enum class Blend : uint8_t {
    None,     // Written as they are.
    Alpha,    // Straight alpha over the attachment.
    Multiply, // dst = dst x src, per colour channel.
};

struct GraphicsPipelineDesc {
    std::span<const uint32_t> vert, frag; // SPIR-V (render/shader_code.h).
    const char* vert_name = "";
    const char* frag_name = "";
    const char* name = "";                // The pipeline's debug name.
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkFormat color_format = VK_FORMAT_UNDEFINED;
    VkFormat depth_format = VK_FORMAT_UNDEFINED; // Set: depth test GREATER (reversed).
    bool depth_write = true;                     // With a depth format: passing fragments write it.
    Blend blend = Blend::None;
    const VkSpecializationInfo* specialization = nullptr; // Both stages' (null: none).
};

// Triangle lists, no culling (the shaders reject what they must), one sample.
VkPipeline make_graphics_pipeline(Context& ctx, const GraphicsPipelineDesc& desc);

} // namespace vx::render
