// `vx world gen` and `vx world info`: pregenerate a terrain world into a store, and inspect or
// verify one.
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "commands.h"
#include "engine/job_batch.h"
#include "engine/world_pregen.h"
#include "world/store/sqlite_store.h"
#include "world/store/store_open.h"
#include "world/gen/terrain.h"

namespace vx::tools {
namespace {

// vx's own URI parameter (pg_uri_params.h), where a world path may be a URI.
constexpr const char* kPgUriHelp = " (vx_query_timeout_ms=N in it: the longest wait for one server answer, "
                                   "1 to 3600000 ms; default 15000)";

using namespace vx::world;
using Clock = std::chrono::steady_clock;

struct GenArgs {
    std::string path;
    uint64_t seed = 1;
    int radius = 8;
    int bottom = -6, top = 5; // Chunk y range: the terrain's caves to its peaks.
    std::string part = "1/1"; // K/N: this process makes the K-th of N slabs along x (a farm).
    int lod_levels = 0;       // Coarse levels 1..N stored over the box too.
};

// "K/N" with 1 <= K <= N <= 1024, or nullopt.
std::optional<std::pair<int, int>> parse_part(const std::string& s) {
    int k = 0, n = 0;
    char slash = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &k, &slash, &n, &extra) != 3 || slash != '/' || n < 1 || n > 1024 ||
        k < 1 || k > n)
        return std::nullopt;
    return std::make_pair(k, n);
}

void progress(size_t done, size_t total, double seconds) {
    const int width = 40, filled = int(double(width) * double(done) / double(total));
    std::fprintf(stderr, "\r[%.*s%*s] %zu/%zu chunks, %.1f s", filled,
                 "========================================", width - filled, "", done, total, seconds);
    std::fflush(stderr);
}

// The most chunk layers `vx world gen` fills: 32,768 blocks, far past any terrain.
constexpr int64_t kMaxGenLayers = 1024;

// Generates, meshes and saves every chunk in the box through the engine (engine/world_pregen.h).
int run_gen(const GenArgs& a) {
    if (a.radius < 0 || a.radius > 256)
        return bad_input("--radius must be 0..256 chunks");
    if (a.bottom > a.top)
        return bad_input("--bottom must not be above --top");
    if (a.bottom == INT32_MIN || a.top == INT32_MAX) // Its loop once never ended there.
        return bad_input("--bottom and --top must leave the world's outermost chunk layer (-2147483648, 2147483647) "
                         "out: it has no neighbours to mesh against");
    if (int64_t(a.top) - a.bottom >= kMaxGenLayers) // 2^32 layers once ran for days.
        return bad_input("--bottom..--top must span at most " + std::to_string(kMaxGenLayers) + " chunk layers, got " +
                         std::to_string(int64_t(a.top) - a.bottom + 1));
    if (a.lod_levels < 0 || a.lod_levels > kMaxLodLevel)
        return bad_input("--lod-levels must be 0.." + std::to_string(kMaxLodLevel));
    // Part K of N: the K-th of N slabs of the box along x, so N processes (or machines) sharing
    // one PostgreSQL world fill it together without overlap.
    const auto part = parse_part(a.part);
    if (!part)
        return bad_input("--part must be K/N with 1 <= K <= N <= 1024");
    const int width = 2 * a.radius + 1, k = part->first - 1, n = part->second;
    const int x0 = -a.radius + width * k / n, x1 = -a.radius + width * (k + 1) / n - 1;
    if (x1 < x0)
        return bad_input("--part " + a.part + " is empty: the box is only " + std::to_string(width) + " chunks wide");
    engine::JobSystem jobs(engine::batch_job_system_info());
    if (const std::string why = job_system_problem(jobs.start_error()); !why.empty())
        return failed(why);
    // Only now the store: a refused command creates no file.
    // A SQLite file or a postgresql:// URI; nothing here polls other processes' changes, so no
    // listener collects them.
    auto store = open_store({.name = a.path, .listen = false});
    if (!store)
        return bad_input(store.error());
    // A world made by a game's generator (meta "generator", engine/world_setup.cpp) would get
    // terrain chunks beside its own: refused. The built-in terrain records itself as "terrain".
    auto made_by = (*store)->get_meta("generator");
    if (made_by && *made_by && **made_by != "terrain")
        return bad_input("'" + store_display_name(a.path) + "' was made by a game's generator (" + **made_by +
                         "), not the built-in terrain");
    // An imported world (meta "source", tools/world_io.cpp) is a volume, not terrain: terrain
    // chunks around it would be made up.
    auto source = (*store)->get_meta("source");
    if (source && *source && !(made_by && *made_by))
        return bad_input("'" + store_display_name(a.path) + "' was imported (" + **source +
                         "), not made by the built-in terrain");
    if (a.lod_levels > 0 && !(*store)->supports_lod())
        return bad_input("'" + store_display_name(a.path) + "' keeps no coarse levels (--lod-levels)");
    auto old_seed = (*store)->get_meta("seed");
    if (old_seed && *old_seed && **old_seed != std::to_string(a.seed))
        return bad_input("'" + store_display_name(a.path) + "' holds a world of seed " + **old_seed + ", not " +
                         std::to_string(a.seed));
    // Written once every check has passed: a refused command changes nothing.
    if (Status s = (*store)->set_meta("generator", "terrain"); !s)
        return bad_input(s.error());
    if (Status s = (*store)->set_meta("seed", std::to_string(a.seed)); !s)
        return bad_input(s.error());

    const TerrainGenerator gen(a.seed);
    engine::PregenInfo info{ChunkCoord(x0, a.bottom, -a.radius), ChunkCoord(x1, a.top, a.radius), {}};
    info.lod_levels = a.lod_levels;
    const auto t0 = Clock::now();
    const bool bar = stderr_is_terminal(); // Piped: only the summary line below.
    if (bar)
        info.progress = [&](size_t done, size_t total) {
            progress(done, total, std::chrono::duration<double>(Clock::now() - t0).count());
        };
    auto made = engine::pregenerate(jobs, gen, **store, info);
    if (bar)
        std::fputc('\n', stderr);
    if (!made)
        return bad_input(made.error());
    const size_t total = made->chunks;
    const uint64_t non_uniform = made->non_uniform, quads = made->quads;
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf("vx world gen: %zu chunks (%" PRIu64 " non-uniform, %" PRIu64 " quads isolated) in %.2f s "
                "(%.0f chunks/s), seed %" PRIu64 ", saved to %s\n",
                total, non_uniform, quads, secs, double(total) / secs, a.seed, store_display_name(a.path).c_str());
    if (made->kept || made->lod_kept)
        std::printf("  kept as stored: %zu chunks, %zu coarse chunks\n", made->kept, made->lod_kept);
    for (size_t level = 1; level <= made->lod_chunks.size(); ++level)
        std::printf("  level %zu: %zu coarse chunks\n", level, made->lod_chunks[level - 1]);
    return kExitOk;
}

int run_info(const std::string& path, bool check) {
    if (check) {
        auto r = check_world(path);
        if (!r)
            return bad_input(r.error());
        for (const std::string& p : r->problems)
            std::printf("  problem: %s\n", p.c_str());
        if (!r->database_ok)
            std::printf("  database structure check failed\n");
        std::printf("records: %" PRIu64 ", corrupt: %" PRIu64 "\n", r->records, r->corrupt);
        if (r->quarantined)
            std::printf("quarantined earlier: %" PRIu64 "\n", r->quarantined);
        return r->corrupt == 0 && r->database_ok ? kExitOk : kExitFailure;
    }
    auto store = open_store({path, /*read_only=*/true, /*create=*/false, /*listen=*/false});
    if (!store)
        return bad_input(store.error());
    auto count = (*store)->count();
    if (!count)
        return bad_input(count.error());
    ChunkCoord lo(INT32_MAX), hi(INT32_MIN);
    Status s = (*store)->for_each_coord([&](ChunkCoord c) {
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
        return true;
    });
    if (!s)
        return bad_input(s.error());
    auto seed = (*store)->get_meta("seed");
    std::printf("world: %s\n", store_display_name(path).c_str());
    std::printf("  chunks stored: %" PRIu64 "\n", *count);
    if (*count)
        std::printf("  chunk bounds: (%d,%d,%d) .. (%d,%d,%d)\n", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    std::printf("  seed: %s\n", seed && *seed ? (*seed)->c_str() : "(none)");
    auto lods = (*store)->list_lod_coords();
    if (!lods)
        return bad_input(lods.error());
    std::vector<uint64_t> per_level(size_t(kMaxLodLevel) + 1, 0);
    for (const LodCoord& c : *lods)
        if (valid_lod_level(c.level))
            ++per_level[size_t(c.level)];
    for (int k = 1; k <= kMaxLodLevel; ++k)
        if (per_level[size_t(k)])
            std::printf("  level %d coarse chunks stored: %" PRIu64 "\n", k, per_level[size_t(k)]);
    if (auto dirty = (*store)->list_lod_dirty(); dirty && !dirty->empty())
        std::printf("  coarse chunks marked dirty: %zu\n", dirty->size());
    if (auto* sqlite = dynamic_cast<SqliteStore*>(store->get())) {
        if (auto q = sqlite->quarantine_count(); q)
            std::printf("  quarantined records: %" PRIu64 "\n", uint64_t(*q));
    }
    return kExitOk;
}

} // namespace

void add_world_command(CLI::App& app, std::function<int()>& action) {
    CLI::App* world = app.add_subcommand("world", "Create and inspect stored worlds");
    world->require_subcommand(1);

    auto gen = std::make_shared<GenArgs>();
    CLI::App* g = world->add_subcommand("gen", "Pregenerate (and mesh) the chunks around the origin into a store");
    g->add_option("path", gen->path,
                  std::string("World store: a SQLite file (its folder must exist) or a postgresql:// URI") + kPgUriHelp)
        ->required();
    g->add_option("--seed", gen->seed, "Terrain seed")
        ->check(seed_range());
    g->add_option("--radius", gen->radius, "Horizontal radius in chunks around the origin");
    g->add_option("--bottom", gen->bottom, "Lowest chunk y (default -6: below the caves)");
    g->add_option("--top", gen->top, "Highest chunk y (default 5: above the peaks)");
    g->add_option("--lod-levels", gen->lod_levels,
                  "Also store coarse levels of detail 1..N over the box (each level-k cell is 2^k blocks)");
    g->add_option("--part", gen->part, "K/N: make only the K-th of N slabs along x (several processes, one world)");
    g->callback([gen, &action] { action = [gen] { return run_gen(*gen); }; });

    auto path = std::make_shared<std::string>();
    auto check = std::make_shared<bool>(false);
    CLI::App* i = world->add_subcommand("info", "Print what a world holds; --check verifies every record");
    i->add_option("path", *path, std::string("World store: a SQLite file or a postgresql:// URI") + kPgUriHelp)
        ->required();
    i->add_flag("--check", *check, "Read and verify every record: exit 0 if none is corrupt, 1 otherwise");
    i->callback([path, check, &action] { action = [path, check] { return run_info(*path, *check); }; });
}

} // namespace vx::tools
