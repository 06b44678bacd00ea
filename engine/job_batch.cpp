#include "engine/job_batch.h"

#include <chrono>
#include <thread>

namespace vx::engine {

BatchStats run_batch(JobSystem& jobs, std::vector<std::unique_ptr<Job>> batch) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const JobMetrics before = jobs.metrics();
    jobs.submit_batch(std::move(batch));
    BatchStats stats;
    // wait_idle() returns once nothing is queued or running; completions then run here, and may
    // submit follow-up jobs, so loop until the system is idle with nothing left to complete.
    for (;;) {
        jobs.wait_idle();
        const CompletionStats c = jobs.process_completions({std::chrono::nanoseconds::max(), SIZE_MAX});
        const JobMetrics m = jobs.metrics();
        if (c.remaining == 0 && m.queued == 0 && m.in_flight == 0 && m.awaiting_completion == 0)
            break;
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
