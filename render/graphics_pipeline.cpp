#include "render/graphics_pipeline.h"

namespace vx::render {

VkShaderModule make_shader_module(Context& ctx, std::span<const uint32_t> spirv, const char* name) {
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = spirv.size_bytes();
    ci.pCode = spirv.data();
    VkShaderModule m = VK_NULL_HANDLE;
    if (ctx.create_call("vkCreateShaderModule", name,
                        [&] { return vkCreateShaderModule(ctx.device(), &ci, nullptr, &m); }) != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(m, VK_OBJECT_TYPE_SHADER_MODULE, name);
    return m;
}

VkPipeline make_compute_pipeline(Context& ctx, VkPipelineLayout layout, std::span<const uint32_t> code, const char* name) {
    if (!layout)
        return VK_NULL_HANDLE; // Its creation failed (logged).
    const VkShaderModule module = make_shader_module(ctx, code, name);
    if (!module)
        return VK_NULL_HANDLE;
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = module;
    ci.stage.pName = "main";
    ci.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = ctx.create_call("vkCreateComputePipelines", name, [&] {
        return vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline);
    });
    vkDestroyShaderModule(ctx.device(), module, nullptr);
    if (r != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(pipeline, VK_OBJECT_TYPE_PIPELINE, name);
    return pipeline;
}

VkPipelineLayout make_push_constant_layout(Context& ctx, uint32_t bytes, const char* name) {
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, bytes};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    if (ctx.create_call("vkCreatePipelineLayout", name,
                        [&] { return vkCreatePipelineLayout(ctx.device(), &pl, nullptr, &layout); }) != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, name);
    return layout;
}

namespace {

VkPipelineColorBlendAttachmentState blend_attachment(Blend blend) {
    VkPipelineColorBlendAttachmentState a{};
    a.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if (blend == Blend::None)
        return a;
    a.blendEnable = VK_TRUE;
    if (blend == Blend::Alpha) {
        a.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
        a.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    } else { // src x 0 + dst x src (Vulkan spec, "Blend Factors").
        a.srcColorBlendFactor = VK_BLEND_FACTOR_ZERO;
        a.dstColorBlendFactor = VK_BLEND_FACTOR_SRC_COLOR;
    }
    a.colorBlendOp = VK_BLEND_OP_ADD;
    a.srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO; // The attachment's alpha stays.
    a.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    a.alphaBlendOp = VK_BLEND_OP_ADD;
    return a;
}

} // namespace

VkPipeline make_graphics_pipeline(Context& ctx, const GraphicsPipelineDesc& d) {
    if (!d.layout)
        return VK_NULL_HANDLE; // Its creation failed (logged).
    const VkShaderModule vert = make_shader_module(ctx, d.vert, d.vert_name);
    const VkShaderModule frag = vert ? make_shader_module(ctx, d.frag, d.frag_name) : VK_NULL_HANDLE;
    if (!frag) {
        vkDestroyShaderModule(ctx.device(), vert, nullptr);
        return VK_NULL_HANDLE;
    }
    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vert;
    stages[0].pName = "main";
    stages[0].pSpecializationInfo = d.specialization;
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = frag;
    stages[1].pName = "main";
    stages[1].pSpecializationInfo = d.specialization;
    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    if (d.depth_format != VK_FORMAT_UNDEFINED) {
        depth.depthTestEnable = VK_TRUE;
        depth.depthWriteEnable = d.depth_write ? VK_TRUE : VK_FALSE;
        depth.depthCompareOp = VK_COMPARE_OP_GREATER; // Reversed depth (raster_pipeline.h).
    }
    const VkPipelineColorBlendAttachmentState attachment = blend_attachment(d.blend);
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &attachment;
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &d.color_format;
    rendering.depthAttachmentFormat = d.depth_format;

    VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
    ci.stageCount = 2;
    ci.pStages = stages;
    ci.pVertexInputState = &vertex_input;
    ci.pInputAssemblyState = &assembly;
    ci.pViewportState = &viewport;
    ci.pRasterizationState = &raster;
    ci.pMultisampleState = &multisample;
    ci.pDepthStencilState = &depth;
    ci.pColorBlendState = &blend;
    ci.pDynamicState = &dynamic;
    ci.layout = d.layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = ctx.create_call("vkCreateGraphicsPipelines", d.name, [&] {
        return vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline);
    });
    vkDestroyShaderModule(ctx.device(), vert, nullptr);
    vkDestroyShaderModule(ctx.device(), frag, nullptr);
    if (r != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(pipeline, VK_OBJECT_TYPE_PIPELINE, d.name);
    return pipeline;
}

} // namespace vx::render
