// PgStore's change notifications: other processes hear of commits, and missed ones are caught up.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "pg_store_test_util.h"
#include "pg_test_util.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"

using namespace vx::world;
using vx::world::test::open_pg;
using vx::world::test::sql;
using vx::world::test::wait_until;
using vx::world::test::versioned_chunk;
using Clock = std::chrono::steady_clock;

namespace {

// Waits (polling, bounded) until `store` reports a change of `c`; the time it took.
std::optional<double> wait_change(PgStore& store, ChunkCoord c, double timeout_s) {
    const auto start = Clock::now();
    std::vector<ChunkCoord> got;
    while (std::chrono::duration<double>(Clock::now() - start).count() < timeout_s) {
        store.poll_changes(got);
        if (std::find(got.begin(), got.end(), c) != got.end())
            return std::chrono::duration<double>(Clock::now() - start).count();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return std::nullopt;
}

// Commits chunk `probe` from `writer` until `reader` hears of it: its listener is up (bounded).
bool wait_listening(PgStore& writer, PgStore& reader, ChunkCoord probe) {
    for (int i = 0; i < 60; ++i) {
        if (!writer.save(probe, Chunk(BlockId(3 + i % 2))).ok() || !writer.flush().ok())
            return false;
        if (wait_change(reader, probe, 1.0))
            return true;
    }
    return false;
}

} // namespace

TEST(PgStore, OtherProcessesLearnOfCommitsQuickly) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto reader = open_pg(uri);
    // Let the listener connect (it starts in the background).
    for (int i = 0; i < 500 && !reader->health().connected; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const pid_t pid = fork();
    if (pid == 0) { // Another process writes one chunk.
        PgStoreCreateInfo info;
        info.uri = uri;
        info.listen = false;
        auto w = PgStore::open(info);
        _exit(w && (*w)->save({1, 2, 3}, Chunk(7)) && (*w)->flush() ? 0 : 1);
    }
    const std::optional<double> seen = wait_change(*reader, {1, 2, 3}, 10.0);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    ASSERT_TRUE(seen.has_value()) << "no notification within 10 s";
    // Its own commits are not reported back to it.
    ASSERT_TRUE(reader->save({5, 5, 5}, Chunk(2)).ok());
    ASSERT_TRUE(reader->flush().ok());
    EXPECT_FALSE(wait_change(*reader, {5, 5, 5}, 0.3).has_value());
    auto load = reader->load({1, 2, 3});
    ASSERT_TRUE(load.ok());
    EXPECT_EQ(load->state, LoadState::Present);
}

// A server restart cuts the listener off; commits made before it listens again send
// notifications nobody receives. The reader connects as its own role, kept out (NOLOGIN) while the
// writer commits, so its listener cannot be back in time by chance: only the catch-up on
// reconnect can report those chunks.
TEST(PgStore, ChangesMissedDuringAServerRestartAreCaughtUp) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const std::string db = uri.substr(uri.find(":///") + 4, uri.find('?') - uri.find(":///") - 4);
    const std::string role = "reader_" + db;
    sql(cluster->uri("postgres"), ("CREATE ROLE " + role + " SUPERUSER LOGIN").c_str());
    std::string reader_uri = uri;
    reader_uri.replace(reader_uri.find("user=vx"), 7, "user=" + role);

    std::vector<ChunkCoord> coords;
    for (int i = 0; i < 6; ++i)
        coords.push_back({i, 1, -i});
    auto writer = open_pg(uri);
    for (ChunkCoord c : coords)
        ASSERT_TRUE(writer->save(c, versioned_chunk(c, 1)).ok());
    ASSERT_TRUE(writer->flush().ok());
    auto reader = open_pg(reader_uri);
    ASSERT_TRUE(reader);
    for (ChunkCoord c : coords)
        ASSERT_EQ(reader->load(c)->state, LoadState::Present);
    const ChunkCoord created{50, 1, 50}; // Absent when the reader looked; created meanwhile.
    ASSERT_EQ(reader->load(created)->state, LoadState::Absent);
    // Wait until the reader's listener is up (it starts in the background): a commit reaches it.
    bool heard = false;
    for (int i = 0; i < 60 && !heard; ++i) {
        ASSERT_TRUE(writer->save({99, 0, 0}, Chunk(BlockId(3 + i % 2))).ok());
        ASSERT_TRUE(writer->flush().ok());
        heard = wait_change(*reader, {99, 0, 0}, 1.0).has_value();
    }
    ASSERT_TRUE(heard);
    EXPECT_FALSE(reader->health().listener_down);
    ASSERT_TRUE(reader->tick(Clock::now()).ok()); // The first catch-up (nothing changed).
    EXPECT_EQ(reader->health().caught_up, 0u);

    sql(cluster->uri("postgres"), ("ALTER ROLE " + role + " NOLOGIN").c_str());
    ASSERT_TRUE(cluster->stop());
    ASSERT_TRUE(cluster->start());
    for (ChunkCoord c : coords)
        ASSERT_TRUE(writer->save(c, versioned_chunk(c, 2)).ok());
    ASSERT_TRUE(writer->save(created, versioned_chunk(created, 2)).ok());
    vx::Status s = writer->flush(); // Reconnects at once.
    ASSERT_TRUE(s.ok()) << s.error();
    std::vector<ChunkCoord> got;
    (void)reader->tick(Clock::now());
    reader->poll_changes(got);
    EXPECT_TRUE(got.empty()) << "the reader cannot have heard of these commits yet";
    // Its listener cannot log in again: health says changes come late (it used to say nothing).
    EXPECT_TRUE(wait_until([&] { return reader->health().listener_down; }, 10.0));

    sql(cluster->uri("postgres"), ("ALTER ROLE " + role + " LOGIN").c_str());
    coords.push_back(created);
    const auto limit = Clock::now() + std::chrono::seconds(60); // The listener backs off up to 8 s.
    auto seen_all = [&] {
        for (ChunkCoord c : coords)
            if (std::find(got.begin(), got.end(), c) == got.end())
                return false;
        return true;
    };
    while (!seen_all() && Clock::now() < limit) {
        (void)reader->tick(Clock::now()); // Reconnects, then catches up.
        reader->poll_changes(got);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_TRUE(seen_all()) << got.size() << " of " << coords.size() << " changed chunks reported";
    EXPECT_EQ(reader->health().caught_up, coords.size());
    EXPECT_FALSE(reader->health().listener_down); // Caught up after it listened again.
    for (size_t i = 0; i + 1 < coords.size(); ++i) // And a reload gets the new records.
        EXPECT_TRUE(*reader->load(coords[i])->chunk == versioned_chunk(coords[i], 2)) << i;
}

// As above, but the reader has forgotten most versions (max_known_versions) of the chunks it
// still shows: a catch-up comparing only the versions it remembers missed the others (12 of 16
// in the review), which then stayed stale for ever. Now the catch-up asks for a resync. The gap:
// the reader's role is kept out (NOLOGIN) and its connections are cut.
TEST(PgStore, ChangesMissedWithForgottenVersionsAskForAResync) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const std::string db = uri.substr(uri.find(":///") + 4, uri.find('?') - uri.find(":///") - 4);
    const std::string role = "reader_" + db;
    const std::string admin = cluster->uri("postgres");
    sql(admin, ("CREATE ROLE " + role + " SUPERUSER LOGIN").c_str());
    std::vector<ChunkCoord> coords;
    for (int i = 0; i < 16; ++i)
        coords.push_back({i, 2, 0});
    auto writer = open_pg(uri);
    for (ChunkCoord c : coords)
        ASSERT_TRUE(writer->save(c, versioned_chunk(c, 1)).ok());
    ASSERT_TRUE(writer->flush().ok());
    PgStoreCreateInfo info;
    info.uri = uri;
    info.uri.replace(info.uri.find("user=vx"), 7, "user=" + role);
    info.max_known_versions = 4; // 16 loaded: most are forgotten.
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    PgStore& reader = **opened;
    for (ChunkCoord c : coords)
        ASSERT_EQ(reader.load(c)->state, LoadState::Present);
    ASSERT_TRUE(wait_listening(*writer, reader, {99, 0, 0}));
    ASSERT_TRUE(reader.tick(Clock::now()).ok()); // The first catch-up.
    std::vector<ChunkCoord> got;
    (void)reader.poll_changes(got);

    sql(admin, ("ALTER ROLE " + role + " NOLOGIN").c_str());
    sql(admin, ("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE usename = '" + role + "'").c_str());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (ChunkCoord c : coords)
        ASSERT_TRUE(writer->save(c, versioned_chunk(c, 2)).ok());
    ASSERT_TRUE(writer->flush().ok());
    sql(admin, ("ALTER ROLE " + role + " LOGIN").c_str());

    got.clear();
    bool resync = false;
    auto all_reported = [&] {
        for (ChunkCoord c : coords)
            if (std::find(got.begin(), got.end(), c) == got.end())
                return false;
        return true;
    };
    const auto limit = Clock::now() + std::chrono::seconds(30); // The listener backs off up to 8 s.
    while (!resync && !all_reported() && Clock::now() < limit) {
        (void)reader.tick(Clock::now()); // Reconnects, then catches up.
        resync = reader.poll_changes(got);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_TRUE(resync || all_reported()) << got.size() << " of " << coords.size() << " changed chunks reported";
    for (ChunkCoord c : coords) { // What a resync does: every held chunk is read again.
        vx::Result<ChunkLoad> load = reader.load(c);
        for (int i = 0; i < 200 && !load.ok(); ++i) { // The cut connection is noticed, then back.
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            load = reader.load(c);
        }
        ASSERT_TRUE(load.ok()) << load.error();
        EXPECT_TRUE(load->chunk && *load->chunk == versioned_chunk(c, 2)) << c.x;
    }
    // One at the first catch-up (the 16 were loaded, and most forgotten, before the listener
    // was up), one after the gap.
    EXPECT_EQ(reader.health().resyncs, 2u);
}

// A process that never polls (`vx world gen`, or coarse changes the engine never asks for) must
// not pile up every coordinate other processes commit: the same chunk committed again is pending
// once, and coarse changes are kept only once someone asked for them. Before, every notified
// coordinate was appended for ever (the review's 200k + 200k).
TEST(PgStore, PendingChangesAreDeduplicatedAndCoarseOnesKeptOnlyWhenAskedFor) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto reader = open_pg(uri), writer = open_pg(uri);
    ASSERT_TRUE(reader && writer);
    ASSERT_TRUE(wait_listening(*writer, *reader, {99, 0, 0}));
    const LodCoord coarse{2, {1, 1, 1}};
    for (uint32_t round = 1; round <= 5; ++round) { // One chunk (and one coarse chunk), 5 commits.
        ASSERT_TRUE(writer->save({7, 7, 7}, versioned_chunk({7, 7, 7}, round)).ok());
        ASSERT_TRUE(writer->save_lod(coarse, versioned_chunk(coarse.chunk, round)).ok());
        ASSERT_TRUE(writer->flush().ok());
    }
    ASSERT_TRUE(writer->save({8, 8, 8}, Chunk(BlockId(2))).ok()); // The last commit: heard after the others.
    ASSERT_TRUE(writer->flush().ok());
    std::vector<ChunkCoord> got;
    const auto limit = Clock::now() + std::chrono::seconds(10);
    while (std::find(got.begin(), got.end(), ChunkCoord(8, 8, 8)) == got.end() && Clock::now() < limit) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20)); // Polled rarely: pending piles up.
        reader->poll_changes(got);
    }
    EXPECT_EQ(std::count(got.begin(), got.end(), ChunkCoord(7, 7, 7)), 1) << "pending once, not once per commit";
    std::vector<LodCoord> lods;
    reader->poll_lod_changes(lods);
    EXPECT_TRUE(lods.empty()) << lods.size() << " coarse changes kept though nobody asked for them";
    // Asked for once, they are kept from then on.
    ASSERT_TRUE(writer->save_lod(coarse, versioned_chunk(coarse.chunk, 9)).ok());
    ASSERT_TRUE(writer->flush().ok());
    for (int i = 0; i < 500 && lods.empty(); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        reader->poll_lod_changes(lods);
    }
    ASSERT_EQ(lods.size(), 1u);
    EXPECT_EQ(lods[0], coarse);
}

// More pending changes than the store keeps: they are forgotten and poll_changes() says so, which
// makes the engine re-check every chunk it holds (chunk_streamer_jobs.cpp, poll_store_changes)
// instead of missing some.
TEST(PgStore, TooManyPendingChangesAskForAResync) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    info.max_pending_changes = 8;
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    PgStore& reader = **opened;
    auto writer = open_pg(uri);
    ASSERT_TRUE(wait_listening(*writer, reader, {99, 0, 0}));
    std::vector<ChunkCoord> got;
    EXPECT_FALSE(reader.poll_changes(got));
    std::vector<ChunkWrite> batch;
    const Chunk stone(3);
    for (int i = 0; i < 20; ++i) // 20 > 8 chunks in one commit.
        batch.push_back({ChunkCoord(i, 0, 0), &stone});
    ASSERT_TRUE(writer->save(batch).ok());
    ASSERT_TRUE(writer->flush().ok());
    bool resync = false;
    for (int i = 0; i < 500 && !resync; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        got.clear();
        resync = reader.poll_changes(got);
    }
    EXPECT_TRUE(resync);
    EXPECT_LE(got.size(), 8u);
    got.clear();
    EXPECT_FALSE(reader.poll_changes(got)) << "said once";
}

// Coarse chunks committed by another process are notified with their level ("lod;level,x,y,z;"
// payloads), apart from the level-0 changes of the same commit: a listener reading only level-0
// payloads (a build before coarse levels) finds no number at "lod;" and ignores the payload.
TEST(PgStore, CoarseChangesAreNotifiedWithTheirLevel) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto reader = open_pg(uri);
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = false;
    auto writer = PgStore::open(info);
    ASSERT_TRUE(writer) << writer.error();
    const LodCoord coarse{3, {-2, 0, 7}};
    std::vector<LodCoord> lods;
    std::vector<ChunkCoord> chunks;
    // The listener connects in the background: commit again until one is heard (bounded).
    const auto start = Clock::now();
    bool heard = false;
    for (uint32_t round = 1; !heard && Clock::now() - start < std::chrono::seconds(10); ++round) {
        ASSERT_TRUE((*writer)->save_lod(coarse, versioned_chunk(coarse.chunk, round)).ok());
        ASSERT_TRUE((*writer)->save({4, 5, 6}, versioned_chunk({4, 5, 6}, round)).ok());
        ASSERT_TRUE((*writer)->flush().ok());
        for (int i = 0; i < 100 && !heard; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            reader->poll_lod_changes(lods);
            heard = !lods.empty();
        }
    }
    ASSERT_TRUE(heard) << "no coarse notification within 10 s";
    for (const LodCoord& c : lods)
        EXPECT_EQ(c, coarse);
    for (int i = 0; i < 500 && chunks.empty(); ++i) { // Sent in the same commit: already there.
        reader->poll_changes(chunks);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_FALSE(chunks.empty());
    for (ChunkCoord c : chunks)
        EXPECT_EQ(c, ChunkCoord(4, 5, 6)); // No coordinates made up from the coarse payloads.
    auto load = reader->load_lod(coarse);
    ASSERT_TRUE(load.ok()) << load.error();
    EXPECT_EQ(load->state, LoadState::Present);
}

// The listener connects with the URI too: without vx's parameters, or libpq refuses it and the
// store never hears other processes (the store's own connection worked).
TEST(PgStore, AStoreOpenedWithVxUriParametersHearsOtherProcesses) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto writer = open_pg(uri);
    auto reader = open_pg(uri + "&vx_query_timeout_ms=5000");
    ASSERT_TRUE(writer && reader);
    EXPECT_TRUE(wait_listening(*writer, *reader, {7, 0, 7}));
}
