// JobSystem life cycle: completion budgets (with a fake clock), re-entrant submits from complete(),
// shutdown with work outstanding, worker count and the metrics identity.

#include <thread>

#include <gtest/gtest.h>

#include "job_test_util.h"

using namespace vx::engine;
using namespace vx::engine::test;
using namespace std::chrono_literals;

namespace {

// A job that counts live instances, runs and completions, to prove nothing leaks or completes
// after shutdown.
struct Tally {
    std::atomic<int> live{0}, runs{0}, completes{0};
};

class TallyJob final : public Job {
public:
    TallyJob(JobKey key, Tally& tally, std::function<void(JobContext&)> body = {})
        : Job(key), m_tally(tally), m_body(std::move(body)) {
        ++m_tally.live;
    }
    ~TallyJob() override { --m_tally.live; }
    void run(JobContext& ctx) override {
        ++m_tally.runs;
        if (m_body)
            m_body(ctx);
    }
    void complete() override { ++m_tally.completes; }

private:
    Tally& m_tally;
    std::function<void(JobContext&)> m_body;
};

} // namespace

TEST(JobSystem, CompletionBudgetIsRespectedWithAFakeClock) {
    // Every complete() advances the fake clock by 1 ms, so the budget arithmetic is exact.
    std::atomic<int64_t> fake_ns{0};
    JobSystemCreateInfo info = test_info(2);
    info.clock = [&] { return std::chrono::nanoseconds(fake_ns.load()); };
    JobSystem jobs(info);
    for (int i = 0; i < 10; ++i)
        jobs.submit(make_job(key_at(i, 0, 0), [](JobContext&) {}, [&] { fake_ns += 1'000'000; }));
    jobs.wait_idle();

    // 2.5 ms: checks at 0, 1 and 2 ms pass, the one at 3 ms stops. The last job overran by 0.5 ms.
    CompletionStats s = jobs.process_completions({2500us, SIZE_MAX});
    EXPECT_EQ(s.applied, 3u);
    EXPECT_EQ(s.remaining, 7u);
    EXPECT_EQ(s.time_used, 3ms);
    EXPECT_EQ(jobs.metrics().last_completion_time, 3ms);

    // A count budget: at most 4, though time would allow all.
    s = jobs.process_completions({1h, 4});
    EXPECT_EQ(s.applied, 4u);
    EXPECT_EQ(s.remaining, 3u);

    // A zero budget applies nothing; leftovers still wait.
    s = jobs.process_completions({0ns, SIZE_MAX});
    EXPECT_EQ(s.applied, 0u);
    EXPECT_EQ(s.remaining, 3u);

    s = jobs.process_completions({1h, SIZE_MAX});
    EXPECT_EQ(s.applied, 3u);
    EXPECT_EQ(s.remaining, 0u);
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.completed, 10u);
    EXPECT_EQ(m.max_completion_time, 4ms);
    EXPECT_EQ(m.total_completion_time, 10ms);
}

TEST(JobSystem, CompleteMaySubmitFollowUpJobs) {
    // A chain load -> generate -> mesh, each stage submitted from the previous one's complete().
    JobSystem jobs(test_info(2));
    Recorder stages;
    const JobKey mesh = key_at(0, 0, 0, JobKind::Mesh), gen = key_at(0, 0, 0, JobKind::Generate);
    jobs.submit(make_job(key_at(0, 0, 0, JobKind::Load), [](JobContext&) {}, [&] {
        stages.add(1);
        jobs.submit(make_job(gen, [](JobContext&) {}, [&] {
            stages.add(2);
            jobs.submit(make_job(mesh, [](JobContext&) {}, [&] { stages.add(3); }));
        }));
    }));
    for (int frame = 0; frame < 3; ++frame)
        drain(jobs);
    EXPECT_EQ(stages.values(), (std::vector<int>{1, 2, 3}));
}

TEST(JobSystem, RunMaySubmitJobs) {
    // A worker fans out: one job submits four more from run(); all complete on the main thread.
    JobSystem jobs(test_info(2));
    std::atomic<int> children_run{0};
    std::atomic<int> completes{0};
    jobs.submit(make_job(key_at(0, 0, 0, JobKind::Task), [&](JobContext&) {
        for (int i = 1; i <= 4; ++i)
            jobs.submit(make_job(key_at(i, 0, 0), [&](JobContext&) { ++children_run; }, [&] { ++completes; }));
    }, [&] { ++completes; }));
    // The parent is done once it ran; children it submitted are queued or running by then, so
    // wait_idle covers them too (it waits for queued as well as running jobs).
    drain(jobs);
    EXPECT_EQ(children_run.load(), 4);
    EXPECT_EQ(completes.load(), 5);
}

TEST(JobSystem, ShutdownWithWorkOutstanding) {
    Tally tally;
    std::atomic<bool> blocker_saw_stop{false};
    Gate started; // Outlives the system: the blocker may still be inside open() at shutdown.
    {
        JobSystem jobs(test_info(1));
        // One finished result awaiting completion, one running job, 200 queued jobs on both lanes.
        jobs.submit(std::make_unique<TallyJob>(key_at(-1, 0, 0), tally));
        jobs.wait_idle();
        jobs.submit(std::make_unique<TallyJob>(key_at(0, 0, 0), tally, [&](JobContext& ctx) {
            started.open();
            while (!ctx.is_cancelled())
                std::this_thread::yield();
            blocker_saw_stop = true;
        }));
        started.wait();
        for (int i = 1; i <= 100; ++i) {
            jobs.submit(std::make_unique<TallyJob>(key_at(i, 0, 0), tally));
            jobs.submit(std::make_unique<TallyJob>(key_at(i, 0, 0, JobKind::Save), tally));
        }
        EXPECT_EQ(tally.live.load(), 202); // Finished results are still owned by the system.
    } // The destructor cancels, stops, joins and discards.
    EXPECT_TRUE(blocker_saw_stop.load());
    EXPECT_EQ(tally.live.load(), 0);     // No leaks.
    EXPECT_EQ(tally.completes.load(), 0); // Nothing completed, during or after destruction.
    // The I/O thread may have started some saves before the destructor took the lock; pool jobs
    // other than the first two could not start (one worker, blocked).
    EXPECT_GE(tally.runs.load(), 2);
    EXPECT_LE(tally.runs.load(), 102);
}

TEST(JobSystem, DefaultWorkerCountIsCoresMinusOneAtLeastOne) {
    JobSystem jobs;
    const int hw = int(std::thread::hardware_concurrency());
    EXPECT_EQ(jobs.worker_count(), hw > 1 ? hw - 1 : 1);
    // And it runs jobs.
    std::atomic<int> ran{0};
    jobs.submit(make_job(key_at(0, 0, 0), [&](JobContext&) { ++ran; }));
    EXPECT_EQ(drain(jobs), 1u);
    EXPECT_EQ(ran.load(), 1);
}

TEST(JobSystem, MetricsAccountForEveryJob) {
    JobSystem jobs(test_info(2, true));
    // 30 submits over 10 keys: 20 replaced while paused; of the 10 survivors, cancel 3.
    std::vector<JobTicket> last(10);
    for (int i = 0; i < 30; ++i)
        last[size_t(i % 10)] = jobs.submit(make_job(key_at(i % 10, 0, 0), [](JobContext&) {}));
    for (int k = 0; k < 3; ++k)
        last[size_t(k)].token.cancel();
    EXPECT_EQ(jobs.metrics().queued, 10u);
    jobs.resume();
    drain(jobs);
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.submitted, 30u);
    EXPECT_EQ(m.replaced, 20u);
    EXPECT_EQ(m.cancelled, 23u);
    EXPECT_EQ(m.completed, 7u);
    EXPECT_EQ(m.submitted, m.completed + m.cancelled + m.dropped_stale);
    EXPECT_EQ(m.queued + m.in_flight + m.awaiting_completion, 0u);
}

TEST(JobSystem, CancelAllDropsQueuedAndStopsRunning) {
    Gate started;
    JobSystem jobs(test_info(1));
    std::atomic<int> completes{0};
    std::atomic<bool> saw_cancel{false};
    jobs.submit(make_job(key_at(0, 0, 0), [&](JobContext& ctx) {
        started.open();
        while (!ctx.is_cancelled())
            std::this_thread::yield();
        saw_cancel = true;
    }, [&] { ++completes; }));
    started.wait();
    jobs.pause(); // Keeps the I/O lane from starting the saves before cancel_all.
    for (int i = 1; i <= 5; ++i)
        jobs.submit(make_job(key_at(i, 0, 0), [](JobContext&) {}, [&] { ++completes; }));
    for (int i = 1; i <= 3; ++i)
        jobs.submit(make_job(key_at(i, 0, 0, JobKind::Save), [](JobContext&) {}, [&] { ++completes; }));
    EXPECT_EQ(jobs.metrics().queued, 8u);
    jobs.cancel_all();
    EXPECT_EQ(jobs.metrics().queued, 0u);
    jobs.wait_idle(); // Paused but nothing queued: returns once the running job has stopped.
    jobs.resume();
    EXPECT_EQ(drain(jobs), 0u);
    EXPECT_TRUE(saw_cancel.load());
    EXPECT_EQ(completes.load(), 0);
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.cancelled, 9u); // 8 queued + the running one.
    EXPECT_EQ(m.submitted, m.cancelled);
}
