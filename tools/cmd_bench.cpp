// `vx bench SUITE [flags]`: runs the Google Benchmark registrations named SUITE/..., with any
// --benchmark_* flags passed through (e.g. --benchmark_repetitions=9).
#include <cstdio>
#include <optional>
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
        m_runs += runs.size();
        for (const Run& run : runs)
            if (run.error_occurred)
                m_failed.push_back(run.benchmark_name() + ": " + run.error_message);
        m_inner->ReportRuns(runs);
    }
    void Finalize() override { m_inner->Finalize(); }
    const std::vector<std::string>& failed() const { return m_failed; }
    size_t runs() const { return m_runs; }

private:
    benchmark::BenchmarkReporter* m_inner; // Google Benchmark's own, not ours to delete.
    std::vector<std::string> m_failed;
    size_t m_runs = 0;
};

// Why a --benchmark_* flag that Google Benchmark would take badly is refused, or "": a negative
// repetition count aborted (std::length_error), zero measured nothing and exited 0, and an
// unknown format printed the usage and exited 0.
std::string flag_problem(const std::string& arg) {
    auto value_of = [&](const char* name) -> std::optional<std::string> {
        const std::string prefix = std::string(name) + "=";
        return arg.rfind(prefix, 0) == 0 ? std::optional(arg.substr(prefix.size())) : std::nullopt;
    };
    if (auto v = value_of("--benchmark_repetitions")) {
        const std::optional<int64_t> n = parse_i64(*v);
        if (!n || *n < 1 || *n > 100000)
            return "--benchmark_repetitions must be 1..100000, got '" + *v + "'";
    }
    for (const char* name : {"--benchmark_format", "--benchmark_out_format"})
        if (auto v = value_of(name); v && *v != "console" && *v != "json" && *v != "csv")
            return std::string(name) + " must be console, json or csv, got '" + *v + "'";
    return {};
}

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
        std::fprintf(stderr, "usage: vx bench SUITE [--benchmark_* flags]   (suites: mesh, terrain, stream, store, pg; render, lod: renderer reports; vdb: export memory)\n");
        return kExitBadInput;
    }
    const std::string suite = argv[1];
    std::vector<std::string> storage = {"vx bench " + suite};
    bool has_filter = false;
    for (int i = 2; i < argc; ++i) {
        storage.emplace_back(argv[i]);
        if (const std::string why = flag_problem(storage.back()); !why.empty())
            return bad_input(why);
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
    if (reporter.runs() == 0) {
        std::fprintf(stderr, "vx: the benchmarks of suite '%s' reported no run\n", suite.c_str());
        return kExitFailure;
    }
    return reporter.failed().empty() ? kExitOk : kExitFailure;
#endif
}

} // namespace vx::tools
