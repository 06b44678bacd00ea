// PostgreSQL-only behaviour of PgStore: refusing foreign databases, concurrent writers of one
// chunk keeping both edits, change notifications, and a server restart under a running writer.
// The backend-independent suite (store_suite_test.cpp, store_crash_test.cpp) runs here as well.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "pg_cluster.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"
#include "world/store/store_open.h"

using namespace vx::world;
using vx::world::test::PgCluster;
using vx::world::test::versioned_chunk;
using Clock = std::chrono::steady_clock;

namespace {

PgCluster* cluster_or_skip() {
    std::string why;
    PgCluster* c = PgCluster::get(&why);
    if (!c)
        std::printf("PostgreSQL tests skipped: %s\n", why.c_str());
    return c;
}

#define VX_NEED_PG()                                                                                                  \
    PgCluster* cluster = cluster_or_skip();                                                                           \
    if (!cluster)                                                                                                     \
    GTEST_SKIP() << "no PostgreSQL cluster (see the line above)"

std::unique_ptr<PgStore> open_pg(const std::string& uri) {
    PgStoreCreateInfo info;
    info.uri = uri;
    auto s = PgStore::open(info);
    EXPECT_TRUE(s.ok()) << s.error();
    return s.ok() ? std::move(*s) : nullptr;
}

void sql(const std::string& uri, const char* statement) {
    PGconn* c = PQconnectdb(uri.c_str());
    PGresult* r = PQexec(c, statement);
    EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(c);
    PQclear(r);
    PQfinish(c);
}

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

} // namespace

TEST(PgStore, UriHelpers) {
    EXPECT_TRUE(is_pg_uri("postgresql://h/db"));
    EXPECT_TRUE(is_pg_uri("postgres:///db?host=/tmp"));
    EXPECT_FALSE(is_pg_uri("worlds/postgresql.db"));
    EXPECT_EQ(redact_pg_uri("postgresql://ann:secret@host:5/db"), "postgresql://ann:***@host:5/db");
    EXPECT_EQ(redact_pg_uri("postgresql:///db?user=a&password=pw&host=/tmp"),
              "postgresql:///db?user=a&password=***&host=/tmp");
    EXPECT_EQ(redact_pg_uri("postgresql://ann@host/db"), "postgresql://ann@host/db");
}

TEST(PgStore, ClearErrorsForMissingAndForeignDatabases) {
    VX_NEED_PG();
    PgStoreCreateInfo info;
    info.uri = cluster->uri("no_such_database");
    auto missing = PgStore::open(info);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().find("cannot connect"), std::string::npos) << missing.error();
    EXPECT_NE(missing.error().find("no_such_database"), std::string::npos) << missing.error();

    const std::string foreign = cluster->new_database();
    sql(foreign, "CREATE TABLE songs(title text)");
    info.uri = foreign;
    auto refused = PgStore::open(info);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("other tables"), std::string::npos) << refused.error();

    // Through the generic opener too (as every tool opens worlds).
    auto generic = open_store({foreign});
    ASSERT_FALSE(generic.ok());
    EXPECT_NE(generic.error().find("refusing"), std::string::npos) << generic.error();
}

TEST(PgStore, TwoWritersOfOneChunkBothKeepTheirEdits) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const ChunkCoord c{4, -1, 7};
    {
        auto seed = open_pg(uri);
        ASSERT_TRUE(seed->save(c, versioned_chunk(c, 1)).ok());
        ASSERT_TRUE(seed->flush().ok());
    }
    auto a = open_pg(uri), b = open_pg(uri);
    Chunk ca = *a->load(c)->chunk, cb = *b->load(c)->chunk;
    EXPECT_EQ(a->known_version(c), 1u);
    // Different blocks of the same chunk, edited by each writer from the same version.
    const BlockEdit ea[] = {{{3, 20, 3}, 9}, {{4, 20, 3}, 9}};
    const BlockEdit eb[] = {{{10, 25, 30}, 11}};
    for (const BlockEdit& e : ea)
        ca.set(e.pos, e.id);
    for (const BlockEdit& e : eb)
        cb.set(e.pos, e.id);
    const ChunkWrite wa{c, &ca, ea}, wb{c, &cb, eb};
    ASSERT_TRUE(a->save(std::span(&wa, 1)).ok());
    ASSERT_TRUE(b->save(std::span(&wb, 1)).ok());
    ASSERT_TRUE(a->flush().ok());
    ASSERT_TRUE(b->flush().ok()); // Finds version 2 (a's), re-applies its edit on top.
    EXPECT_EQ(b->health().conflicts, 1u);
    EXPECT_EQ(a->health().conflicts, 0u);
    std::vector<ChunkCoord> merged;
    b->poll_changes(merged); // b's in-memory copy lacks a's edits: it is told to reload.
    EXPECT_NE(std::find(merged.begin(), merged.end(), c), merged.end());

    auto check = open_pg(uri);
    const Chunk stored = *check->load(c)->chunk;
    EXPECT_EQ(check->known_version(c), 3u);
    EXPECT_EQ(stored.get(LocalPos(3, 20, 3)), 9);
    EXPECT_EQ(stored.get(LocalPos(4, 20, 3)), 9);
    EXPECT_EQ(stored.get(LocalPos(10, 25, 30)), 11);
    Chunk want = versioned_chunk(c, 1);
    want.set(LocalPos(3, 20, 3), 9);
    want.set(LocalPos(4, 20, 3), 9);
    want.set(LocalPos(10, 25, 30), 11);
    EXPECT_TRUE(stored == want); // Nothing else changed.
}

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

TEST(PgStore, ServerRestartUnderARunningWriterLosesNothing) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto store = open_pg(uri);
    ASSERT_TRUE(store->save({0, 0, 0}, versioned_chunk({0, 0, 0}, 1)).ok());
    ASSERT_TRUE(store->flush().ok());
    ASSERT_TRUE(cluster->stop());
    // Edits while the server is gone stay queued; flush says why it cannot make them durable.
    for (int i = 1; i <= 5; ++i)
        ASSERT_TRUE(store->save({i, 0, 0}, versioned_chunk({i, 0, 0}, 1)).ok());
    vx::Status down = store->flush();
    ASSERT_FALSE(down.ok());
    EXPECT_NE(down.error().find("edits kept in memory"), std::string::npos) << down.error();
    EXPECT_FALSE(store->health().connected);
    EXPECT_EQ(store->pending_edits(), 5u);
    EXPECT_FALSE(store->load({9, 9, 9}).ok()); // A load cannot say "absent" while the server is away.
    ASSERT_TRUE(cluster->start());
    vx::Status up = store->flush();
    ASSERT_TRUE(up.ok()) << up.error();
    EXPECT_TRUE(store->health().connected);
    EXPECT_GE(store->health().reconnects, 1u);
    auto check = open_pg(uri);
    EXPECT_EQ(*check->count(), 6u);
    for (int i = 0; i <= 5; ++i)
        EXPECT_TRUE(*check->load({i, 0, 0})->chunk == versioned_chunk({i, 0, 0}, 1));
}

TEST(PgStore, ForgottenVersionsCostAConflictButLoseNothing) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    info.max_known_versions = 4; // Forget down to 2 once 5 are known.
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    PgStore& store = **opened;
    std::vector<ChunkCoord> coords;
    for (int i = 0; i < 12; ++i)
        coords.push_back({i, 0, -i});
    for (ChunkCoord c : coords)
        ASSERT_TRUE(store.save(c, versioned_chunk(c, 1)).ok());
    ASSERT_TRUE(store.flush().ok());
    size_t known = 0;
    for (ChunkCoord c : coords)
        known += store.known_version(c) != 0;
    EXPECT_LE(known, 4u); // Bounded, not one entry per chunk ever seen.

    // Edit every chunk from a fresh load; some versions get forgotten again on the way.
    for (ChunkCoord c : coords) {
        Chunk chunk = *store.load(c)->chunk;
        const BlockEdit e{{1, 2, 3}, 7};
        chunk.set(e.pos, e.id);
        const ChunkWrite w{c, &chunk, std::span(&e, 1)};
        ASSERT_TRUE(store.save(std::span(&w, 1)).ok());
    }
    ASSERT_TRUE(store.flush().ok());
    auto check = open_pg(uri);
    for (ChunkCoord c : coords) {
        Chunk want = versioned_chunk(c, 1);
        want.set(LocalPos(1, 2, 3), 7);
        EXPECT_TRUE(*check->load(c)->chunk == want) << c.x;
    }
}
