// PostgreSQL-only behaviour of PgStore: refusing foreign databases, concurrent writers of one
// chunk keeping both edits, change notifications (and catching up on those missed while the server
// restarted), overlapping writers without deadlocks, and a server restart under a running writer.
// The backend-independent suite (store_suite_test.cpp, store_crash_test.cpp) runs here as well.
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <barrier>
#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <vx/log.h>

#include "pg_test_util.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"
#include "world/store/pg_wire.h"
#include "world/store/store_open.h"

using namespace vx::world;
namespace pg = vx::world::pg;
using vx::world::test::PgCluster;
using vx::world::test::wait_until;
using vx::world::test::versioned_chunk;
using Clock = std::chrono::steady_clock;

namespace {

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
    EXPECT_TRUE(PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK) << PQerrorMessage(c);
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

// Stops (SIGSTOP) the backends of a database's vx connections and the postmaster: the server
// is alive (keepalives pass) but answers nothing, as a frozen host or a stuck disk. thaw()
// (SIGCONT) is idempotent and runs on destruction, so a failed assertion never leaves it stopped;
// a watchdog thaws it after 8 s, so a build whose call waits for the server does not hang the test.
class FrozenServer {
public:
    explicit FrozenServer(const std::string& uri) {
        PGconn* c = PQconnectdb(uri.c_str());
        pg::ResultPtr r(PQexec(c, "SELECT pid FROM pg_stat_activity "
                                  "WHERE datname = current_database() AND application_name = 'vx'"));
        for (int i = 0; i < PQntuples(r.get()); ++i)
            m_pids.push_back(std::atoi(PQgetvalue(r.get(), i, 0)));
        PQfinish(c);
        if (!m_pids.empty())
            m_pids.push_back(parent_of(m_pids[0])); // The postmaster: no new backend either.
        for (int pid : m_pids)
            ::kill(pid, SIGSTOP);
        m_watchdog = std::thread([this] {
            for (int i = 0; i < 800 && !m_done.load(); ++i)
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            thaw();
        });
    }
    ~FrozenServer() {
        m_done.store(true);
        m_watchdog.join();
        thaw();
    }
    const std::vector<int>& pids() const { return m_pids; }
    void thaw() {
        for (int pid : m_pids)
            ::kill(pid, SIGCONT);
    }

private:
    static int parent_of(int pid) {
        std::ifstream status("/proc/" + std::to_string(pid) + "/status");
        for (std::string line; std::getline(status, line);)
            if (line.starts_with("PPid:"))
                return std::atoi(line.c_str() + 5);
        return 0;
    }
    std::vector<int> m_pids;
    std::atomic<bool> m_done{false};
    std::thread m_watchdog;
};

// After a failed flush: the edit of chunk (0, 0, 0) to Chunk(6) is still queued, and the next
// flush commits it (a second connection reads it back).
void expect_kept_then_committed(ChunkStore& store, const std::string& uri) {
    EXPECT_EQ(store.pending_edits(), 1u);
    vx::Status again = store.flush();
    ASSERT_TRUE(again.ok()) << again.error();
    auto check = open_pg(uri);
    EXPECT_TRUE(*check->load({0, 0, 0})->chunk == Chunk(6));
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
    // A password holding '/' or '@' (libpq reads them unencoded), a percent-encoded parameter name
    // (libpq decodes names too), key=value strings with spaces and quotes: all once leaked.
    EXPECT_EQ(redact_pg_uri("postgresql://ann:se/cr@t@host:5/db"), "postgresql://ann:***@host:5/db");
    EXPECT_EQ(redact_pg_uri("postgresql:///db?user=a&pass%77ord=pw&host=/tmp"),
              "postgresql:///db?user=a&pass%77ord=***&host=/tmp");
    EXPECT_EQ(redact_pg_uri("postgres:///db?%70assword=pw"), "postgres:///db?%70assword=***");
    EXPECT_EQ(redact_pg_uri("host=/tmp password = 'se cr\\'et' user=a"), "host=/tmp password = *** user=a");
    EXPECT_EQ(redact_pg_uri("dbname=w password=pw"), "dbname=w password=***");
}

// Both connections get TCP keepalives and a user timeout (a dead peer is noticed), and a URI's
// own connect_timeout wins over the store's default (it used to be overridden).
TEST(PgStore, ConnectionsKeepAliveAndTheUriWins) {
    VX_NEED_PG();
    const std::string uri = cluster->uri("postgres") + "&connect_timeout=7&keepalives_idle=42";
    for (bool polling : {false, true}) {
        PGconn* conn = polling ? pg::connect_start(uri, 3) : pg::connect(uri, 3);
        ASSERT_NE(conn, nullptr);
        std::map<std::string, std::string> options;
        PQconninfoOption* info = PQconninfo(conn);
        for (PQconninfoOption* o = info; o && o->keyword; ++o)
            options[o->keyword] = o->val ? o->val : "";
        PQconninfoFree(info);
        PQfinish(conn);
        EXPECT_EQ(options["connect_timeout"], "7");
        EXPECT_EQ(options["keepalives_idle"], "42");
        EXPECT_EQ(options["keepalives"], "1");
        EXPECT_EQ(options["keepalives_interval"], "5");
        EXPECT_EQ(options["keepalives_count"], "3");
        EXPECT_EQ(options["tcp_user_timeout"], "30000");
        EXPECT_EQ(options["application_name"], "vx");
    }
}

// Another session holds a row lock (idle in transaction): the commit fails after lock_timeout,
// keeps its edits and commits once the lock is gone. It used to block the I/O lane for as long as
// the lock was held (here 4 s; in the field for ever).
TEST(PgStore, ALockedRowFailsACommitInsteadOfBlockingIt) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = false;
    info.lock_timeout = std::chrono::milliseconds(200);
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    PgStore& store = **opened;
    ASSERT_TRUE(store.save({0, 0, 0}, Chunk(5)).ok());
    ASSERT_TRUE(store.flush().ok());
    PGconn* other = PQconnectdb(uri.c_str());
    pg::ResultPtr(PQexec(other, "BEGIN"));
    pg::ResultPtr locked(PQexec(other, "SELECT * FROM vx_chunks FOR UPDATE"));
    ASSERT_EQ(PQresultStatus(locked.get()), PGRES_TUPLES_OK) << PQerrorMessage(other);
    std::atomic<bool> returned{false};
    std::thread release([&] { // After the flush returned, or after 4 s on a build that blocks.
        for (int i = 0; i < 400 && !returned.load(); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        pg::ResultPtr(PQexec(other, "ROLLBACK"));
    });
    ASSERT_TRUE(store.save({0, 0, 0}, Chunk(6)).ok());
    const auto t0 = Clock::now();
    vx::Status s = store.flush();
    const double waited = std::chrono::duration<double>(Clock::now() - t0).count();
    returned.store(true);
    release.join();
    PQfinish(other);
    EXPECT_LT(waited, 2.0) << "the commit waited for the lock";
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().find("lock timeout"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("edits kept in memory"), std::string::npos) << s.error();
    EXPECT_TRUE(store.health().connected);
    expect_kept_then_committed(store, uri);
}

// The server frozen (SIGSTOP) while two stores are connected: a flush (a pipelined commit) and a
// load each fail within query_timeout with an error naming it, the edit is kept, a flush while
// still frozen fails within connect_timeout, and once the server runs again the next flush commits
// the edit. They used to block until the server woke (here the watchdog's 8 s; in the field for
// ever), and then report success.
TEST(PgStore, AFrozenServerFailsWithinTheQueryTimeout) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = false;
    info.connect_timeout_s = 2; // libpq's least.
    info.query_timeout = std::chrono::milliseconds(500);
    auto writer = PgStore::open(info);
    auto reader = PgStore::open(info);
    ASSERT_TRUE(writer.ok() && reader.ok());
    ASSERT_TRUE((*writer)->save({0, 0, 0}, Chunk(5)).ok());
    ASSERT_TRUE((*writer)->flush().ok());
    ASSERT_TRUE((*writer)->save({0, 0, 0}, Chunk(6)).ok());
    FrozenServer frozen(uri);
    ASSERT_EQ(frozen.pids().size(), 3u); // Both stores' backends and the postmaster.
    const auto timed = [](auto&& call) {
        const auto t0 = Clock::now();
        auto result = call();
        return std::make_pair(std::move(result), std::chrono::duration<double>(Clock::now() - t0).count());
    };
    auto [flushed, flush_s] = timed([&] { return (*writer)->flush(); });
    auto [loaded, load_s] = timed([&] { return (*reader)->load({1, 0, 0}); });
    auto [again, again_s] = timed([&] { return (*writer)->flush(); }); // Reconnecting: connect_timeout.
    frozen.thaw();
    EXPECT_LT(flush_s, 2.0) << "the flush waited for the frozen server";
    ASSERT_FALSE(flushed.ok());
    EXPECT_NE(flushed.error().find("query_timeout"), std::string::npos) << flushed.error();
    EXPECT_NE(flushed.error().find("edits kept in memory"), std::string::npos) << flushed.error();
    EXPECT_LT(load_s, 2.0) << "the load waited for the frozen server";
    ASSERT_FALSE(loaded.ok());
    EXPECT_NE(loaded.error().find("query_timeout"), std::string::npos) << loaded.error();
    EXPECT_LT(again_s, 4.0) << "the reconnect waited past connect_timeout";
    EXPECT_FALSE(again.ok());
    EXPECT_EQ((*writer)->pending_edits(), 1u);
    EXPECT_FALSE((*writer)->health().connected);
    vx::Status retried = (*writer)->flush();
    ASSERT_TRUE(retried.ok()) << retried.error();
    EXPECT_EQ((*writer)->pending_edits(), 0u);
    auto check = open_pg(uri);
    EXPECT_TRUE(*check->load({0, 0, 0})->chunk == Chunk(6));
    auto reload = (*reader)->load({0, 0, 0}); // The reader reconnects too.
    ASSERT_TRUE(reload.ok()) << reload.error();
    EXPECT_TRUE(*reload->chunk == Chunk(6));
}

// A write if absent (pregeneration's) commits where nothing or a tombstone is stored, and is
// dropped where another process stored a chunk after this one looked (theirs kept); a plain write
// of the same coordinate queued after it is unconditional.
TEST(PgStore, AWriteIfAbsentKeepsAnotherProcesssChunk) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto mine = open_pg(uri);
    auto other = open_pg(uri);
    // x = 0: the other stores it after our check; 1: the other erased it (a tombstone); 2: never
    // stored; 3: the other stores it, and our plain write follows our write if absent.
    ASSERT_TRUE(other->save({1, 0, 0}, Chunk(4)).ok());
    ASSERT_TRUE(other->flush().ok());
    ASSERT_TRUE(other->erase({1, 0, 0}).ok());
    ASSERT_TRUE(other->flush().ok());
    for (int x = 0; x < 4; ++x)
        EXPECT_FALSE(*mine->contains({x, 0, 0}));
    ASSERT_TRUE(other->save({0, 0, 0}, Chunk(9)).ok());
    ASSERT_TRUE(other->save({3, 0, 0}, Chunk(9)).ok());
    ASSERT_TRUE(other->flush().ok());
    const Chunk terrain(5);
    for (int x = 0; x < 4; ++x) {
        ChunkWrite w{{x, 0, 0}, &terrain};
        w.if_absent = true;
        ASSERT_TRUE(mine->save(std::span<const ChunkWrite>(&w, 1)).ok());
    }
    ASSERT_TRUE(mine->save({3, 0, 0}, Chunk(6)).ok());
    vx::Status s = mine->flush();
    ASSERT_TRUE(s.ok()) << s.error();
    EXPECT_EQ(mine->pending_edits(), 0u);
    auto check = open_pg(uri);
    const BlockId want[4] = {9, 5, 5, 6};
    for (int x = 0; x < 4; ++x)
        EXPECT_TRUE(*check->load({x, 0, 0})->chunk == Chunk(want[x])) << "x = " << x;
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

// A load whose result the caller does not apply (an engine's reload still on its way to the main
// thread while a save of the older copy is queued) must not make that older copy current: the save
// names the version its copy was loaded as (ChunkWrite::base_version), so it merges with b's edit
// instead of writing over it. The store once took the version of its last load, and b's edit was
// gone (found in review). A copy saved twice, never told the version its first save made, is this
// process's own lineage: no conflict.
TEST(PgStore, AStaleCopyMergesEvenAfterALoadOfANewerVersion) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const ChunkCoord c{-3, 2, 5};
    {
        auto seed = open_pg(uri);
        ASSERT_TRUE(seed->save(c, versioned_chunk(c, 1)).ok());
        ASSERT_TRUE(seed->flush().ok());
    }
    auto a = open_pg(uri), b = open_pg(uri);
    vx::Result<ChunkLoad> la = a->load(c), lb = b->load(c);
    ASSERT_TRUE(la && lb);
    ASSERT_EQ(la->version, 1u);
    Chunk ca = *la->chunk, cb = *lb->chunk;
    const BlockEdit eb[] = {{{10, 25, 30}, 11}};
    cb.set(eb[0].pos, eb[0].id);
    ChunkWrite wb{c, &cb, eb};
    wb.base_version = lb->version;
    ASSERT_TRUE(b->save(std::span(&wb, 1)).ok());
    ASSERT_TRUE(b->flush().ok()); // Version 2: b's edit.
    vx::Result<ChunkLoad> unapplied = a->load(c); // Read, never applied to `ca`.
    ASSERT_TRUE(unapplied);
    EXPECT_EQ(unapplied->version, 2u);
    const BlockEdit ea[] = {{{3, 20, 3}, 9}};
    ca.set(ea[0].pos, ea[0].id);
    ChunkWrite wa{c, &ca, ea};
    wa.base_version = la->version; // 1: what `ca` is.
    ASSERT_TRUE(a->save(std::span(&wa, 1)).ok());
    ASSERT_TRUE(a->flush().ok());
    EXPECT_EQ(a->health().conflicts, 1u);
    auto check = open_pg(uri);
    Chunk want = versioned_chunk(c, 1);
    want.set(eb[0].pos, eb[0].id);
    want.set(ea[0].pos, ea[0].id);
    EXPECT_TRUE(*check->load(c)->chunk == want) << "both edits";

    // b saves its copy (version 2 plus its edit) twice more, never learning what its saves made.
    const BlockEdit eb2[] = {{{11, 25, 30}, 12}};
    cb = *check->load(c)->chunk; // Version 3 (a's merge); b applies it, as an engine's reload does.
    const uint64_t v3 = check->load(c)->version;
    cb.set(eb2[0].pos, eb2[0].id);
    ChunkWrite wb2{c, &cb, eb2};
    wb2.base_version = v3;
    ASSERT_TRUE(b->save(std::span(&wb2, 1)).ok());
    ASSERT_TRUE(b->flush().ok());
    const BlockEdit eb3[] = {{{12, 25, 30}, 13}};
    cb.set(eb3[0].pos, eb3[0].id);
    ChunkWrite wb3{c, &cb, eb3};
    wb3.base_version = v3; // Still what b loaded: its lineage maps it to its own last write.
    ASSERT_TRUE(b->save(std::span(&wb3, 1)).ok());
    ASSERT_TRUE(b->flush().ok());
    EXPECT_EQ(b->health().conflicts, 0u);
    want.set(eb2[0].pos, eb2[0].id);
    want.set(eb3[0].pos, eb3[0].id);
    auto last = open_pg(uri);
    EXPECT_TRUE(*last->load(c)->chunk == want) << "every edit of both";
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

// Two writers commit overlapping batches at the same time, each in its own order: writer A's
// queue has grown large before (so its hash table iterates in another order than B's), and they
// insert the shared chunks in opposite orders. Upserts sent in coordinate order lock rows in the
// same order in both transactions, so neither waits for a row the other holds while holding one
// it wants: no deadlock (which the server would break by aborting one: a failed flush here).
TEST(PgStore, OverlappingWritersNeverDeadlock) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    constexpr int kShared = 64, kRounds = 12;
    std::unique_ptr<PgStore> w[2] = {open_pg(uri), open_pg(uri)};
    std::vector<ChunkWrite> warm; // 4,096 uniform chunks: A's table grows (and keeps) its buckets.
    const Chunk stone(3);
    for (int i = 0; i < 4096; ++i)
        warm.push_back({ChunkCoord(i, -50, 0), &stone});
    ASSERT_TRUE(w[0]->save(warm).ok());
    ASSERT_TRUE(w[0]->flush().ok());
    std::vector<ChunkCoord> shared;
    for (int i = 0; i < kShared; ++i)
        shared.push_back({i % 8, 0, i / 8});
    std::barrier sync(2);
    std::atomic<int> failures{0};
    auto write = [&](int who) {
        for (int round = 0; round < kRounds; ++round) {
            // Each round edits what the store reads now, as the engine's copy would be after
            // reloading the chunks another process changed (a stale copy would overwrite them).
            std::vector<Chunk> copies;
            for (ChunkCoord c : shared) {
                auto got = w[who]->load(c);
                copies.push_back(got && got->chunk ? *got->chunk : Chunk(kAir));
            }
            std::vector<BlockEdit> edits(kShared);
            std::vector<ChunkWrite> batch;
            for (int k = 0; k < kShared; ++k) {
                const int i = who == 0 ? k : kShared - 1 - k; // Opposite orders.
                edits[size_t(i)] = {LocalPos(who, round, 0), BlockId(10 + round)};
                copies[size_t(i)].set(edits[size_t(i)].pos, edits[size_t(i)].id);
                batch.push_back({shared[size_t(i)], &copies[size_t(i)], std::span(&edits[size_t(i)], 1)});
            }
            sync.arrive_and_wait(); // Both commit at once.
            if (!w[who]->save(batch) || !w[who]->flush())
                failures.fetch_add(1);
        }
    };
    std::thread a(write, 0), b(write, 1);
    a.join();
    b.join();
    EXPECT_EQ(failures.load(), 0);
    // Every edit of both writers is stored (the conflicts merged them).
    auto check = open_pg(uri);
    for (ChunkCoord c : shared) {
        const Chunk got = *check->load(c)->chunk;
        for (int round = 0; round < kRounds; ++round)
            for (int who = 0; who < 2; ++who)
                ASSERT_EQ(got.get(LocalPos(who, round, 0)), BlockId(10 + round)) << c.x << "," << c.z;
    }
}

// A metadata row the server refuses for good (here a trigger's exception; in the field a key a
// later schema constraint rejects) is dropped and reported, not kept in the queue where it failed
// every later commit and so held the chunk edits queued beside it hostage until they were lost.
TEST(PgStore, ARefusedMetadataRowDoesNotHoldChunkEditsHostage) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto store = open_pg(uri);
    ASSERT_TRUE(store);
    sql(uri, "CREATE FUNCTION vx_test_refuse() RETURNS trigger LANGUAGE plpgsql AS $$ BEGIN "
             "IF NEW.key = 'poison' THEN RAISE EXCEPTION 'poison refused'; END IF; RETURN NEW; END $$");
    sql(uri, "CREATE TRIGGER vx_test_refuse BEFORE INSERT ON vx_meta FOR EACH ROW EXECUTE FUNCTION vx_test_refuse()");
    ASSERT_TRUE(store->save({1, 1, 1}, Chunk(3)).ok());
    ASSERT_TRUE(store->set_meta("poison", "x").ok());
    ASSERT_TRUE(store->set_meta("seed", "7").ok());
    vx::Status first = store->flush();
    ASSERT_FALSE(first.ok()) << "the dropped row must be reported";
    EXPECT_NE(first.error().find("metadata 'poison' refused by the server and dropped"), std::string::npos)
        << first.error();
    EXPECT_NE(first.error().find("poison refused"), std::string::npos) << first.error();
    EXPECT_EQ(first.error().find("unknown error"), std::string::npos) << first.error();
    EXPECT_EQ(store->pending_edits(), 0u);
    EXPECT_TRUE(store->flush().ok());
    auto check = open_pg(uri);
    EXPECT_EQ(check->load({1, 1, 1})->state, LoadState::Present);
    EXPECT_EQ(check->get_meta("seed")->value_or(""), "7");
    EXPECT_FALSE(check->get_meta("poison")->has_value());
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

// A world opened by URI alone (open_store: the engine's WorldSource, the vx CLI) sets the query
// timeout with vx_query_timeout_ms: a flush to a frozen server fails within it (400 ms, not the
// default 15 s) naming it, the edit is kept and commits once the server runs again. libpq used to
// refuse the URI ("invalid URI query parameter").
TEST(PgStore, AUrisQueryTimeoutIsWhatAFrozenServersCallFailsWithin) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto opened = open_store({.name = uri + "&vx_query_timeout_ms=400", .listen = false});
    ASSERT_TRUE(opened.ok()) << opened.error();
    ChunkStore& store = **opened;
    ASSERT_TRUE(store.save({0, 0, 0}, Chunk(5)).ok());
    ASSERT_TRUE(store.flush().ok());
    ASSERT_TRUE(store.save({0, 0, 0}, Chunk(6)).ok());
    vx::Status flushed;
    double flush_s = 0;
    {
        FrozenServer frozen(uri);
        ASSERT_EQ(frozen.pids().size(), 2u); // The store's backend and the postmaster.
        const auto t0 = Clock::now();
        flushed = store.flush();
        flush_s = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    EXPECT_GE(flush_s, 0.35);
    // Far under the default 15 s and the watchdog's 8 s; loose for a loaded machine (TSan).
    EXPECT_LT(flush_s, 5.0) << "the flush did not fail within the URI's 400 ms";
    ASSERT_FALSE(flushed.ok());
    EXPECT_NE(flushed.error().find("query_timeout (400 ms)"), std::string::npos) << flushed.error();
    expect_kept_then_committed(store, uri);
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

// A bad value fails the open with a message naming the parameter, and nothing is opened: the
// empty database stays empty (no tables created).
TEST(PgStore, ABadUriQueryTimeoutIsRefusedNamingIt) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    for (const char* value : {"soon", "0", "-1", "86400000000"}) {
        auto opened = open_store({.name = uri + "&vx_query_timeout_ms=" + value});
        ASSERT_FALSE(opened.ok()) << value;
        EXPECT_NE(opened.error().find("vx_query_timeout_ms must be a whole number of milliseconds"),
                  std::string::npos)
            << opened.error();
        EXPECT_NE(opened.error().find(std::string("'") + value + "'"), std::string::npos) << opened.error();
        EXPECT_NE(opened.error().find("nothing opened"), std::string::npos) << opened.error();
    }
    PGconn* c = PQconnectdb(uri.c_str());
    pg::ResultPtr r(PQexec(c, "SELECT count(*) FROM pg_tables WHERE schemaname = current_schema()"));
    ASSERT_EQ(PQresultStatus(r.get()), PGRES_TUPLES_OK) << PQerrorMessage(c);
    EXPECT_STREQ(PQgetvalue(r.get(), 0, 0), "0");
    PQfinish(c);
}
