// The change listener of a shared world (pg::ChangeListener, world/store/pg_listener.h) against
// a real server whose failures are injected: a LISTEN frozen, refused or interrupted, poll()
// failing, a database that is not there yet. Each failure is logged once, the listener reconnects
// and hears other processes again, and destruction never waits on a frozen server.
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "pg_test_util.h"
#include "world/store/pg_listener.h"
#include "world/store/pg_wire.h"

using namespace vx::world;
namespace pg = vx::world::pg;
using vx::world::test::LogCapture;
using vx::world::test::PgCluster;
using vx::world::test::wait_until;
using Clock = std::chrono::steady_clock;

namespace {

// Sends NOTIFY vx_chunks "x,y,z" of `c` from a connection of its own until `listener` collects
// it (bounded): the listener hears other processes.
bool hears(pg::ChangeListener& listener, const std::string& uri, ChunkCoord c) {
    PGconn* conn = PQconnectdb(uri.c_str());
    const std::string sql = "NOTIFY vx_chunks, '" + pg::coord_str(c) + "'";
    std::vector<ChunkCoord> got;
    bool heard = false;
    for (int i = 0; i < 50 && !heard; ++i) {
        pg::ResultPtr(PQexec(conn, sql.c_str()));
        heard = wait_until([&] {
            listener.take(got);
            return std::find(got.begin(), got.end(), c) != got.end();
        }, 0.2);
    }
    PQfinish(conn);
    return heard;
}

// A listener (connect timeout 2 s) on a new database of `cluster`, whose URI goes to `uri`, once
// it listens and has heard another process; null, with a test failure, if it never did.
std::unique_ptr<pg::ChangeListener> heard_listener(PgCluster& cluster, std::string& uri) {
    uri = cluster.new_database();
    auto listener = std::make_unique<pg::ChangeListener>(uri, 2, 1024);
    if (!wait_until([&] { return listener->listening(); }, 10.0) || !hears(*listener, uri, {1, 2, 3})) {
        ADD_FAILURE() << "the listener never heard another process";
        return nullptr;
    }
    return listener;
}

// Each test: the test program's cluster (skipped, saying why, without one) and the log's lines
// from the start of the test on.
class PgListener : public ::testing::Test {
protected:
    void SetUp() override {
        cluster = vx::world::test::cluster_or_skip();
        if (!cluster)
            GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    }
    PgCluster* cluster = nullptr;
    LogCapture log;
    std::string heard_uri; // heard_listener's database.
};

} // namespace

// The listener's first backend is frozen (SIGSTOP) between its connect and its LISTEN: the LISTEN
// gets no answer within the connect timeout (2 s). The listener logs it, drops that connection,
// reconnects (listen_epoch 1: the store would then catch up) and hears other processes. It used
// to give up on that LISTEN silently.
TEST_F(PgListener, AListenerWhoseListenGetsNoAnswerReportsItAndReconnects) {
    const std::string uri = cluster->new_database();
    std::atomic<int> frozen{0};
    const auto t0 = Clock::now();
    {
        pg::ChangeListener listener(uri, 2, 1024, [&](int pid) {
            int none = 0;
            if (frozen.compare_exchange_strong(none, pid))
                ::kill(pid, SIGSTOP);
        });
        const bool up = wait_until([&] { return listener.listening(); }, 20.0);
        const double took = std::chrono::duration<double>(Clock::now() - t0).count();
        ::kill(frozen.load(), SIGCONT); // Its connection is gone: the backend exits.
        ASSERT_NE(frozen.load(), 0);
        ASSERT_TRUE(up) << "the listener never listened again";
        EXPECT_GE(took, 1.9) << "the frozen LISTEN was not waited for";
        EXPECT_EQ(listener.listen_epoch(), 1u);
        EXPECT_EQ(log.count("LISTEN got no answer within 2 s"), 1u);
        EXPECT_TRUE(hears(listener, uri, {4, 5, 6}));
    }
}

// The listener's first backend is terminated (SIGTERM, as pg_terminate_backend) between its
// connect and its LISTEN, and gone before the LISTEN is sent: the server's answer is an error,
// not silence. The listener logs it (sent and refused, or refused at the send: which one is the
// kernel's timing), never reports itself listening on that connection, reconnects and hears.
TEST_F(PgListener, AListenerWhoseListenIsRefusedReportsItAndReconnects) {
    const std::string uri = cluster->new_database();
    std::atomic<int> terminated{0};
    {
        pg::ChangeListener listener(uri, 5, 1024, [&](int pid) {
            int none = 0;
            if (!terminated.compare_exchange_strong(none, pid))
                return;
            ::kill(pid, SIGTERM);
            // The postmaster reaps it; bounded, as a test must not hang on a machine's bad day.
            for (int i = 0; i < 500 && ::kill(pid, 0) == 0; ++i)
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
        });
        ASSERT_TRUE(wait_until([&] { return listener.listening(); }, 20.0)) << "the listener never listened";
        ASSERT_NE(terminated.load(), 0);
        EXPECT_NE(::kill(terminated.load(), 0), 0) << "the terminated backend outlived the wait";
        EXPECT_EQ(log.count("LISTEN failed: ") + log.count("cannot send LISTEN: "), 1u);
        EXPECT_EQ(log.count("cannot connect"), 0u);
        EXPECT_TRUE(hears(listener, uri, {8, 9, 10}));
        // Listening once, on the second connection: the refused one never counted, so it was
        // never found lost afterwards.
        EXPECT_EQ(listener.listen_epoch(), 1u) << "the refused LISTEN counted as listening";
        EXPECT_EQ(log.count("connection lost"), 0u);
    }
}

// Destroyed while its LISTEN waits on a frozen server, the listener stops at once; it used to
// wait out the LISTEN's deadline (the connect timeout, here 10 s; a PgStore's destructor with it).
// It waits in 50 ms slices: 3 s is loose for a loaded machine and far under the deadline.
TEST_F(PgListener, AListenerStopsPromptlyDuringAnUnansweredListen) {
    const std::string uri = cluster->new_database();
    std::atomic<int> frozen{0};
    auto listener = std::make_unique<pg::ChangeListener>(uri, 10, 1024, [&](int pid) {
        int none = 0;
        if (frozen.compare_exchange_strong(none, pid))
            ::kill(pid, SIGSTOP);
    });
    ASSERT_TRUE(wait_until([&] { return frozen.load() != 0; }, 10.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(200)); // Inside the LISTEN's wait.
    const auto t0 = Clock::now();
    listener.reset();
    const double took = std::chrono::duration<double>(Clock::now() - t0).count();
    ::kill(frozen.load(), SIGCONT);
    EXPECT_LT(took, 3.0) << "destruction waited for the frozen LISTEN";
}

// poll() failing under the listening loop (injected: EIO) is logged naming poll and the error;
// the listener reconnects and listens again (listen_epoch 2: the store catches up on what it
// may have missed) and hears other processes. It used to reconnect without a word. The
// reconnect's first poll is interrupted (EINTR): that attempt goes on, no failure logged (it
// used to be abandoned, waiting out a back-off).
TEST_F(PgListener, AFailedPollIsReportedAndTheListenerReconnects) {
    const auto heard = heard_listener(*cluster, heard_uri);
    ASSERT_TRUE(heard);
    pg::ChangeListener& listener = *heard;
    ASSERT_EQ(listener.listen_epoch(), 1u);
    listener.fail_next_poll(EIO);
    listener.fail_next_poll(EINTR);
    EXPECT_TRUE(wait_until([&] { return listener.listen_epoch() == 2 && listener.listening(); }, 10.0));
    EXPECT_EQ(log.count("cannot wait on its connection: poll: " + std::string(std::strerror(EIO))), 1u);
    EXPECT_EQ(log.count("cannot connect"), 0u);
    EXPECT_TRUE(hears(listener, heard_uri, {3, 2, 1}));
}

// A listener that cannot connect (its database does not exist yet) says so once, naming the
// cause, not at every retry (attempts at about 0, 0.25 and 0.75 s); once the database is
// there it listens. A failed attempt after it was up again is reported again: poll() failing
// (injected) first under the listening loop, then while reconnecting. Failed connects used to
// be silent.
TEST_F(PgListener, AListenerThatCannotConnectSaysSoOncePerRunOfFailures) {
    const std::string name = cluster->next_database_name();
    pg::ChangeListener listener(cluster->uri(name), 2, 1024);
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    EXPECT_FALSE(listener.listening());
    EXPECT_EQ(log.count("cannot connect"), 1u);
    EXPECT_EQ(log.count("does not exist"), 1u);
    const std::string uri = cluster->create_database(name);
    ASSERT_TRUE(wait_until([&] { return listener.listening(); }, 15.0));
    EXPECT_TRUE(hears(listener, uri, {1, 2, 3}));
    listener.fail_next_poll(EIO);
    listener.fail_next_poll(EIO);
    EXPECT_TRUE(wait_until([&] { return listener.listen_epoch() == 2 && listener.listening(); }, 15.0));
    EXPECT_EQ(log.count("cannot connect: cannot wait on its connection: poll: " + std::string(std::strerror(EIO))), 1u);
    EXPECT_EQ(log.count("cannot connect"), 2u);
}

// A poll() interrupted by a signal (EINTR) is no failure: the listener keeps its connection (no
// reconnect, no missed notification, nothing logged). It used to drop it and reconnect.
TEST_F(PgListener, AnInterruptedPollKeepsTheListenersConnection) {
    const auto heard = heard_listener(*cluster, heard_uri);
    ASSERT_TRUE(heard);
    pg::ChangeListener& listener = *heard;
    listener.fail_next_poll(EINTR);
    ASSERT_TRUE(wait_until([&] { return !listener.listening() || listener.listen_epoch() != 1; }, 0.5) == false)
        << "the listener dropped its connection";
    EXPECT_TRUE(hears(listener, heard_uri, {3, 2, 1}));
    EXPECT_EQ(listener.listen_epoch(), 1u);
    EXPECT_EQ(log.count("reconnecting"), 0u);
}
