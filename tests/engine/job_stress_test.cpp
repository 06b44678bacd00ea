// Stress: several threads submit, resubmit and cancel thousands of jobs over a few keys while the
// main thread completes results, moves the viewer and pauses; invariants are checked with atomics.
// Sized to stay within seconds under ThreadSanitizer on 2 cores.

#include <array>
#include <cstdio>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "job_test_util.h"

using namespace vx::engine;
using namespace vx::engine::test;

namespace {

constexpr int kThreads = 4;
constexpr int kOpsPerThread = 2500;
constexpr int kChunks = 40;
constexpr int kKeys = kChunks * 3; // Mesh and Generate (pool), Save (I/O lane).
constexpr int kMaxJobs = kThreads * kOpsPerThread * 3 + kKeys + 2000;

JobKey key_of(int k) {
    static constexpr JobKind kinds[3] = {JobKind::Mesh, JobKind::Generate, JobKind::Save};
    return JobKey{vx::world::ChunkCoord(k % kChunks, (k % 3) - 1, 0), kinds[k / kChunks]};
}

// Per-job and per-key observations. Everything a worker touches is atomic.
struct Observed {
    std::array<std::atomic<int>, kKeys> running{};
    std::vector<std::atomic<int>> runs = std::vector<std::atomic<int>>(kMaxJobs);
    std::vector<std::atomic<int>> completes = std::vector<std::atomic<int>>(kMaxJobs);
    std::vector<std::atomic<int>> destroyed = std::vector<std::atomic<int>>(kMaxJobs);
    std::atomic<int> next_id{0}, live{0}, not_completed{0};
    std::atomic<int> two_in_flight{0}, ran_twice{0}, bad_complete{0};
    std::array<uint64_t, kKeys> last_applied{}; // Main thread only.
    std::thread::id main_thread = std::this_thread::get_id();
};

class StressJob final : public Job {
public:
    StressJob(Observed& o, int key_index, CancellationToken token)
        : Job(key_of(key_index), std::move(token)), m_o(o), m_k(key_index), m_id(o.next_id++) {
        ++m_o.live;
    }
    ~StressJob() override {
        ++m_o.destroyed[size_t(m_id)];
        if (m_o.completes[size_t(m_id)].load() == 0)
            ++m_o.not_completed;
        --m_o.live;
    }
    int id() const { return m_id; }

    void run(JobContext& ctx) override {
        if (m_o.running[size_t(m_k)].fetch_add(1) != 0)
            ++m_o.two_in_flight;
        if (m_o.runs[size_t(m_id)].fetch_add(1) != 0)
            ++m_o.ran_twice;
        // A little work, polled for cancellation like a long job would.
        uint32_t h = uint32_t(m_id);
        for (int step = 0; step < 16 && !ctx.is_cancelled(); ++step)
            for (int i = 0; i < 1000; ++i)
                h = h * 1664525u + 1013904223u;
        m_result = h;
        m_o.running[size_t(m_k)].fetch_sub(1);
    }
    void complete() override {
        const bool on_main = std::this_thread::get_id() == m_o.main_thread;
        const bool ran_once = m_o.runs[size_t(m_id)].load() == 1;
        const bool first = m_o.completes[size_t(m_id)].fetch_add(1) == 0;
        // Stale results are dropped, so applied generations of a key only grow.
        const bool newer = generation() > m_o.last_applied[size_t(m_k)];
        m_o.last_applied[size_t(m_k)] = generation();
        if (!on_main || !ran_once || !first || !newer)
            ++m_o.bad_complete;
    }

private:
    Observed& m_o;
    int m_k;
    int m_id;
    uint32_t m_result = 0;
};

void submitter(JobSystem& jobs, Observed& o, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<CancellationToken> recent;
    CancellationToken group;
    for (int op = 0; op < kOpsPerThread; ++op) {
        const int k = int(rng() % kKeys);
        const unsigned r = rng() % 100;
        if (r < 50) {
            recent.push_back(jobs.submit(std::make_unique<StressJob>(o, k, CancellationToken{})).token);
        } else if (r < 60) {
            // Resubmit right away: replaces the queued job or supersedes the running one.
            jobs.submit(std::make_unique<StressJob>(o, k, CancellationToken{}));
            jobs.submit(std::make_unique<StressJob>(o, k, CancellationToken{}));
        } else if (r < 65) {
            std::vector<std::unique_ptr<Job>> batch; // May hold one key twice.
            for (int i = 0; i < 3; ++i)
                batch.push_back(std::make_unique<StressJob>(o, int(rng() % kKeys), CancellationToken{}));
            jobs.submit_batch(std::move(batch));
        } else if (r < 75) {
            jobs.submit(std::make_unique<StressJob>(o, k, group)); // Shares the group's token.
        } else if (r < 85) {
            jobs.cancel(key_of(k));
        } else if (r < 92 && !recent.empty()) {
            recent[rng() % recent.size()].cancel();
        } else if (r < 96) {
            jobs.set_viewer({glm::dvec3(rng() % 400, 0, 0), glm::dvec3(double(rng() % 3) - 1.0, 0, 1)});
        } else if (r < 99) {
            group.cancel();
            group = CancellationToken{};
        } else {
            jobs.cancel_all();
        }
        if (recent.size() > 64)
            recent.erase(recent.begin(), recent.begin() + 32);
        std::this_thread::yield(); // Let workers make progress between operations.
    }
}

} // namespace

TEST(JobSystemStress, ConcurrentSubmitCancelResubmitKeepsInvariants) {
    Observed o;
    {
        JobSystem jobs(test_info(3));
        std::atomic<int> done{0};
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t)
            threads.emplace_back([&, t] {
                submitter(jobs, o, 1234u + unsigned(t));
                ++done;
            });
        // Main thread: a frame loop with small budgets, occasional pauses.
        for (int frame = 0; done.load() < kThreads; ++frame) {
            if (frame % 50 == 0)
                jobs.pause();
            else if (frame % 50 == 1)
                jobs.resume();
            jobs.process_completions({std::chrono::microseconds(200), 64});
            const JobMetrics m = jobs.metrics();
            EXPECT_LE(m.in_flight, size_t(jobs.worker_count() + 1));
            std::this_thread::yield();
        }
        for (std::thread& t : threads)
            t.join();
        jobs.resume();
        // One last uncancelled job per key: each must complete.
        for (int k = 0; k < kKeys; ++k)
            jobs.submit(std::make_unique<StressJob>(o, k, CancellationToken{}));
        drain(jobs);
        for (int k = 0; k < kKeys; ++k)
            EXPECT_GT(o.last_applied[size_t(k)], 0u) << "key " << k;

        const JobMetrics m = jobs.metrics();
        EXPECT_EQ(m.queued + m.in_flight + m.awaiting_completion, 0u);
        EXPECT_EQ(m.submitted, uint64_t(o.next_id.load()));
        EXPECT_EQ(m.submitted, m.completed + m.cancelled + m.dropped_stale);
        EXPECT_EQ(o.live.load(), 0); // Drained: every job object is gone.
        EXPECT_EQ(uint64_t(o.not_completed.load()), m.cancelled + m.dropped_stale);
        EXPECT_GE(m.completed, uint64_t(kKeys));
        std::printf("stress: submitted %llu completed %llu cancelled %llu (replaced %llu) dropped_stale %llu "
                    "run %.1f ms wasted %.1f ms\n",
                    (unsigned long long)m.submitted, (unsigned long long)m.completed,
                    (unsigned long long)m.cancelled, (unsigned long long)m.replaced,
                    (unsigned long long)m.dropped_stale, m.run_time.count() / 1e6, m.wasted_work.count() / 1e6);

        // Then shut down with work outstanding.
        for (int i = 0; i < 2000; ++i)
            jobs.submit(std::make_unique<StressJob>(o, i % kKeys, CancellationToken{}));
    }
    EXPECT_EQ(o.two_in_flight.load(), 0);
    EXPECT_EQ(o.ran_twice.load(), 0);
    EXPECT_EQ(o.bad_complete.load(), 0);
    EXPECT_EQ(o.live.load(), 0);
    uint64_t total_completes = 0;
    for (int id = 0; id < o.next_id.load(); ++id) {
        ASSERT_EQ(o.destroyed[size_t(id)].load(), 1) << "job " << id;
        ASSERT_LE(o.completes[size_t(id)].load(), 1) << "job " << id;
        if (o.completes[size_t(id)].load() == 1) {
            ASSERT_EQ(o.runs[size_t(id)].load(), 1) << "job " << id;
        }
        total_completes += uint64_t(o.completes[size_t(id)].load());
    }
    EXPECT_EQ(total_completes + uint64_t(o.not_completed.load()), uint64_t(o.next_id.load()));
}
