// JobSystem scheduling: priority order, re-prioritization, cancellation, the one-per-key rule,
// stale results and the serial I/O lane. Every wait is on an event, never on time.

#include <thread>

#include <gtest/gtest.h>

#include "job_test_util.h"

using namespace vx::engine;
using namespace vx::engine::test;

namespace {

// Submits one recording Mesh job per chunk x (y = z = 0); run() appends x to `order`.
void atomic_max(std::atomic<int>& m, int v) {
    int cur = m.load();
    while (cur < v && !m.compare_exchange_weak(cur, v)) {
    }
}

void submit_row(JobSystem& jobs, Recorder& order, std::initializer_list<int> xs) {
    for (int x : xs)
        jobs.submit(make_job(key_at(x, 0, 0), [&order, x](JobContext&) { order.add(x); }));
}

} // namespace

TEST(JobSystem, OneWorkerRunsNearestFirst) {
    JobSystem jobs(test_info(1, /*paused=*/true));
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    Recorder order;
    submit_row(jobs, order, {5, 1, 3, 2, 4});
    jobs.resume();
    EXPECT_EQ(drain(jobs), 5u); // complete() runs (and counts) even when it does nothing.
    EXPECT_EQ(order.values(), (std::vector<int>{1, 2, 3, 4, 5}));
}

TEST(JobSystem, InFrontBeforeBehindAtEqualDistance) {
    JobSystem jobs(test_info(1, true));
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    Recorder order;
    // All three chunk centres are 96 blocks away: behind (x=-3) and beside (z=3) are submitted
    // first, yet the one in front (x=3) runs first. Scores 96 (front), 144 (side), 192 (behind).
    jobs.submit(make_job(key_at(-3, 0, 0), [&](JobContext&) { order.add(-3); }));
    jobs.submit(make_job(key_at(0, 0, 3), [&](JobContext&) { order.add(100); }));
    jobs.submit(make_job(key_at(3, 0, 0), [&](JobContext&) { order.add(3); }));
    jobs.resume();
    drain(jobs);
    EXPECT_EQ(order.values(), (std::vector<int>{3, 100, -3}));
}

TEST(JobSystem, ViewerMoveReprioritizesQueuedJobs) {
    // One worker, busy with a blocker while the row is queued, so the heap is built for the first
    // viewer; then the viewer moves and the remaining order must follow the new position.
    JobSystem jobs(test_info(1));
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    Gate started, release;
    jobs.submit(make_job(key_at(0, 0, 0, JobKind::Task), [&](JobContext&) {
        started.open();
        release.wait();
    }));
    started.wait();
    Recorder order;
    submit_row(jobs, order, {1, 2, 3, 4, -1, -2, -3, -4});
    const uint64_t rebuilds_before = jobs.metrics().heap_rebuilds;
    // The viewer walks to chunk -5, still facing +x: now chunk -4 is nearest, 4 farthest.
    jobs.set_viewer({chunk_centre(-5, 0, 0), {1, 0, 0}});
    release.open();
    drain(jobs);
    EXPECT_EQ(order.values(), (std::vector<int>{-4, -3, -2, -1, 1, 2, 3, 4}));
    EXPECT_EQ(jobs.metrics().heap_rebuilds, rebuilds_before + 1); // One re-heap for one move.
}

TEST(JobSystem, SmallViewerMovesKeepTheQueueOrder) {
    JobSystemCreateInfo info = test_info(1, true);
    info.reprioritize_distance = 8.0;
    JobSystem jobs(info);
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}}); // Far from the default origin: applies.
    Recorder order;
    submit_row(jobs, order, {2, 1, 3});
    // Moving 4 blocks (below the 8-block threshold) and turning 1 degree changes nothing.
    jobs.set_viewer({chunk_centre(0, 0, 0) + glm::dvec3(4, 0, 0), {1, 0.0175, 0}});
    jobs.resume();
    drain(jobs);
    EXPECT_EQ(order.values(), (std::vector<int>{1, 2, 3}));
    EXPECT_EQ(jobs.metrics().heap_rebuilds, 1u); // The first set_viewer's re-heap only.
}

TEST(JobSystem, CancelledBeforeStartNeverRuns) {
    JobSystem jobs(test_info(2, true));
    std::atomic<int> runs{0}, completes{0};
    auto counting = [&](int x) {
        return make_job(key_at(x, 0, 0), [&](JobContext&) { ++runs; }, [&] { ++completes; });
    };
    const JobTicket a = jobs.submit(counting(1));
    jobs.submit(counting(2));
    jobs.submit(counting(3));
    a.token.cancel();                        // By token.
    EXPECT_TRUE(jobs.cancel(key_at(2, 0, 0))); // By key.
    EXPECT_FALSE(jobs.cancel(key_at(9, 0, 0)));
    jobs.resume();
    EXPECT_EQ(drain(jobs), 1u);
    EXPECT_EQ(runs.load(), 1);
    EXPECT_EQ(completes.load(), 1);
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.cancelled, 2u);
    EXPECT_EQ(m.completed, 1u);
    EXPECT_EQ(m.wasted_work.count(), 0); // Nothing ran in vain.
}

TEST(JobSystem, CancelledMidRunIsDiscardedAndCountedAsWaste) {
    JobSystem jobs(test_info(1));
    for (int variant = 0; variant < 2; ++variant) {
        Gate started;
        std::atomic<bool> saw_cancel{false}, completed{false};
        const JobTicket t = jobs.submit(make_job(
            key_at(variant, 0, 0),
            [&](JobContext& ctx) {
                started.open();
                while (!ctx.is_cancelled()) // A long job polling between steps.
                    std::this_thread::yield();
                saw_cancel = true;
            },
            [&] { completed = true; }));
        started.wait();
        if (variant == 0)
            t.token.cancel();
        else
            jobs.cancel(t.key);
        drain(jobs);
        EXPECT_TRUE(saw_cancel.load());
        EXPECT_FALSE(completed.load());
    }
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.cancelled, 2u);
    EXPECT_EQ(m.completed, 0u);
    EXPECT_GT(m.wasted_work.count(), 0);
    EXPECT_EQ(m.wasted_work, m.run_time); // All run time was wasted.
}

TEST(JobSystem, QueuedJobIsReplacedBySameKeySubmit) {
    JobSystem jobs(test_info(2, true));
    Recorder ran, completed;
    for (int version = 1; version <= 3; ++version)
        jobs.submit(make_job(
            key_at(7, 0, 0), [&ran, version](JobContext&) { ran.add(version); },
            [&completed, version] { completed.add(version); }));
    jobs.resume();
    drain(jobs);
    EXPECT_EQ(ran.values(), (std::vector<int>{3}));
    EXPECT_EQ(completed.values(), (std::vector<int>{3}));
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.replaced, 2u);
    EXPECT_EQ(m.cancelled, 2u);
    EXPECT_EQ(m.submitted, 3u);
}

TEST(JobSystem, AtMostOneJobPerKeyInFlight) {
    // Two workers; job 1 of key K blocks one. A same-key job 2 submitted meanwhile must wait,
    // even though the other worker is free: a filler job (worse score, submitted after job 2) runs
    // on the free worker first. Had job 2 been runnable, that worker would have taken it first.
    JobSystem jobs(test_info(2));
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    const JobKey k = key_at(1, 0, 0);
    std::atomic<int> running_k{0}, max_running_k{0};
    auto enter = [&] { atomic_max(max_running_k, ++running_k); };
    Gate started1, release1, filler_done;
    std::atomic<bool> job1_saw_supersede{false}, job2_started{false};
    Recorder completed;
    jobs.submit(make_job(
        k,
        [&](JobContext& ctx) {
            enter();
            started1.open();
            release1.wait();
            job1_saw_supersede = ctx.is_cancelled();
            --running_k;
        },
        [&] { completed.add(1); }));
    started1.wait();
    jobs.submit(make_job(
        k,
        [&](JobContext&) {
            job2_started = true;
            enter();
            --running_k;
        },
        [&] { completed.add(2); }));
    jobs.submit(make_job(key_at(9, 0, 0), [&](JobContext&) { filler_done.open(); }));
    filler_done.wait();
    EXPECT_FALSE(job2_started.load());
    EXPECT_EQ(jobs.metrics().queued, 1u); // Job 2, parked behind job 1.
    release1.open();
    drain(jobs);
    EXPECT_TRUE(job1_saw_supersede.load()); // The newer submit told job 1 to stop early.
    EXPECT_TRUE(job2_started.load());
    EXPECT_EQ(max_running_k.load(), 1);
    EXPECT_EQ(completed.values(), (std::vector<int>{2})); // Job 1's result was stale.
    EXPECT_EQ(jobs.metrics().dropped_stale, 1u);
}

TEST(JobSystem, FinishedResultDroppedWhenANewerRequestCame) {
    JobSystem jobs(test_info(1));
    Recorder completed;
    const JobKey k = key_at(0, 2, 0);
    jobs.submit(make_job(k, [](JobContext&) {}, [&] { completed.add(1); }));
    jobs.wait_idle(); // Job 1 finished; its result waits for the main thread.
    jobs.pause();
    const JobTicket t2 = jobs.submit(make_job(k, [](JobContext&) {}, [&] { completed.add(2); }));
    EXPECT_EQ(t2.generation, 2u);
    CompletionStats s = jobs.process_completions();
    EXPECT_EQ(s.applied, 0u);
    EXPECT_EQ(s.discarded, 1u); // Generation 1 < latest 2: stale.
    jobs.resume();
    drain(jobs);
    EXPECT_EQ(completed.values(), (std::vector<int>{2}));
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.dropped_stale, 1u);
    EXPECT_EQ(m.completed, 1u);
}

TEST(JobSystem, IoLaneRunsOneAtATimeInSubmissionOrder) {
    JobSystem jobs(test_info(3, true));
    // The viewer would order these nearest-first; the I/O lane ignores it.
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    Recorder order;
    std::atomic<int> inside{0}, max_inside{0}, wrong_thread{0};
    auto io_job = [&](int x, JobKind kind, int tag) {
        return make_job(key_at(x, 0, 0, kind), [&, tag](JobContext& ctx) {
            atomic_max(max_inside, ++inside);
            if (ctx.worker_index() != -1)
                ++wrong_thread;
            order.add(tag);
            --inside;
        });
    };
    std::vector<int> expected;
    for (int i = 0; i < 40; ++i) {
        const int x = (i * 7) % 40 - 20;
        jobs.submit(io_job(x, i % 2 ? JobKind::Save : JobKind::Load, i));
        expected.push_back(i);
    }
    // A replacing save takes the replaced one's place in line (1002 runs where 1000 was, before
    // the load 1001 submitted between them, which so reads the newest data).
    jobs.submit(io_job(100, JobKind::Save, 1000));
    jobs.submit(io_job(100, JobKind::Load, 1001));
    jobs.submit(io_job(100, JobKind::Save, 1002));
    // Cancelling a queued save and submitting again puts the new one at the back.
    jobs.submit(io_job(101, JobKind::Save, 1003));
    jobs.submit(io_job(102, JobKind::Save, 1004));
    jobs.cancel(key_at(101, 0, 0, JobKind::Save));
    jobs.submit(io_job(101, JobKind::Save, 1005));
    // A replacing load goes to the back: it reads what the save submitted before it wrote (in
    // the replaced load's place, 1008 ran before 1007).
    jobs.submit(io_job(103, JobKind::Load, 1006));
    jobs.submit(io_job(103, JobKind::Save, 1007));
    jobs.submit(io_job(103, JobKind::Load, 1008));
    expected.insert(expected.end(), {1002, 1001, 1004, 1005, 1007, 1008});
    jobs.resume();
    drain(jobs);
    EXPECT_EQ(order.values(), expected);
    EXPECT_EQ(max_inside.load(), 1);
    EXPECT_EQ(wrong_thread.load(), 0);
}

TEST(JobSystem, BatchSubmitFollowsTheSameRules) {
    JobSystem jobs(test_info(1, true));
    jobs.set_viewer({chunk_centre(0, 0, 0), {1, 0, 0}});
    Recorder order;
    std::vector<std::unique_ptr<Job>> batch;
    for (int x : {4, 2, 3, 2, 1}) // Chunk 2 twice: the second replaces the first.
        batch.push_back(make_job(key_at(x, 0, 0), [&order, x](JobContext&) { order.add(x); }));
    const std::vector<JobTicket> tickets = jobs.submit_batch(std::move(batch));
    ASSERT_EQ(tickets.size(), 5u);
    for (size_t i = 1; i < tickets.size(); ++i)
        EXPECT_GT(tickets[i].generation, tickets[i - 1].generation); // Vector order.
    EXPECT_EQ(tickets[3].key, key_at(2, 0, 0));
    jobs.resume();
    EXPECT_EQ(drain(jobs), 4u);
    EXPECT_EQ(order.values(), (std::vector<int>{1, 2, 3, 4}));
    EXPECT_EQ(jobs.metrics().replaced, 1u);
}

namespace {

// A job whose run() calls `run_fn` and then hands over `next` as its continuation.
class ChainJob final : public Job {
public:
    ChainJob(JobKey key, std::function<void(JobContext&)> run_fn, std::unique_ptr<Job> next)
        : Job(key), m_run(std::move(run_fn)), m_next(std::move(next)) {}
    void run(JobContext& ctx) override { m_run(ctx); }
    void complete() override {}
    std::unique_ptr<Job> take_continuation() override { return std::move(m_next); }

private:
    std::function<void(JobContext&)> m_run;
    std::unique_ptr<Job> m_next;
};

} // namespace

TEST(JobSystem, ContinuationRunsWithoutTheMainThread) {
    // An I/O job hands a pool job over; wait_idle() returns only after both ran, and no
    // process_completions() call happens in between: the chain needs no main thread.
    JobSystem jobs(test_info(1));
    std::atomic<int> io_runs{0}, pool_runs{0};
    auto next = make_job(key_at(4, 0, 0, JobKind::Generate), [&](JobContext& ctx) {
        EXPECT_GE(ctx.worker_index(), 0); // A pool worker, not the I/O lane (-1).
        EXPECT_EQ(io_runs.load(), 1);     // Runs after its parent.
        ++pool_runs;
    });
    jobs.submit(std::make_unique<ChainJob>(key_at(4, 0, 0, JobKind::Load), [&](JobContext&) { ++io_runs; },
                                           std::move(next)));
    jobs.wait_idle();
    EXPECT_EQ(io_runs.load(), 1);
    EXPECT_EQ(pool_runs.load(), 1);
    EXPECT_EQ(drain(jobs), 2u); // Both results still reach the main thread.
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.submitted, 2u);
    EXPECT_EQ(m.completed, 2u);
}

TEST(JobSystem, CancelledParentDropsItsContinuation) {
    JobSystem jobs(test_info(1));
    Gate started, release;
    std::atomic<int> pool_runs{0};
    auto next = make_job(key_at(5, 0, 0, JobKind::Generate), [&](JobContext&) { ++pool_runs; });
    jobs.submit(std::make_unique<ChainJob>(
        key_at(5, 0, 0, JobKind::Load),
        [&](JobContext&) {
            started.open();
            release.wait();
        },
        std::move(next)));
    started.wait();
    EXPECT_TRUE(jobs.cancel(key_at(5, 0, 0, JobKind::Load))); // While it runs: its result is unwanted.
    release.open();
    jobs.wait_idle();
    EXPECT_EQ(drain(jobs), 0u);
    EXPECT_EQ(pool_runs.load(), 0);
    const JobMetrics m = jobs.metrics();
    EXPECT_EQ(m.submitted, 1u); // The continuation was never submitted.
    EXPECT_EQ(m.cancelled, 1u);
}
