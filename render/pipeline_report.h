#pragma once
// What the driver made of the ray-tracing pipeline's variants (render/rt_pipeline.h). Code a frame
// never runs can still cost every ray, through the registers and the stack it takes
// (docs/render_report.md, stop 56: the see-through code costs the terrain's view 10% on the H100,
// where no ray needs it); these are the numbers a driver gives about that, per variant:
// - each shader group's stack size (vkGetRayTracingShaderGroupStackSizeKHR, core to
//   VK_KHR_ray_tracing_pipeline): what the shader keeps across its trace calls needs that stack;
// - where the device offers VK_KHR_pipeline_executable_properties and the renderer was created with
//   RendererCreateInfo::pipeline_statistics, each executable's statistics as the driver names them
//   (register counts, code size...).
// Plain data, thread-free; filled on the main thread by Renderer::pipeline_report().

#include <cstdint>
#include <string>
#include <vector>

namespace vx::render {

struct PipelineStatistic {
    std::string name;        // The driver's, e.g. "Register Count".
    std::string description; // The driver's.
    std::string value;       // As text: an integer, a float or true / false, in the driver's units.
};

struct PipelineExecutable {
    std::string name, description; // The driver's (e.g. "raygen", "closest hit").
    uint32_t stages = 0;           // VkShaderStageFlags it was compiled from.
    uint32_t subgroup_size = 0;
    std::vector<PipelineStatistic> statistics;
};

// Stack sizes of one shader group, bytes (VK_SHADER_GROUP_SHADER_*: general for raygen and miss
// groups, closest and any hit for hit groups; 0 where the group has no such shader).
struct PipelineGroupStack {
    std::string group; // "raygen", "primary miss", "shadow miss", "hit", "raygen flat".
    uint64_t general = 0, closest_hit = 0, any_hit = 0;
};

struct PipelineVariantReport {
    std::string name; // The variant's debug name, e.g. "rt pipeline, probes".
    std::vector<PipelineGroupStack> stacks;
    std::vector<PipelineExecutable> executables; // Empty without statistics.
};

struct PipelineReport {
    std::string device;
    std::vector<PipelineVariantReport> variants;
    // Why no variant lists executables ("" when statistics were kept): the device lacks the
    // extension, the renderer was not asked to keep them, or the driver lists none for ray-tracing
    // pipelines.
    std::string statistics_note;
};

// Where statistics were kept (no note) but no variant lists an executable, says so in the note: a
// driver may keep statistics and list none for ray-tracing pipelines (the extension first covered
// graphics and compute pipelines only: Vulkan-Docs issue 1433).
void note_missing_executables(PipelineReport& report);

// The report as text, one variant after another: its stacks, then each executable's statistics.
std::string format_pipeline_report(const PipelineReport& report);

} // namespace vx::render
