// `vx bench SUITE [flags]`: runs the Google Benchmark registrations named SUITE/..., with any
// --benchmark_* flags passed through (e.g. --benchmark_repetitions=9).
#include <cstdio>
#include <string>
#include <vector>

#ifdef VX_HAVE_BENCHMARKS
#include <benchmark/benchmark.h>
#endif

#include "cli_common.h"
#include "commands.h"

namespace vx::tools {

int run_bench(int argc, char** argv) {
    if (argc >= 2 && std::string(argv[1]) == "render") // A renderer report, not Google Benchmark.
        return run_bench_render_command(argc - 1, argv + 1);
    if (argc >= 2 && std::string(argv[1]) == "lod") // LOD against full detail (a renderer report too).
        return run_bench_lod_command(argc - 1, argv + 1);
#ifndef VX_HAVE_BENCHMARKS
    (void)argc, (void)argv;
    std::fprintf(stderr, "vx: this build has no benchmarks (configure with -DVX_BUILD_BENCHMARKS=ON)\n");
    return kExitBadInput;
#else
    if (argc < 2 || argv[1][0] == '-') {
        std::fprintf(stderr, "usage: vx bench SUITE [--benchmark_* flags]   (suites: mesh, terrain, stream, store, pg)\n");
        return kExitBadInput;
    }
    const std::string suite = argv[1];
    std::vector<std::string> storage = {"vx bench " + suite};
    bool has_filter = false;
    for (int i = 2; i < argc; ++i) {
        storage.emplace_back(argv[i]);
        has_filter |= storage.back().rfind("--benchmark_filter", 0) == 0;
    }
    if (!has_filter)
        storage.push_back("--benchmark_filter=^" + suite + "/");
    std::vector<char*> args;
    for (std::string& s : storage)
        args.push_back(s.data());
    int n = int(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data()))
        return kExitBadInput;
    if (benchmark::RunSpecifiedBenchmarks() == 0) {
        std::fprintf(stderr, "vx: no benchmark matches suite '%s'\n", suite.c_str());
        return kExitBadInput;
    }
    benchmark::Shutdown();
    return kExitOk;
#endif
}

} // namespace vx::tools
