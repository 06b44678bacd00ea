// `vx info`: version, the libraries vx was built with, and the Vulkan devices that can ray trace.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>
#include <zstd.h>

#include "cli_common.h"
#include "commands.h"
#include "render/device_probe.h"

namespace vx::tools {
namespace {

// What a device lacks for vx's renderer, named; empty when it can ray trace.
std::string missing_parts(const render::DeviceReport& d) {
    std::string out;
    auto add = [&](bool ok, const char* what) {
        if (!ok)
            out += std::string(out.empty() ? "" : ", ") + what;
    };
    add(d.api_version >= ((1u << 22) | (3u << 12)), "Vulkan 1.3"); // VK_MAKE_API_VERSION(0, 1, 3, 0)
    add(d.acceleration_structure, "VK_KHR_acceleration_structure");
    add(d.ray_tracing_pipeline, "VK_KHR_ray_tracing_pipeline");
    add(d.deferred_host_operations, "VK_KHR_deferred_host_operations");
    add(d.buffer_device_address, "bufferDeviceAddress");
    add(d.float_atomic_add, "shaderBufferFloat32AtomicAdd");
    add(d.compute_subgroup_sums, "compute subgroup ballot + arithmetic");
    return out;
}

// Vulkan devices; a missing loader or driver is a line of output, not a failure.
void print_devices() {
    const auto devices = render::probe_devices();
    if (!devices) {
        std::printf("vulkan: none (%s)\n", devices.error().c_str());
        return;
    }
    std::printf("vulkan devices: %zu\n", devices->size());
    for (const render::DeviceReport& d : *devices) {
        const std::string missing = missing_parts(d);
        constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
        std::printf("  [%u] %s (%s), Vulkan %s, driver %s, ray tracing: %s, memory %.1f GiB, largest buffer %.1f GiB\n",
                    d.index, d.name.c_str(), render::device_type_name(d.type), d.api_version_string().c_str(),
                    d.driver_info.c_str(), missing.empty() ? "yes" : ("no (missing " + missing + ")").c_str(),
                    double(d.device_memory) / kGiB, double(d.max_buffer_size) / kGiB);
    }
}

int run_info() {
    std::printf("vx %s\n", VX_VERSION_STRING);
    std::printf("dependencies:\n");
    std::printf("  GLM %d.%d.%d\n", GLM_VERSION_MAJOR, GLM_VERSION_MINOR, GLM_VERSION_PATCH);
    std::printf("  zstd %s (runtime %s)\n", ZSTD_VERSION_STRING, ZSTD_versionString());
    std::printf("  CLI11 %s\n", CLI11_VERSION);
    print_devices();
    return kExitOk;
}

} // namespace

void add_info_command(CLI::App& app, std::function<int()>& action) {
    CLI::App* cmd = app.add_subcommand("info", "Version, dependencies and Vulkan ray-tracing devices");
    cmd->callback([&action] { action = [] { return run_info(); }; });
}

} // namespace vx::tools
