#include "engine/job_batch.h"

#include <chrono>
#include <thread>

namespace vx::engine {

BatchStats run_batch(JobSystem& jobs, std::vector<std::unique_ptr<Job>> batch, const std::function<void()>& tick) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const JobMetrics before = jobs.metrics();
    jobs.submit_batch(std::move(batch));
    BatchStats stats;
    const CompletionBudget all{std::chrono::nanoseconds::max(), SIZE_MAX};
    const CompletionBudget slice{std::chrono::milliseconds(50), SIZE_MAX};
    // Completions may submit follow-up jobs: done only when nothing is queued, running or waiting.
    for (;;) {
        if (!tick)
            jobs.wait_idle();
        jobs.process_completions(tick ? slice : all);
        const JobMetrics m = jobs.metrics();
        if (m.queued == 0 && m.in_flight == 0 && m.awaiting_completion == 0)
            break;
        if (tick) {
            tick();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    const JobMetrics after = jobs.metrics();
    stats.completed = size_t(after.completed - before.completed);
    stats.dropped = size_t((after.cancelled - before.cancelled) + (after.dropped_stale - before.dropped_stale));
    stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return stats;
}

JobSystemCreateInfo batch_job_system_info(unsigned threads) {
    JobSystemCreateInfo info;
    const unsigned hw = std::thread::hardware_concurrency();
    info.worker_count = threads > 0 ? int(threads) : hw > 0 ? int(hw) : 1;
    return info;
}

} // namespace vx::engine
