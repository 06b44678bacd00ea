// PostgreSQL-only behaviour of PgStore: refusing foreign databases, connection options, locked rows,
// a frozen server and a server restart under a running writer, refused metadata, and the URI's
// query timeout. Concurrent writers are in pg_store_conflict_test.cpp, change notifications in
// pg_store_changes_test.cpp. The backend-independent suite (store_suite_test.cpp,
// store_crash_test.cpp) runs here as well.
#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <thread>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "pg_store_test_util.h"
#include "pg_test_util.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"
#include "world/store/pg_wire.h"
#include "world/store/store_open.h"

using namespace vx::world;
namespace pg = vx::world::pg;
using vx::world::test::open_pg;
using vx::world::test::sql;
using vx::world::test::versioned_chunk;
using Clock = std::chrono::steady_clock;

namespace {

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
