#include "world_io.h"

#include <cstdio>
#include <filesystem>
#include <vector>

#include <unistd.h>

#include "cli_common.h"
#include "world/base/file_lock.h"
#include "world/block_registry_text.h"
#include "world/store/pg_store.h"
#include "world/store/sqlite_store.h"
#include "world/store/store_open.h"

namespace vx::tools {

using namespace vx::world;

namespace {

// Built step by step: one long `+` chain trips a false -Wrestrict in GCC 12's std::string.
std::string corrupt_message(const std::string& path, ChunkCoord c, const std::string& problem) {
    std::string m = "'";
    m += store_display_name(path);
    m += "': chunk " + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
    m += " is corrupt (" + problem + "); run vx world info --check";
    return m;
}

} // namespace

Result<World> load_store_world(const std::string& path, std::optional<ChunkCoord> lo, std::optional<ChunkCoord> hi) {
    auto store = open_store({path, /*read_only=*/true, /*create=*/false, /*listen=*/false});
    if (!store)
        return Error{store.error()};
    auto coords = (*store)->list_coords();
    if (!coords)
        return Error{coords.error()};
    World w;
    for (const ChunkCoord& c : *coords) {
        if (lo && hi && (glm::any(glm::lessThan(c, *lo)) || glm::any(glm::greaterThan(c, *hi))))
            continue;
        auto r = (*store)->load(c);
        if (!r)
            return Error{r.error()};
        if (r->state == LoadState::Corrupt)
            return Error{corrupt_message(path, c, r->problem)};
        if (r->state == LoadState::Present)
            w.put_chunk(c, std::move(*r->chunk));
    }
    return w;
}

namespace {

// The meta an imported world's store carries: where it came from, what its ids mean (the table,
// for a later export: block_registry_text.h) and the names the engine holds a game's blocks to
// (a game with other blocks is refused).
Status write_world_meta(ChunkStore& store, const World& world, const std::string& source) {
    if (Status s = store.set_meta("source", source); !s)
        return s;
    if (Status s = store.set_meta("registry", registry_to_text(world.registry())); !s)
        return s;
    return store.set_meta("blocks", registry_names_text(world.registry()));
}

// A PostgreSQL world is replaced in one transaction: every chunk of `world` saved, every other
// stored chunk erased, the queue never committed early (no size bound), then one flush. A failure
// rolls it all back, so the database keeps the world it had.
Status replace_pg_world(const World& world, const std::string& uri, const std::string& source) {
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = false;
    info.max_pending_bytes = SIZE_MAX;
    info.max_pending_age = std::chrono::hours(24 * 365);
    auto store = PgStore::open(info);
    if (!store)
        return Error{store.error()};
    auto old = (*store)->list_coords();
    if (!old)
        return Error{old.error()};
    Status failure;
    world.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        if (failure.ok())
            failure = (*store)->save(c, chunk);
    });
    for (ChunkCoord c : *old)
        if (failure.ok() && !world.find_chunk(c))
            failure = (*store)->erase(c);
    if (failure.ok())
        failure = write_world_meta(**store, world, source);
    if (failure.ok())
        failure = (*store)->flush();
    if (failure.ok())
        std::fprintf(stderr, "wrote %zu chunks\n", world.chunk_count());
    return failure;
}

} // namespace

Status check_store_output(const std::string& path) {
    if (path.empty())
        return Error{"need --out WORLD"};
    if (is_pg_uri(path))
        return {};
    if (std::string why = output_file_problem(path); !why.empty())
        return Error{why + " (a world store is one SQLite file)"};
    return {};
}

namespace {

// Writes every chunk into a new SQLite store at `tmp`, flushed; the store is closed on return.
Status write_sqlite_world(const World& world, const std::string& tmp, const std::string& source) {
    auto store = SqliteStore::open({tmp});
    if (!store)
        return Error{store.error()};
    size_t done = 0;
    const size_t total = world.chunk_count();
    const bool bar = stderr_is_terminal(); // Piped: one line at the end instead.
    Status failure;
    world.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        if (!failure.ok())
            return;
        if (Status s = (*store)->save(c, chunk); !s)
            failure = s;
        ++done;
        if (bar && (done % 256 == 0 || done == total))
            std::fprintf(stderr, "\rwriting %zu/%zu chunks", done, total);
    });
    if (bar)
        std::fputc('\n', stderr);
    else
        std::fprintf(stderr, "wrote %zu chunks\n", total);
    if (failure.ok())
        failure = write_world_meta(**store, world, source);
    if (failure.ok())
        failure = (*store)->flush();
    return failure; // Closing the last connection checkpoints the WAL into the file and deletes it.
}

// Moves the finished store at `tmp` over `path`.
Status replace_sqlite_world(const std::string& tmp, const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(path, ec)) {
        // Fold the old world's WAL into its file first, so no stale -wal is applied to the new one.
        // Refused while a writer has it open (its lock), or a reader (its -wal stays).
        if (auto old = SqliteStore::open({path}); !old)
            return Error{"cannot replace '" + path + "': " + old.error()};
        if (fs::exists(path + "-wal", ec))
            return Error{"cannot replace '" + path + "': it is open in another process"};
    }
    // No writer may open the old world between the check and the rename (its edits would go to a
    // removed file).
    auto lock = FileLock::acquire(path);
    if (!lock)
        return Error{"cannot replace " + lock.error()};
    fs::rename(tmp, path, ec);
    if (ec)
        return Error{"cannot move the new world into place at '" + path + "': " + ec.message()};
    return {};
}

} // namespace

Status save_store_world(const World& world, const std::string& path, const std::string& source) {
    if (is_pg_uri(path))
        return replace_pg_world(world, path, source);
    if (Status s = check_store_output(path); !s)
        return s;
    namespace fs = std::filesystem;
    const std::string tmp = path + ".tmp-" + std::to_string(getpid());
    auto remove_tmp = [&tmp] {
        std::error_code ec;
        for (const char* suffix : {"", "-wal", "-shm"})
            fs::remove(tmp + suffix, ec);
    };
    remove_tmp();
    Status s = write_sqlite_world(world, tmp, source);
    if (s.ok())
        s = replace_sqlite_world(tmp, path);
    if (!s.ok())
        remove_tmp(); // No failure leaves the half-written store beside the world.
    std::error_code ec;
    fs::remove(lock_file_of(tmp), ec); // This process's own temporary's lock.
    return s;
}

} // namespace vx::tools
