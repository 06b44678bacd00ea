#pragma once
// Blocking batches on the job system: the CLI's and tools' way to fan a fixed set of jobs out on
// the engine's one pool (or its I/O lane) and wait for all of them. A frame-driven caller (the
// streamer) submits and polls instead; a batch owns the system until it returns.

#include <functional>
#include <memory>
#include <vector>

#include "engine/job_system.h"

namespace vx::engine {

// What one batch did. Plain value (not thread-safe).
struct BatchStats {
    size_t completed = 0; // complete() calls made for this batch's jobs.
    size_t dropped = 0;   // Jobs cancelled or stale (a duplicate key, a cancel from elsewhere).
    double seconds = 0;   // Wall time from submit to the last complete(), steady clock.
};

// Main thread of `jobs`. Submits `batch` in one go and blocks until every job of it has run and
// its complete() has been called on this thread. Jobs should have distinct keys: a later job of a
// key replaces an earlier one (key rule in job_system.h), which then counts as dropped. Waits for
// every job in the system, not only the batch's, so other users must not keep it busy forever;
// their finished results are completed here too. Jobs' complete() may submit follow-up jobs
// (a save after a generation): the batch waits for those as well. `tick`, when given, is called on
// this thread about every 50 ms while the batch runs (progress bars); results are then applied as
// they come instead of after the pool is idle.
BatchStats run_batch(JobSystem& jobs, std::vector<std::unique_ptr<Job>> batch,
                     const std::function<void()>& tick = {});

// Thread-safe (pure). A job system for a process whose main thread only waits on batches:
// `threads` pool workers, or one per hardware thread when 0 (all cores, at least 1).
JobSystemCreateInfo batch_job_system_info(unsigned threads = 0);

} // namespace vx::engine
