// JobSystem when the OS refuses its threads (tests/engine/thread_refusal.h injects real refusals):
// with none, it says why and is safe to destroy; with some, it runs on the workers that started.

#include <gtest/gtest.h>

#include "job_test_util.h"
#include "thread_refusal.h"

using namespace vx::engine;
using namespace vx::engine::test;

// No thread starts: the I/O thread is the first refused, the reason is kept, nothing runs, and
// destroying the system with a job queued cancels it instead of waiting.
TEST(JobStart, NoThreadSaysWhyAndIsSafeToDestroy) {
    std::optional<JobSystem> jobs;
    {
        RefuseThreads refuse;
        ASSERT_TRUE(refuse.ok()) << "could not set the default thread attributes";
        jobs.emplace(test_info(4));
    }
    EXPECT_EQ(jobs->worker_count(), 0);
    EXPECT_NE(jobs->start_error().find("the OS refused the I/O thread"), std::string::npos) << jobs->start_error();
    EXPECT_NE(jobs->start_error().find("Resource temporarily unavailable"), std::string::npos) << jobs->start_error();
    std::atomic<bool> ran{false};
    jobs->submit(make_job(key_at(0, 0, 0), [&ran](JobContext&) { ran = true; }));
    jobs.reset();
    EXPECT_FALSE(ran.load());
    // Threads start again once the OS lets them.
    JobSystem again(test_info(2));
    EXPECT_TRUE(again.start_error().empty()) << again.start_error();
    EXPECT_EQ(again.worker_count(), 2);
}

// Some threads start: the system runs every job on those, and says how many it lacks and why.
// Not under sanitizers: they reserve terabytes of address space, so the cap on it cannot apply.
TEST(JobStart, FewerWorkersThanAskedStillRunEveryJob) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    GTEST_SKIP() << "sanitizers reserve terabytes of address space: no address-space cap to hit";
#else
    constexpr int kAsked = 32;
    std::optional<JobSystem> jobs;
    {
        RefuseThreads refuse(3);
        ASSERT_TRUE(refuse.ok()) << "could not cap the address space";
        jobs.emplace(test_info(kAsked));
    }
    ASSERT_TRUE(jobs->start_error().empty()) << jobs->start_error();
    EXPECT_GE(jobs->worker_count(), 1);
    EXPECT_LT(jobs->worker_count(), kAsked);
    EXPECT_EQ(jobs->refused_workers(), kAsked - jobs->worker_count());
    EXPECT_NE(jobs->refused_reason().find("Resource temporarily unavailable"), std::string::npos)
        << jobs->refused_reason();
    std::atomic<int> ran{0};
    for (int x = 0; x < 100; ++x)
        jobs->submit(make_job(key_at(x, 0, 0), [&ran](JobContext&) { ++ran; }));
    EXPECT_EQ(drain(*jobs), 100u);
    EXPECT_EQ(ran.load(), 100);
#endif
}
