// `vx bench vdb`: peak memory of `vx export-vdb` on a VDB world with an edits overlay, for a world
// and one of 8x the chunks. Each export runs as its own `vx export-vdb` process (this binary, or
// --exe), so its peak RSS (wait4; an isolated reader child included, the larger of the two) is the
// user's cost. The worlds are made in forked children, so this process stays small: Linux carries
// the old address space's high-water mark over exec, and posix_spawn's child runs in ours until
// then, so a spawned child's ru_maxrss is at least this process's peak. Prints the baseline (a
// run that fails at once: process and libraries) and one line per size.
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/scratch_dir.h"
#include "cli_common.h"
#include "commands.h"
#include "world/gen/terrain.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world/vdb/vdb_world.h"

extern char** environ;

namespace vx::tools {
namespace {

using namespace vx::world;

struct Run {
    uint64_t peak_rss_kb = 0;
    double seconds = 0;
    int status = -1;
};

// Runs `exe` with `args`, returns its exit status, peak RSS and wall time.
Run run_exe(const std::string& exe, const std::vector<std::string>& args) {
    std::vector<std::string> all = {exe};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    Run r;
    const auto t0 = std::chrono::steady_clock::now();
    pid_t pid = 0;
    if (::posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
        return r;
    int status = 0;
    rusage use{};
    while (::wait4(pid, &status, 0, &use) < 0 && errno == EINTR) {
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.peak_rss_kb = uint64_t(use.ru_maxrss);
    return r;
}

// A terrain world of nx x 4 x nz chunks (y -1..2: rock, the surface and sky), exported to `vdb`,
// with every 16th chunk edited in its overlay. Returns the chunk count.
Result<size_t> make_world(const std::string& vdb, int nx, int nz) {
    const TerrainGenerator gen(1);
    size_t chunks = 0;
    {
        World w;
        for (int z = 0; z < nz; ++z)
            for (int y = -1; y <= 2; ++y)
                for (int x = 0; x < nx; ++x)
                    w.put_chunk(ChunkCoord(x, y, z), gen.generate(ChunkCoord(x, y, z)));
        chunks = w.chunk_count();
        if (Status s = vdb::export_vdb(w, vdb); !s)
            return Error{s.error()};
    }
    std::error_code ec;
    std::filesystem::remove(vdb::default_overlay_name(vdb), ec);
    vdb::VdbOverlayOpenInfo info;
    info.vdb_path = vdb;
    info.read.isolated = false; // Our own file, just written.
    auto store = vdb::VdbOverlayStore::open(info);
    if (!store)
        return Error{store.error()};
    int k = 0;
    for (int z = 0; z < nz; ++z)
        for (int x = 0; x < nx; ++x)
            if (k++ % 16 == 0)
                if (Status s = (*store)->save(ChunkCoord(x, 0, z), Chunk(BlockId(1 + k % 8))); !s)
                    return Error{s.error()};
    if (Status s = (*store)->flush(); !s)
        return Error{s.error()};
    return chunks;
}

// make_world in a forked child (see the top of the file); its result comes back through a pipe.
Result<size_t> make_world_apart(const std::string& vdb, int nx, int nz) {
    int fds[2];
    if (::pipe(fds) != 0)
        return Error{"pipe failed"};
    const pid_t pid = ::fork();
    if (pid < 0)
        return Error{"fork failed"};
    if (pid == 0) {
        ::close(fds[0]);
        Result<size_t> r = make_world(vdb, nx, nz);
        const std::string msg = r ? "ok " + std::to_string(*r) : "error " + r.error();
        const bool written = ::write(fds[1], msg.data(), msg.size()) == ssize_t(msg.size());
        ::_exit(written ? 0 : 1);
    }
    ::close(fds[1]);
    std::string msg;
    char buf[256];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) != 0;)
        if (n > 0)
            msg.append(buf, size_t(n));
        else if (errno != EINTR)
            break;
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (msg.rfind("ok ", 0) == 0)
        return size_t(std::strtoull(msg.c_str() + 3, nullptr, 10));
    return Error{msg.rfind("error ", 0) == 0 ? msg.substr(6) : "the world-making child failed"};
}

} // namespace

int run_bench_vdb(int argc, char** argv) {
    CLI::App app("Peak RSS of vx export-vdb of a VDB world with edits, at 1x and 8x the chunks", "vx bench vdb");
    int side = 8;
    std::string scratch_base; // Empty: $TMPDIR, else /tmp (bench/scratch_dir.h).
    app.add_option("--side", side, "1x world: side x 4 x side chunks; 8x: 4 side x 4 x 2 side (default 8)")
        ->check(CLI::Range(1, 256));
    app.add_option("--dir", scratch_base,
                   "Folder in which to make a new scratch folder, removed afterwards (default: $TMPDIR, else /tmp)");
    std::string exe = "/proc/self/exe";
    app.add_option("--exe", exe, "The vx binary whose export-vdb is measured (default: this one), e.g. an older build");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return parse_failure(app, e);
    }
    // A folder of its own, made here: only it is removed at the end, never what --dir names.
    Result<ScratchDir> scratch = ScratchDir::make("vx_bench_vdb", scratch_base);
    if (!scratch)
        return bad_input(scratch.error());
    const std::string& dir = scratch->path();
    std::error_code ec;
    int rc = kExitOk;
    const Run base = run_exe(exe, {"export-vdb", dir + "/missing.vdb", "--out", dir + "/none.vdb"});
    // A vx refuses the missing file with exit 2; anything else (no such program, /bin/true) would
    // make every figure below a wrong one (a baseline of 0 MB, a merged file of 2^64 bytes).
    if (base.status != kExitBadInput)
        return bad_input("--exe '" + exe + "' is not a vx: its export-vdb of a missing file exited " +
                         std::to_string(base.status) + ", not 2");
    std::printf("vx bench vdb: baseline (export-vdb of a missing file: process and libraries): peak RSS %.1f MB\n",
                double(base.peak_rss_kb) / 1024.0);
    for (const int scale : {1, 8}) {
        const int nx = scale == 1 ? side : 4 * side, nz = scale == 1 ? side : 2 * side;
        const std::string vdb = dir + "/w" + std::to_string(scale) + ".vdb", out = dir + "/merged.vdb";
        Result<size_t> chunks = make_world_apart(vdb, nx, nz);
        if (!chunks) {
            rc = bad_input(chunks.error());
            break;
        }
        const Run r = run_exe(exe, {"export-vdb", vdb, "--out", out});
        if (r.status != 0) {
            rc = bad_input("vx export-vdb " + vdb + " failed (exit " + std::to_string(r.status) + ")");
            break;
        }
        if (!std::filesystem::is_regular_file(out, ec)) {
            rc = bad_input("vx export-vdb " + vdb + " exited 0 but wrote no '" + out + "'");
            break;
        }
        std::printf("vx bench vdb: %dx: %zu chunks (%d x 4 x %d), file %.1f MB -> merged %.1f MB: peak RSS %.1f MB, "
                    "%.2f s\n",
                    scale, *chunks, nx, nz, double(std::filesystem::file_size(vdb, ec)) / 1e6,
                    double(std::filesystem::file_size(out, ec)) / 1e6, double(r.peak_rss_kb) / 1024.0, r.seconds);
        std::fflush(stdout);
    }
    return rc; // ~ScratchDir removes the folder.
}

} // namespace vx::tools
