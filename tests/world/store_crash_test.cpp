// Crash safety of every store backend (SQLite, PostgreSQL): a forked child saves and flushes chunks in rounds and reports each
// acknowledged flush through a pipe; the parent SIGKILLs it at a random moment, reopens the store
// and checks that every record verifies, holds an old or new version of its chunk, and that no
// acknowledged edit was lost. VX_STORE_CRASH_CYCLES (default 200) and VX_STORE_CRASH_SEED tune it.

#include <csignal>
#include <cstdlib>
#include <random>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "store_backend.h"
#include "store_test_util.h"
#include "world/store/store_open.h"

using namespace vx::world;
using vx::world::test::StoreSuite;
using vx::world::test::versioned_chunk;
using vx::world::test::versioned_chunk_version;

namespace {

constexpr int kCoords = 16;

ChunkCoord coord_of(int k) { return ChunkCoord(k % 4 - 2, k / 4 % 2, -(k / 8) * 1000); }

uint32_t env_u32(const char* name, uint32_t fallback) {
    const char* v = std::getenv(name);
    return v && *v ? uint32_t(std::strtoul(v, nullptr, 10)) : fallback;
}

// Child: round v writes version v of every coordinate in random batches (some commits happen
// early: tiny queue bound, tick with bound 0), then flush() and report v. Never returns.
[[noreturn]] void child_main(test::StoreBackend& backend, const std::string& world, uint32_t first_version,
                             int ack_fd, uint32_t seed) {
    test::StoreOptions o;
    o.max_pending_age = std::chrono::milliseconds(0);
    o.max_pending_bytes = size_t(12) << 10; // A few commits per round.
    std::unique_ptr<ChunkStore> opened = backend.open(world, o);
    if (!opened)
        _exit(3);
    ChunkStore& store = *opened;
    std::mt19937 rng(seed);
    for (uint32_t v = first_version;; ++v) {
        std::vector<int> order(kCoords);
        for (int k = 0; k < kCoords; ++k)
            order[size_t(k)] = k;
        std::shuffle(order.begin(), order.end(), rng);
        for (size_t i = 0; i < order.size();) {
            const size_t n = std::min(order.size() - i, size_t(1 + rng() % 8));
            std::vector<Chunk> chunks;
            std::vector<ChunkWrite> batch;
            for (size_t j = 0; j < n; ++j)
                chunks.push_back(versioned_chunk(coord_of(order[i + j]), v));
            for (size_t j = 0; j < n; ++j)
                batch.push_back({coord_of(order[i + j]), &chunks[j]});
            if (!store.save(batch) || (rng() % 8 == 0 && !store.tick(ChunkStore::Clock::now())))
                _exit(4);
            i += n;
        }
        if (!store.flush())
            _exit(5);
        if (write(ack_fd, &v, sizeof v) != sizeof v)
            _exit(6);
    }
}

struct CycleResult {
    bool any_ack = false;
    uint32_t last_ack = 0;
};

// Kills the child `delay_us` after its `acks_before_kill`-th acknowledged flush (counting acks
// instead of time keeps every cycle meaningful however slow the machine or the sanitizer).
CycleResult run_and_kill(test::StoreBackend& backend, const std::string& path, uint32_t first_version, uint32_t seed, int acks_before_kill,
                         int delay_us) {
    int fds[2];
    EXPECT_EQ(pipe(fds), 0);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        child_main(backend, path, first_version, fds[1], seed);
    }
    close(fds[1]);
    CycleResult out;
    uint32_t v;
    for (int i = 0; i < acks_before_kill && read(fds[0], &v, sizeof v) == sizeof v; ++i) {
        out.any_ack = true;
        out.last_ack = v;
    }
    usleep(useconds_t(delay_us));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status)) << "child exited early with status " << WEXITSTATUS(status);
    while (read(fds[0], &v, sizeof v) == sizeof v) {
        out.any_ack = true;
        out.last_ack = v;
    }
    close(fds[0]);
    return out;
}

} // namespace

TEST_P(StoreSuite, SigkillNeverLosesAcknowledgedEditsOrCorruptsRecords) {
    const uint32_t cycles = env_u32("VX_STORE_CRASH_CYCLES", 200);
    const uint32_t seed = env_u32("VX_STORE_CRASH_SEED", 20261122);
    std::mt19937 rng(seed);
    const std::string path = backend().new_world();
    uint32_t next_version = 1;
    uint32_t acked = 0; // Every coordinate holds at least this version (0: none acknowledged yet).
    uint64_t total_acks = 0, newer_than_ack = 0;
    for (uint32_t cycle = 0; cycle < cycles; ++cycle) {
        // Kill moments: 0-2 acknowledged flushes, then 0-10 ms: during open, mid-round, mid-commit,
        // between flushes.
        const int acks_before_kill = int(rng() % 3);
        const int delay_us = int(rng() % 10000);
        const CycleResult r = run_and_kill(backend(), path, next_version, rng(), acks_before_kill, delay_us);
        // The version being written when the child died; it is never reused afterwards.
        const uint32_t in_flight = r.any_ack ? r.last_ack + 1 : next_version;
        if (r.any_ack) {
            total_acks += r.last_ack - next_version + 1;
            acked = r.last_ack;
        }
        next_version = in_flight + 1;

        std::unique_ptr<ChunkStore> opened = backend().open(path, {});
        ASSERT_TRUE(opened) << "cycle " << cycle;
        ChunkStore& store = *opened;
        for (int k = 0; k < kCoords; ++k) {
            const ChunkCoord c = coord_of(k);
            vx::Result<ChunkLoad> load = store.load(c);
            ASSERT_TRUE(load.ok()) << load.error();
            ASSERT_NE(load->state, LoadState::Corrupt) << "cycle " << cycle << ": " << load->problem;
            if (load->state == LoadState::Absent) {
                ASSERT_EQ(acked, 0u) << "cycle " << cycle << ": acknowledged chunk " << k << " lost";
                continue;
            }
            const int64_t v = versioned_chunk_version(*load->chunk);
            ASSERT_GE(v, int64_t(acked)) << "cycle " << cycle << ": chunk " << k << " older than acknowledged";
            ASSERT_LE(v, int64_t(in_flight)) << "cycle " << cycle << ": chunk " << k << " from the future";
            ASSERT_TRUE(*load->chunk == versioned_chunk(c, uint32_t(v))) << "cycle " << cycle << ": content";
            newer_than_ack += v > int64_t(acked);
        }
        if (auto* sqlite = dynamic_cast<SqliteStore*>(&store)) {
            ASSERT_TRUE(sqlite->verify_database().ok()) << "cycle " << cycle;
        }
    }
    EXPECT_EQ(backend().quarantine_count(path), 0u);
    vx::Result<StoreCheck> check = check_world(path);
    ASSERT_TRUE(check.ok()) << check.error();
    EXPECT_EQ(check->corrupt, 0u);
    // The test must have exercised something: flushes acknowledged, and kills that landed after
    // unacknowledged commits (newer versions present) at least once over the run.
    EXPECT_GT(total_acks, 0u);
    RecordProperty("acknowledged_flushes", std::to_string(total_acks));
    RecordProperty("chunks_newer_than_ack", std::to_string(newer_than_ack));
    std::printf("crash test: %u cycles, %llu acknowledged flushes, %llu chunks newer than the last ack\n", cycles,
                (unsigned long long)total_acks, (unsigned long long)newer_than_ack);
}
