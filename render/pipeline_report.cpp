#include "render/pipeline_report.h"

#include <cinttypes>
#include <cstdio>

#include "render/context.h"
#include "render/rt_pipeline.h"

namespace vx::render {

static std::string statistic_value(const VkPipelineExecutableStatisticKHR& s) {
    char text[64];
    switch (s.format) {
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
        return s.value.b32 ? "true" : "false";
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
        std::snprintf(text, sizeof text, "%" PRId64, s.value.i64);
        return text;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
        std::snprintf(text, sizeof text, "%" PRIu64, s.value.u64);
        return text;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR:
        std::snprintf(text, sizeof text, "%.6g", s.value.f64);
        return text;
    default:
        return "?";
    }
}

// Two-call enumeration (the count, then the data) into structures of type `type`.
template <class T, class F> static bool enumerate(VkStructureType type, std::vector<T>& out, F&& call) {
    uint32_t n = 0;
    if (call(&n, static_cast<T*>(nullptr)) != VK_SUCCESS)
        return false;
    out.assign(n, T{type});
    const VkResult r = call(&n, out.data());
    out.resize(n);
    return r == VK_SUCCESS || r == VK_INCOMPLETE;
}

std::vector<PipelineExecutable> read_executables(const Context& ctx, VkPipeline pipeline) {
    std::vector<PipelineExecutable> result;
    if (!ctx.pipeline_statistics())
        return result;
    const VkPipelineInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR, nullptr, pipeline};
    std::vector<VkPipelineExecutablePropertiesKHR> props;
    // Out of host memory here loses only the report's numbers, never the pipeline.
    if (!enumerate(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR, props, [&](uint32_t* n, auto* p) {
            return vkGetPipelineExecutablePropertiesKHR(ctx.device(), &info, n, p);
        }))
        return result;
    for (uint32_t i = 0; i < props.size(); ++i) {
        PipelineExecutable e{props[i].name, props[i].description, props[i].stages, props[i].subgroupSize, {}};
        VkPipelineExecutableInfoKHR which{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
        which.pipeline = pipeline;
        which.executableIndex = i;
        std::vector<VkPipelineExecutableStatisticKHR> stats;
        if (enumerate(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR, stats, [&](uint32_t* n, auto* p) {
                return vkGetPipelineExecutableStatisticsKHR(ctx.device(), &which, n, p);
            }))
            for (const VkPipelineExecutableStatisticKHR& s : stats)
                e.statistics.push_back({s.name, s.description, statistic_value(s)});
        result.push_back(std::move(e));
    }
    return result;
}

void note_missing_executables(PipelineReport& report) {
    for (const PipelineVariantReport& v : report.variants)
        if (!v.executables.empty())
            return;
    if (report.statistics_note.empty())
        report.statistics_note = "the driver lists no executables for ray tracing pipelines";
}

std::string format_pipeline_report(const PipelineReport& report) {
    std::string out = "pipelines on " + report.device + "\n";
    char line[256];
    for (const PipelineVariantReport& v : report.variants) {
        out += v.name + "\n  stack bytes (general / closest hit / any hit):\n";
        for (const PipelineGroupStack& s : v.stacks) {
            std::snprintf(line, sizeof line, "    %-13s %6" PRIu64 " %6" PRIu64 " %6" PRIu64 "\n",
                          s.group.c_str(), s.general, s.closest_hit, s.any_hit);
            out += line;
        }
        for (const PipelineExecutable& e : v.executables) {
            std::snprintf(line, sizeof line, "  executable %s (stages 0x%x, subgroup %u)\n", e.name.c_str(),
                          e.stages, e.subgroup_size);
            out += line;
            for (const PipelineStatistic& s : e.statistics)
                out += "    " + s.name + ": " + s.value + "\n";
        }
    }
    if (!report.statistics_note.empty())
        out += "no executable statistics: " + report.statistics_note + "\n";
    return out;
}

} // namespace vx::render
