// The vx command-line tool. CLI11 reports parse errors by exception: they are caught here, at
// its boundary, and turned into a one-line message and exit code 2.
#include <cstdio>
#include <cstring>
#include <functional>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "commands.h"

int main(int argc, char** argv) {
    using namespace vx::tools;
    if (argc >= 3 && std::strcmp(argv[1], "bench") == 0 && std::strcmp(argv[2], "vdb") == 0)
        return run_bench_vdb(argc - 2, argv + 2);
    if (argc >= 2 && std::strcmp(argv[1], "bench") == 0)
        return run_bench(argc - 1, argv + 1);

    CLI::App app("vx: voxel world streaming engine tools", "vx");
    app.require_subcommand(1);
    std::function<int()> action;
    add_info_command(app, action);
    add_mesh_command(app, action);
    add_world_command(app, action);
    add_vdb_commands(app, action);
    add_render_command(app, action);
    app.add_subcommand("bench", "Run benchmarks: vx bench SUITE [--benchmark_* flags] (suites: mesh, terrain, stream, store, pg; render, lod: renderer reports; vdb: export memory)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return parse_failure(app, e, "'vx --help' or 'vx COMMAND --help'");
    }
    return action ? action() : kExitBadInput;
}
