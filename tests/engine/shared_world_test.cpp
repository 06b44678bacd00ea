// A world shared across processes through PostgreSQL, end to end through the facade: two
// processes generate and edit one world at once (blocks of the same chunk included), each sees
// the other's edits, nothing is lost; the server restarted under a running engine loses nothing;
// edits made while an engine could not reconnect reach it once it does; and shutdown with the server away flushes once. Uses the throwaway cluster of
// tests/world/pg_cluster.h (skips, with a line, without PostgreSQL's server binaries). No GPU
// (RenderTarget::none).
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include <vx/vx.h>

#include "engine/chunk_streamer.h"
#include "facade_test_util.h"
#include "world/gen/terrain.h"
#include "world/store/pg_store.h"

#include "pg_cluster.h"

using Clock = std::chrono::steady_clock;
using vx::world::test::PgCluster;

namespace {

using vx::test::settle;

constexpr uint64_t kSeed = 11;

vx::EngineCreateInfo shared_info(const std::string& uri) {
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::sqlite(uri, kSeed);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 1;
    info.streaming.save_delay_s = 0.05;
    return info;
}

// Updates until `p` holds `id` (true) or `timeout_s` passes.
bool wait_block(vx::Engine& e, vx::BlockPos p, vx::BlockId id, double timeout_s) {
    const auto limit = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (Clock::now() < limit) {
        e.update();
        if (e.get_block(p) == id)
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
}

// The blocks a process edits: a row in the chunk both use (x 4..11 or 20..27 of chunk (0,0,0),
// high in the air so the terrain does not hide them) and a chunk of its own.
std::vector<vx::BlockPos> edits_of(int who) {
    std::vector<vx::BlockPos> out;
    for (int i = 0; i < 8; ++i)
        out.push_back({(who == 0 ? 4 : 20) + i, 30, 5});
    out.push_back({who == 0 ? -20 : 40, 30, 9});
    return out;
}

vx::Viewer viewer() {
    vx::Viewer v;
    v.block = {0, 30, 0};
    v.forward = {1, 0, 0};
    return v;
}

PgCluster* cluster_or_skip() {
    std::string why;
    PgCluster* c = PgCluster::get(&why);
    if (!c)
        std::printf("shared-world tests skipped: %s\n", why.c_str());
    return c;
}

} // namespace

TEST(SharedWorld, TwoProcessesEditOneWorldAndSeeEachOther) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    const vx::BlockId stone = 1, glass = 6;
    int ready[2], go[2];
    ASSERT_EQ(pipe(ready), 0);
    ASSERT_EQ(pipe(go), 0);
    const pid_t pid = fork();
    if (pid == 0) { // The other process: edits, then waits to see the parent's edits.
        auto created = vx::Engine::create(shared_info(uri));
        if (!created)
            _exit(10);
        vx::Engine& e = **created;
        e.set_viewer(viewer());
        if (!settle(e))
            _exit(11);
        for (vx::BlockPos p : edits_of(1))
            if (!e.set_block(p, glass))
                _exit(12);
        auto t = e.save();
        if (!t || !e.wait(*t))
            _exit(13);
        char byte = 1;
        if (write(ready[1], &byte, 1) != 1 || read(go[0], &byte, 1) != 1)
            _exit(14);
        for (vx::BlockPos p : edits_of(0))
            if (!wait_block(e, p, stone, 20.0))
                _exit(15);
        _exit(e.shutdown() ? 0 : 16);
    }
    auto created = vx::Engine::create(shared_info(uri));
    ASSERT_TRUE(created) << created.error();
    vx::Engine& e = **created;
    ASSERT_TRUE(e.set_viewer(viewer()));
    ASSERT_TRUE(settle(e));
    for (vx::BlockPos p : edits_of(0)) // The same chunk as the child's row, at the same time.
        ASSERT_TRUE(e.set_block(p, stone));
    auto ticket = e.save();
    ASSERT_TRUE(ticket);
    ASSERT_TRUE(e.wait(*ticket));
    char byte = 0;
    ASSERT_EQ(read(ready[0], &byte, 1), 1);
    // The child's edits arrive through the change feed (reload + remesh), ours stay.
    for (vx::BlockPos p : edits_of(1))
        EXPECT_TRUE(wait_block(e, p, glass, 20.0)) << "child's edit at " << p.x << "," << p.y << "," << p.z;
    for (vx::BlockPos p : edits_of(0))
        EXPECT_EQ(e.get_block(p), stone);
    ASSERT_EQ(write(go[1], &byte, 1), 1);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status)) << "child died";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "child step " << WEXITSTATUS(status) << " failed";
    ASSERT_TRUE(e.shutdown());

    // Nothing lost: a third engine reads every edit of both from the server.
    auto again = vx::Engine::create(shared_info(uri));
    ASSERT_TRUE(again);
    ASSERT_TRUE((*again)->set_viewer(viewer()));
    ASSERT_TRUE(settle(**again));
    for (vx::BlockPos p : edits_of(0))
        EXPECT_EQ((*again)->get_block(p), stone);
    for (vx::BlockPos p : edits_of(1))
        EXPECT_EQ((*again)->get_block(p), glass);
}

// Updates `e` until its stats satisfy `want` (bounded by timeout_s); whether they did.
template <class Want> bool stats_become(vx::Engine& e, Want want, double timeout_s) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (!want(e.stats()) && std::chrono::steady_clock::now() < limit) {
        e.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return want(e.stats());
}

TEST(SharedWorld, ServerRestartUnderARunningEngineLosesNothing) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    auto created = vx::Engine::create(shared_info(uri));
    ASSERT_TRUE(created) << created.error();
    vx::Engine& e = **created;
    ASSERT_TRUE(e.set_viewer(viewer()));
    ASSERT_TRUE(settle(e));
    ASSERT_TRUE(e.set_block({1, 30, 1}, 3));
    auto first = e.save();
    ASSERT_TRUE(first && e.wait(*first));

    ASSERT_TRUE(cluster->stop());
    ASSERT_TRUE(e.set_block({2, 30, 1}, 4)); // Edits go on while the server is away.
    auto during = e.save();
    ASSERT_TRUE(during);
    EXPECT_FALSE(e.wait(*during)) << "a save cannot be durable without the server";
    for (int i = 0; i < 20; ++i) { // The engine keeps running.
        e.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_FALSE(e.stats().store_connected);
    EXPECT_GE(e.stats().store_pending_edits, 1u);
    EXPECT_EQ(e.get_block({2, 30, 1}), 4);
    // The change listener lost its server too: the game is told others' changes come late.
    EXPECT_TRUE(stats_become(e, [](const vx::Stats& st) { return st.store_listener_down; }, 10.0));

    ASSERT_TRUE(cluster->start());
    auto after = e.save();
    ASSERT_TRUE(after);
    vx::Status s = e.wait(*after);
    ASSERT_TRUE(s) << s.error();
    EXPECT_TRUE(e.stats().store_connected);
    // The listener reconnects by itself (its back-off is at most 8 s).
    EXPECT_TRUE(stats_become(e, [](const vx::Stats& st) { return !st.store_listener_down; }, 30.0));
    ASSERT_TRUE(e.shutdown());

    auto again = vx::Engine::create(shared_info(uri));
    ASSERT_TRUE(again);
    ASSERT_TRUE((*again)->set_viewer(viewer()));
    ASSERT_TRUE(settle(**again));
    EXPECT_EQ((*again)->get_block({1, 30, 1}), 3);
    EXPECT_EQ((*again)->get_block({2, 30, 1}), 4);
}

// Engine B cannot log in while the server restarts (its role is blocked, as a network split
// would keep it away) and engine A edits and saves meanwhile: the notifications of A's commits
// never reach B. Once B reconnects, its store compares the versions it knows with the table and
// B reloads the chunks A changed: it shows A's blocks and counts the reloads.
TEST(SharedWorld, EditsMadeWhileAnEngineWasAwayReachItAfterItReconnects) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    const std::string db = uri.substr(uri.find(":///") + 4, uri.find('?') - uri.find(":///") - 4);
    const std::string role = "engine_b_" + db;
    auto run_sql = [&](const std::string& statement) {
        PGconn* c = PQconnectdb(cluster->uri("postgres").c_str());
        PGresult* r = PQexec(c, statement.c_str());
        EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(c);
        PQclear(r);
        PQfinish(c);
    };
    run_sql("CREATE ROLE " + role + " SUPERUSER LOGIN");
    std::string uri_b = uri;
    uri_b.replace(uri_b.find("user=vx"), 7, "user=" + role);

    auto created_a = vx::Engine::create(shared_info(uri));
    ASSERT_TRUE(created_a) << created_a.error();
    auto created_b = vx::Engine::create(shared_info(uri_b));
    ASSERT_TRUE(created_b) << created_b.error();
    vx::Engine& a = **created_a;
    vx::Engine& b = **created_b;
    ASSERT_TRUE(a.set_viewer(viewer()) && b.set_viewer(viewer()));
    ASSERT_TRUE(settle(a));
    ASSERT_TRUE(settle(b));
    // B hears A's commits (its listener is up) before the restart.
    const vx::BlockId stone = 1, glass = 6;
    ASSERT_TRUE(a.set_block({1, 30, 1}, stone));
    auto first = a.save();
    ASSERT_TRUE(first && a.wait(*first));
    ASSERT_TRUE(wait_block(b, {1, 30, 1}, stone, 20.0));
    const uint64_t reloaded_before = b.stats().chunks_reloaded;

    run_sql("ALTER ROLE " + role + " NOLOGIN");
    ASSERT_TRUE(cluster->stop());
    for (vx::BlockPos p : edits_of(0)) // Edits while the server is away...
        ASSERT_TRUE(a.set_block(p, glass));
    ASSERT_TRUE(cluster->start());
    auto saved = a.save(); // ...saved once it is back (A reconnects; B cannot).
    ASSERT_TRUE(saved);
    vx::Status s = a.wait(*saved);
    ASSERT_TRUE(s) << s.error();
    for (int i = 0; i < 20; ++i) {
        b.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    for (vx::BlockPos p : edits_of(0))
        EXPECT_NE(b.get_block(p), glass) << "B cannot have heard of A's edits yet";

    run_sql("ALTER ROLE " + role + " LOGIN");
    for (vx::BlockPos p : edits_of(0)) // The listener backs off up to 8 s between attempts.
        EXPECT_TRUE(wait_block(b, p, glass, 60.0)) << "A's edit at " << p.x << "," << p.y << "," << p.z;
    // edits_of(0) spans two chunks: both reloaded.
    EXPECT_GE(b.stats().chunks_reloaded, reloaded_before + 2);
    EXPECT_EQ(b.get_block({1, 30, 1}), stone);
    ASSERT_TRUE(a.shutdown());
    ASSERT_TRUE(b.shutdown());
}

namespace {

struct NullSink : vx::engine::MeshSink {
    void on_mesh(vx::world::ChunkCoord, const vx::world::ChunkMesh&, std::span<const int>) override {}
    void on_unload(vx::world::ChunkCoord) override {}
};

} // namespace

// Engine::shutdown with the server away: the streamer's flush fails (reported), and destroying
// the streamer does not flush again (which would spend a second connect timeout on the same
// error): one connection attempt in all. The edit acknowledged as saved before is on the server;
// the later one is reported as not saved, never claimed. Runs the shutdown's steps (flush,
// streamer, store) on a store the test owns, to count its connection attempts.
TEST(SharedWorld, ShutdownWithTheServerAwayFlushesOnce) {
    using namespace vx::world;
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    std::unique_ptr<PgStore> store = std::move(*opened);
    const TerrainGenerator gen(kSeed);
    NullSink sink;
    vx::engine::StreamingSettings settings;
    settings.view_radius = 1;
    settings.view_radius_vertical = 1;
    settings.worker_count = 1;
    auto streamer = std::make_unique<vx::engine::ChunkStreamer>(gen, store.get(), sink, settings);
    const glm::dvec3 eye(16, 40, 16);
    for (auto limit = Clock::now() + std::chrono::minutes(3); !streamer->settled() && Clock::now() < limit;) {
        streamer->update(eye, glm::dvec3(1, 0, 0), Clock::now());
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(streamer->settled());
    ASSERT_TRUE(streamer->set_block({5, 40, 5}, 3));
    ASSERT_TRUE(streamer->flush()); // Acknowledged.

    ASSERT_TRUE(cluster->stop());
    ASSERT_TRUE(streamer->set_block({-5, 40, 5}, 4)); // Another chunk, never acknowledged.
    EXPECT_FALSE(streamer->flush()); // The store learns the server is gone.
    const uint64_t before = store->health().connect_attempts;
    EXPECT_FALSE(streamer->flush()); // What Engine::shutdown does, then:
    streamer.reset();
    EXPECT_EQ(store->health().connect_attempts, before + 1) << "one flush, one connection attempt";
    EXPECT_GE(store->pending_edits(), 1u); // Still reported: not saved.
    store.reset(); // Logs the edits it could not save; tries no connection.

    ASSERT_TRUE(cluster->start());
    PgStoreCreateInfo again;
    again.uri = uri;
    again.listen = false;
    auto reopened = PgStore::open(again);
    ASSERT_TRUE(reopened.ok()) << reopened.error();
    auto load = (*reopened)->load(vx::world::chunk_of(vx::world::BlockPos(5, 40, 5)));
    ASSERT_TRUE(load.ok() && load->chunk);
    EXPECT_EQ(load->chunk->get(vx::world::local_of(vx::world::BlockPos(5, 40, 5))), 3);
}

// The facade's world URI carries vx's query timeout (vx_query_timeout_ms): an engine opens the
// world with it, saves, and a bad value fails Engine::create with a message naming it. libpq used
// to refuse the URI whatever the value.
TEST(SharedWorld, TheWorldUriCarriesTheQueryTimeout) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    {
        auto created = vx::Engine::create(shared_info(uri + "&vx_query_timeout_ms=3000"));
        ASSERT_TRUE(created.ok()) << created.error();
        vx::Engine& e = **created;
        e.set_viewer(viewer());
        ASSERT_TRUE(settle(e));
        ASSERT_TRUE(e.set_block({4, 30, 5}, 6));
        auto t = e.save();
        ASSERT_TRUE(t && e.wait(*t));
    }
    auto bad = vx::Engine::create(shared_info(uri + "&vx_query_timeout_ms=0"));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().find("vx_query_timeout_ms must be a whole number of milliseconds"), std::string::npos)
        << bad.error();
}
