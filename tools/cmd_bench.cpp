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

#ifdef VX_HAVE_BENCHMARKS
namespace {

// The reporter --benchmark_format asks for, noting each run that stopped with SkipWithError
// (a store that could not be opened, a failed save): Google Benchmark prints such a run as an
// error line yet exits 0, and a script must not take its missing figures as measured.
class ErrorNotingReporter final : public benchmark::BenchmarkReporter {
public:
    explicit ErrorNotingReporter(benchmark::BenchmarkReporter* inner) : m_inner(inner) {}
    bool ReportContext(const Context& context) override { return m_inner->ReportContext(context); }
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs)
            if (run.error_occurred)
                m_failed.push_back(run.benchmark_name() + ": " + run.error_message);
        m_inner->ReportRuns(runs);
    }
    void Finalize() override { m_inner->Finalize(); }
    const std::vector<std::string>& failed() const { return m_failed; }

private:
    benchmark::BenchmarkReporter* m_inner; // Google Benchmark's own, not ours to delete.
    std::vector<std::string> m_failed;
};

} // namespace
#endif

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
    ErrorNotingReporter reporter(benchmark::CreateDefaultDisplayReporter());
    if (benchmark::RunSpecifiedBenchmarks(&reporter) == 0) {
        std::fprintf(stderr, "vx: no benchmark matches suite '%s'\n", suite.c_str());
        return kExitBadInput;
    }
    benchmark::Shutdown();
    for (const std::string& failed : reporter.failed())
        std::fprintf(stderr, "vx: benchmark failed, no figure: %s\n", failed.c_str());
    return reporter.failed().empty() ? kExitOk : kExitFailure;
#endif
}

} // namespace vx::tools
