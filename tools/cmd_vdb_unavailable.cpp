// `vx export-vdb` and `vx import-vdb` in a build without OpenVDB (VX_WITH_OPENVDB=OFF): the
// commands still parse, so a script gets one clear line and exit code 2 instead of CLI11's
// "unexpected argument".
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "commands.h"

namespace vx::tools {

void add_vdb_commands(CLI::App& app, std::function<int()>& action) {
    for (const char* name : {"export-vdb", "import-vdb"}) {
        CLI::App* cmd = app.add_subcommand(name, "(unavailable: vx was built without OpenVDB)");
        cmd->allow_extras();
        cmd->callback([name, &action] {
            action = [name] {
                return bad_input(std::string(name) + ": built without OpenVDB (configure with -DVX_WITH_OPENVDB=ON)");
            };
        });
    }
}

int run_bench_vdb(int, char**) {
    return bad_input("bench vdb: built without OpenVDB (configure with -DVX_WITH_OPENVDB=ON)");
}

} // namespace vx::tools
