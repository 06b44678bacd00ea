// Save tickets: a flush covers every sequence up to its own, a later success supersedes an
// earlier failure, unknown tickets are Unknown and fail at once, and wait() wakes when another thread reports.
#include <thread>

#include <gtest/gtest.h>

#include "engine/save_tracker.h"

using namespace vx;
using namespace vx::engine;

TEST(SaveTracker, FlushCoversEarlierSequences) {
    SaveTracker t;
    const uint64_t a = t.next(), b = t.next(), c = t.next();
    EXPECT_EQ(a, 1u);
    EXPECT_EQ(c, 3u);
    EXPECT_EQ(t.state(a), SaveState::Pending);
    t.finished(b, {}); // The flush of b ran after a's saves too (I/O lane order).
    EXPECT_EQ(t.state(a), SaveState::Durable);
    EXPECT_EQ(t.state(b), SaveState::Durable);
    EXPECT_EQ(t.state(c), SaveState::Pending);
    EXPECT_EQ(t.durable(), b);
    t.finished(a, Error{"late report of a replaced flush"}); // Older than a success: no effect.
    EXPECT_EQ(t.state(a), SaveState::Durable);
}

TEST(SaveTracker, LaterSuccessSupersedesFailure) {
    SaveTracker t;
    const uint64_t a = t.next();
    t.finished(a, Error{"disk full"});
    EXPECT_EQ(t.state(a), SaveState::Failed);
    Status w = t.wait(a);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error(), "disk full");
    EXPECT_EQ(t.last_error(), "disk full");
    const uint64_t b = t.next();
    EXPECT_EQ(t.state(b), SaveState::Pending);
    t.finished(b, {});
    EXPECT_EQ(t.state(a), SaveState::Durable);
    EXPECT_TRUE(t.wait(a));
}

// Each ticket's wait() gives the failure that covered it first: a disk-full flush, then a flush
// cancelled at shutdown, left the first ticket reporting "cancelled".
TEST(SaveTracker, EachTicketKeepsItsOwnFailure) {
    SaveTracker t;
    const uint64_t a = t.next(), b = t.next(), c = t.next();
    t.finished(a, Error{"disk full"});
    t.finished(c, Error{"flush cancelled: shutting down"});
    EXPECT_EQ(t.wait(a).error(), "disk full");
    EXPECT_EQ(t.wait(b).error(), "flush cancelled: shutting down"); // Covered by c's flush only.
    EXPECT_EQ(t.wait(c).error(), "flush cancelled: shutting down");
    EXPECT_EQ(t.last_error(), "flush cancelled: shutting down");
    const uint64_t d = t.next();
    t.finished(d, {});
    EXPECT_TRUE(t.wait(a));
    EXPECT_TRUE(t.wait(c));
}

TEST(SaveTracker, UnknownTicketsFail) {
    SaveTracker t;
    EXPECT_EQ(t.state(0), SaveState::Unknown);
    EXPECT_EQ(t.state(1), SaveState::Unknown); // Not issued yet.
    EXPECT_FALSE(t.wait(0));
    Status w = t.wait(7);
    ASSERT_FALSE(w);
    EXPECT_NE(w.error().find("unknown save ticket 7"), std::string::npos) << w.error();
}

TEST(SaveTracker, WaitWakesOnAnotherThreadsReport) {
    SaveTracker t;
    const uint64_t a = t.next();
    Status result = Error{"not set"};
    std::thread waiter([&] { result = t.wait(a); });
    std::thread io([&] { t.finished(a, {}); });
    io.join();
    waiter.join();
    EXPECT_TRUE(result);
}
