#include "render/rt_pipeline.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include "render/commands.h"
#include "render/gbuffer.h"
#include "render/graphics_pipeline.h"
#include "render/shader_code.h"
#include "world/base/log.h"

namespace vx::render {

enum : uint32_t { kGroupRaygen, kGroupPrimaryMiss, kGroupShadowMiss, kGroupHit, kGroupRaygenFlat, kGroupCount };

RtPipeline::RtPipeline(Context& ctx) : m_ctx(&ctx) {
    create_layouts();
    // Out of memory: valid() is false.
    m_variants[variant_index(false, SeeThrough::kPlain)] = create_variant(false, SeeThrough::kPlain);
}

bool RtPipeline::ensure_variant(bool sample_faces, SeeThrough see_through) {
    Variant& slot = m_variants[variant_index(sample_faces, see_through)];
    if (slot.pipeline)
        return true;
    Variant v = create_variant(sample_faces, see_through);
    if (v.sbt.valid()) {
        slot = std::move(v);
        return true;
    }
    vkDestroyPipeline(m_ctx->device(), v.pipeline, nullptr); // Never recorded.
    return false;
}

RtPipeline::~RtPipeline() {
    // Layouts are not used by in-flight work once recorded; the pipelines retire with the frame.
    for (Variant& v : m_variants)
        if (v.pipeline)
            m_ctx->retire_list().pipelines.push_back(v.pipeline);
    vkDestroyPipelineLayout(m_ctx->device(), m_layout, nullptr);
    vkDestroyDescriptorSetLayout(m_ctx->device(), m_set_layout, nullptr);
}

void RtPipeline::create_layouts() {
    const VkShaderStageFlags rgen = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    const VkShaderStageFlags hits = VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR | VK_SHADER_STAGE_ANY_HIT_BIT_KHR;
    // The light cache's resolve pass (render/light_cache.h) reads and writes some of the
    // same images after the trace, through this set.
    const VkShaderStageFlags resolve = rgen | VK_SHADER_STAGE_COMPUTE_BIT;
    const VkDescriptorSetLayoutBinding bindings[] = {
        {kBindingTlas, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1, rgen, nullptr},
        {kBindingOutput, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, resolve, nullptr},
        {kBindingParams, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, resolve | hits, nullptr},
        {kBindingRadiance, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, resolve, nullptr},
        {kBindingAlbedo, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, rgen, nullptr},
        {kBindingNormalDepth, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, rgen, nullptr},
        {kBindingReflected, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, resolve, nullptr},
        {kBindingMirrorLight, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, resolve, nullptr},
        {kBindingMirrorAlbedo, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, rgen, nullptr},
        {kBindingMirrorNormalDepth, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, rgen, nullptr},
    };
    VkDescriptorSetLayoutCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    ci.bindingCount = uint32_t(std::size(bindings));
    ci.pBindings = bindings;
    if (m_ctx->create_call("vkCreateDescriptorSetLayout (rt set layout)", [&] {
            return vkCreateDescriptorSetLayout(m_ctx->device(), &ci, nullptr, &m_set_layout);
        }) != VK_SUCCESS)
        return; // Out of memory: valid() is false.
    m_ctx->set_name(m_set_layout, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, "rt set layout");
    const VkPushConstantRange push{VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(gpu::TracePush)};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &m_set_layout;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &push;
    if (m_ctx->create_call("vkCreatePipelineLayout (rt pipeline layout)", [&] {
            return vkCreatePipelineLayout(m_ctx->device(), &pl, nullptr, &m_layout);
        }) != VK_SUCCESS)
        return;
    m_ctx->set_name(m_layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, "rt pipeline layout");
}

static VkRayTracingShaderGroupCreateInfoKHR group(VkRayTracingShaderGroupTypeKHR type, uint32_t general,
                                                  uint32_t closest_hit, uint32_t any_hit = VK_SHADER_UNUSED_KHR) {
    VkRayTracingShaderGroupCreateInfoKHR g{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = type;
    g.generalShader = general;
    g.closestHitShader = closest_hit;
    g.anyHitShader = any_hit;
    g.intersectionShader = VK_SHADER_UNUSED_KHR;
    return g;
}

RtPipeline::Variant RtPipeline::create_variant(bool sample_faces, SeeThrough see_through) {
    if (!m_layout)
        return Variant{}; // Its creation failed (logged).
    const VkShaderModule modules[] = {
        make_shader_module(*m_ctx, spirv::raygen(), "raygen.rgen"),
        make_shader_module(*m_ctx, spirv::primary_miss(), "primary.rmiss"),
        make_shader_module(*m_ctx, spirv::shadow_miss(), "shadow.rmiss"),
        make_shader_module(*m_ctx, spirv::closest_hit(), "closest_hit.rchit"),
        make_shader_module(*m_ctx, spirv::shadow_any_hit(), "shadow.rahit"),
        make_shader_module(*m_ctx, spirv::raygen_flat(), "raygen_flat.rgen"),
    };
    const VkShaderStageFlagBits stage_bits[] = {VK_SHADER_STAGE_RAYGEN_BIT_KHR, VK_SHADER_STAGE_MISS_BIT_KHR,
                                                VK_SHADER_STAGE_MISS_BIT_KHR, VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR,
                                                VK_SHADER_STAGE_ANY_HIT_BIT_KHR, VK_SHADER_STAGE_RAYGEN_BIT_KHR};
    constexpr uint32_t kStages = uint32_t(std::size(stage_bits));
    VkPipelineShaderStageCreateInfo stages[kStages];
    for (uint32_t i = 0; i < kStages; ++i) {
        stages[i] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        stages[i].stage = stage_bits[i];
        stages[i].module = modules[i];
        stages[i].pName = "main";
    }
    // raygen.rgen's constant_id 0, kSampleFaces, both raygens' and shadow.rahit's constant_id 1,
    // kProbeTouching, and the raygens' 2, kSeeThrough (32-bit bools; an id a shader lacks is
    // ignored: Vulkan spec, VkSpecializationMapEntry).
    const bool probe = see_through == SeeThrough::kProbe;
    const VkBool32 constants[3] = {sample_faces ? VK_TRUE : VK_FALSE, probe ? VK_TRUE : VK_FALSE,
                                   see_through != SeeThrough::kNone ? VK_TRUE : VK_FALSE};
    const VkSpecializationMapEntry entries[3] = {
        {0, 0, sizeof(VkBool32)}, {1, sizeof(VkBool32), sizeof(VkBool32)}, {2, 2 * sizeof(VkBool32), sizeof(VkBool32)}};
    const VkSpecializationInfo spec{3, entries, sizeof constants, constants};
    stages[0].pSpecializationInfo = &spec;
    stages[4].pSpecializationInfo = &spec; // shadow.rahit.
    stages[kStages - 1].pSpecializationInfo = &spec; // raygen_flat.rgen.
    const VkRayTracingShaderGroupCreateInfoKHR groups[kGroupCount] = {
        group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, 0, VK_SHADER_UNUSED_KHR),
        group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, 1, VK_SHADER_UNUSED_KHR),
        group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, 2, VK_SHADER_UNUSED_KHR),
        group(VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR, VK_SHADER_UNUSED_KHR, 3, 4),
        group(VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR, 5, VK_SHADER_UNUSED_KHR),
    };
    VkRayTracingPipelineCreateInfoKHR ci{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
    ci.stageCount = kStages;
    ci.pStages = stages;
    ci.groupCount = kGroupCount;
    ci.pGroups = groups;
    ci.maxPipelineRayRecursionDepth = 1; // Every ray is traced from raygen; reflections loop there.
    ci.layout = m_layout;
    if (m_ctx->pipeline_statistics())
        ci.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
    Variant v;
    const std::string suffix = std::string(sample_faces ? ", emitter faces" : "") + (probe ? ", probes" : "") +
                               (see_through == SeeThrough::kNone ? ", opaque only" : "");
    const std::string name = "rt pipeline" + suffix;
    // The test hook (Context::fail_allocations) stands in for the device's own refusal.
    const bool no_module = std::find(std::begin(modules), std::end(modules), VK_NULL_HANDLE) != std::end(modules);
    const bool refused = no_module || m_ctx->allocation_injected(name.c_str()) ||
                         VK_OUT_OF_MEMORY(vkCreateRayTracingPipelinesKHR(m_ctx->device(), VK_NULL_HANDLE, VK_NULL_HANDLE,
                                                                         1, &ci, nullptr, &v.pipeline));
    for (VkShaderModule m : modules)
        vkDestroyShaderModule(m_ctx->device(), m, nullptr);
    if (refused) { // Variants past the first are made mid-session: that frame fails, a later one retries.
        VX_LOG_ERROR("out of memory for %s", name.c_str());
        return Variant{};
    }
    m_ctx->set_name(v.pipeline, VK_OBJECT_TYPE_PIPELINE, name.c_str());
    v.name = name;
    (void)create_sbt(v, ("shader binding table" + suffix).c_str());
    return v;
}

SbtLayout sbt_layout(uint32_t handle_size, uint32_t handle_alignment, uint32_t base_alignment) {
    SbtLayout l;
    l.stride = align_up(handle_size, handle_alignment);
    l.raygen_size = align_up(l.stride, base_alignment);
    l.miss_size = align_up(2 * l.stride, base_alignment);
    l.hit_size = align_up(l.stride, base_alignment);
    l.raygen_flat_at = l.raygen_size;
    l.miss_at = 2 * l.raygen_size;
    l.hit_at = l.miss_at + l.miss_size;
    l.bytes = l.hit_at + l.hit_size + base_alignment;
    return l;
}

bool RtPipeline::create_sbt(Variant& v, const char* name) {
    const auto& p = m_ctx->rt_properties();
    const uint32_t handle = p.shaderGroupHandleSize;
    const uint32_t base = p.shaderGroupBaseAlignment;
    const SbtLayout l = sbt_layout(handle, p.shaderGroupHandleAlignment, base);
    std::vector<uint8_t> handles(size_t(handle) * kGroupCount);
    if (m_ctx->create_call("vkGetRayTracingShaderGroupHandlesKHR", [&] {
            return vkGetRayTracingShaderGroupHandlesKHR(m_ctx->device(), v.pipeline, 0, kGroupCount, handles.size(),
                                                        handles.data());
        }) != VK_SUCCESS)
        return false; // v.sbt stays invalid: the variant is not used.
    BufferCreateInfo bi;
    bi.size = l.bytes;
    bi.usage = VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR;
    bi.memory = MemoryUse::Upload;
    bi.alignment = base;
    bi.name = name;
    v.sbt = Buffer::create(*m_ctx, bi);
    if (!v.sbt.valid())
        return false; // Logged by Buffer::create.
    const VkDeviceAddress a = sbt_start(v.sbt.address(), base);
    auto* dst = static_cast<uint8_t*>(v.sbt.mapped());
    std::memset(dst, 0, bi.size);
    dst += a - v.sbt.address();
    auto put = [&](uint32_t group_index, VkDeviceSize offset) {
        std::memcpy(dst + offset, handles.data() + size_t(group_index) * handle, handle);
    };
    put(kGroupRaygen, 0);
    put(kGroupRaygenFlat, l.raygen_flat_at);
    put(kGroupPrimaryMiss, l.miss_at);
    put(kGroupShadowMiss, l.miss_at + l.stride);
    put(kGroupHit, l.hit_at);
    v.raygen = {a, l.raygen_size, l.raygen_size}; // Raygen: stride must equal size.
    v.raygen_flat = {a + l.raygen_flat_at, l.raygen_size, l.raygen_size};
    v.miss = {a + l.miss_at, l.stride, l.miss_size};
    v.hit = {a + l.hit_at, l.stride, l.hit_size};
    return true;
}

void RtPipeline::trace(VkCommandBuffer cmd, uint32_t width, uint32_t height, bool flat, bool sample_faces,
                       SeeThrough see_through, const gpu::TracePush& push) const {
    const bool faces = sample_faces && !flat; // Flat shades nothing.
    const Variant& v = m_variants[variant_index(faces, see_through)];
    VX_ASSERT_MSG(v.pipeline != VK_NULL_HANDLE, "trace: the pipeline variant was not made (ensure_variant)");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, v.pipeline);
    vkCmdPushConstants(cmd, m_layout, VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof push, &push);
    vkCmdTraceRaysKHR(cmd, flat ? &v.raygen_flat : &v.raygen, &v.miss, &v.hit, &v.callable, width, height, 1);
}

PipelineVariantReport RtPipeline::report(bool sample_faces, SeeThrough see_through) {
    if (!ensure_variant(sample_faces, see_through))
        return {};
    const Variant& v = m_variants[variant_index(sample_faces, see_through)];
    PipelineVariantReport r{v.name, {}, read_executables(*m_ctx, v.pipeline)};
    const char* names[kGroupCount] = {"raygen", "primary miss", "shadow miss", "hit", "raygen flat"};
    for (uint32_t g = 0; g < kGroupCount; ++g) {
        auto stack = [&](VkShaderGroupShaderKHR shader) {
            return uint64_t(vkGetRayTracingShaderGroupStackSizeKHR(m_ctx->device(), v.pipeline, g, shader));
        };
        // Only the shaders a group has may be asked for
        // (VUID-vkGetRayTracingShaderGroupStackSizeKHR-groupShader-03764).
        if (g == kGroupHit)
            r.stacks.push_back({names[g], 0, stack(VK_SHADER_GROUP_SHADER_CLOSEST_HIT_KHR),
                                stack(VK_SHADER_GROUP_SHADER_ANY_HIT_KHR)});
        else
            r.stacks.push_back({names[g], stack(VK_SHADER_GROUP_SHADER_GENERAL_KHR), 0, 0});
    }
    return r;
}

} // namespace vx::render
