#pragma once
// Subcommands of the vx CLI. Each add_*_command registers its options on `app`; when the
// subcommand is chosen, its callback stores the function to run in `action`.

#include <functional>

namespace CLI {
class App;
}

namespace vx::tools {

void add_info_command(CLI::App& app, std::function<int()>& action);
void add_mesh_command(CLI::App& app, std::function<int()>& action);
void add_world_command(CLI::App& app, std::function<int()>& action);
void add_vdb_commands(CLI::App& app, std::function<int()>& action);
void add_render_command(CLI::App& app, std::function<int()>& action);
// `vx bench SUITE [Google Benchmark flags]` is dispatched before CLI11 parsing (main.cpp).
int run_bench(int argc, char** argv);
int run_bench_vdb(int argc, char** argv); // `vx bench vdb` (argv[0] = "vdb").
// `vx bench render [flags]` (tools/cmd_bench_render.cpp): argv[0] is "render".
int run_bench_render_command(int argc, char** argv);
// `vx bench lod [flags]` (tools/cmd_bench_lod.cpp): argv[0] is "lod".
int run_bench_lod_command(int argc, char** argv);

} // namespace vx::tools
