// `vx info`: version, the libraries vx was built with, and the Vulkan devices that can ray trace.
#include <cstdio>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>
#include <zstd.h>

#include "cli_common.h"
#include "commands.h"

namespace vx::tools {
namespace {

int run_info() {
    std::printf("vx %s\n", VX_VERSION_STRING);
    std::printf("dependencies:\n");
    std::printf("  GLM %d.%d.%d\n", GLM_VERSION_MAJOR, GLM_VERSION_MINOR, GLM_VERSION_PATCH);
    std::printf("  zstd %s (runtime %s)\n", ZSTD_VERSION_STRING, ZSTD_versionString());
    std::printf("  CLI11 %s\n", CLI11_VERSION);
    return kExitOk;
}

} // namespace

void add_info_command(CLI::App& app, std::function<int()>& action) {
    CLI::App* cmd = app.add_subcommand("info", "Version, dependencies and Vulkan ray-tracing devices");
    cmd->callback([&action] { action = [] { return run_info(); }; });
}

} // namespace vx::tools
