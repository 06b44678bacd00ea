#pragma once
// The job system of vx: a pool of worker threads for CPU jobs, ordered by distance to the viewer,
// plus a serial lane for disk I/O, with results applied on the main thread under a time budget.
//
// Policies (what a caller can rely on):
// - Priority (pool lane): lowest priority_score() first (engine/job_priority.h), ties in
//   submission order. Scores follow the viewer: set_viewer() bumps an epoch when the viewer moved
//   or turned enough, and the next worker to pop re-scores and re-heaps the queue once.
// - Key rule: at most one job per JobKey runs at a time, and at most one waits. A submit for a key
//   that already has a queued (not started) job REPLACES it: the old job is destroyed unrun and
//   counted as cancelled (metric `replaced` too). A submit while a job of the key runs marks the
//   running one abandoned (its JobContext::is_cancelled() turns true) and queues the new one; on
//   the pool lane the new job is parked until the running one returns, so two never run at once.
// - Generations: every submit takes a new, globally increasing generation; the key remembers its
//   latest. A job whose generation is older than its key's latest when it finishes running, or
//   when the main thread is about to complete it, is discarded (dropped-stale): complete() only
//   ever applies the newest requested result of a key.
// - Cancellation: a job's token is checked before it starts, by the job itself through
//   JobContext::is_cancelled() while it runs, after it returns and again before complete(). A
//   cancelled job never completes. cancel(key) cancels everything of a key submitted so far and
//   frees its queued job at once; a job cancelled only through its token stays queued (counted in
//   `queued`) until a worker reaches it and drops it unrun.
// - I/O lane: jobs of kinds whose lane_of() is Io run on one dedicated thread, one at a time, in
//   submission order. The lane ignores the viewer: disk order is the caller's order (a save
//   submitted before a load of the same chunk is written first). A replacing save (or other
//   write: Save, IoTask) takes the place in line of the job it replaces, so a job submitted after
//   the first request still runs after the data of that request (or newer) is written; moving it
//   to the back could let a later load read older data than an earlier save. A replacing load
//   goes to the back: it must read every save submitted before it. In its replaced job's place it
//   ran ahead of a save queued between the two (a chunk unloaded with an edit while its reload
//   waited, then loaded again, came back without the edit).
// - Continuations: a job's take_continuation() is submitted by the worker that ran it, under the
//   lock that hands the job's own result over, and only if that result is still wanted; the
//   follow-up then follows the rules above like any submit (chains need no main thread).
// - Completion: process_completions() runs complete() of finished jobs, oldest first, until the
//   budget is spent; the rest wait for the next call. Budget checks happen before each job, so the
//   last one may overrun by its own duration. A zero time budget applies nothing.
// - Shutdown: the destructor cancels queued jobs, tells running ones to stop (is_cancelled()),
//   joins every thread and discards finished results: no complete() runs after destruction.
//
// Use (main thread, per frame):
//   jobs.set_viewer({camera_pos, camera_dir});
//   jobs.submit_batch(std::move(new_requests));      // Or submit() one at a time, from any thread.
//   jobs.process_completions({std::chrono::milliseconds(2)});
//
// Why not oneTBB: the core needs one lock anyway (per-key state, generations and the re-heaped
// priority queue change together), so TBB's lock-free queues would not remove it, and TBB's
// arenas cannot re-prioritize or cancel queued work. Plain std::thread/mutex/condition_variable
// keep the system small and clean under ThreadSanitizer. Cost of that lock, measured on a
// 16-core H200 host with 8192 jobs of 30 µs: about 1 µs of overhead per job; 3 workers reach 94%
// and 7 workers 89% of linear speed-up, 15 workers only ~65% (lock contention). TODO: if jobs
// shorter than ~30 µs must scale past 8 workers, pop several jobs per lock acquisition.

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "engine/job.h"
#include "engine/job_priority.h"

namespace vx::engine {

// Creation parameters. Plain value (not thread-safe).
// The most pool workers a JobSystem starts (the facade and the CLI refuse more).
inline constexpr int kMaxWorkerThreads = 256;

struct JobSystemCreateInfo {
    int worker_count = 0;            // Pool workers, at most kMaxWorkerThreads; <= 0: hardware threads - 1, at least 1.
    double view_weight = 1.0;        // See priority_score(); 0 = pure distance.
    double reprioritize_distance = 8.0; // Blocks the viewer must move before the queue is re-scored.
    double reprioritize_cos = 0.985; // Re-score when the view direction turns past this (cos ~10°).
    bool start_paused = false;       // Start with workers paused (see pause()).
    // Clock for completion budgets and completion-time metrics; nanoseconds since any fixed origin.
    // Default: std::chrono::steady_clock. Tests pass a fake clock. Called on the main thread only.
    std::function<std::chrono::nanoseconds()> clock;
};

// How much main-thread work process_completions() may do this frame. Plain value (not thread-safe).
struct CompletionBudget {
    std::chrono::nanoseconds time{std::chrono::milliseconds(2)};
    size_t max_count = SIZE_MAX; // Also stop after this many complete() calls.
    size_t min_count = 0;        // Apply at least this many (while any wait), whatever the time.
};

// What one process_completions() call did. Plain value (not thread-safe).
struct CompletionStats {
    size_t applied = 0;   // complete() calls made.
    size_t discarded = 0; // Finished results dropped (stale or cancelled) instead of completed.
    size_t remaining = 0; // Finished results left for the next call.
    std::chrono::nanoseconds time_used{0}; // By the system's clock.
};

// A snapshot of the system's state (a plain value, not thread-safe; metrics() is). Gauges are exact at the time of the call; counters are
// cumulative since construction. Every submitted job ends in exactly one of completed, cancelled
// or dropped_stale, so once idle and drained: submitted == completed + cancelled + dropped_stale.
struct JobMetrics {
    size_t queued = 0;              // Submitted, not started (parked jobs included).
    size_t in_flight = 0;           // Running now.
    size_t awaiting_completion = 0; // Finished, waiting for process_completions().
    uint64_t submitted = 0;
    uint64_t completed = 0;     // complete() returned.
    uint64_t cancelled = 0;     // Token, cancel(key), replacement or shutdown; never completed.
    uint64_t replaced = 0;      // Subset of cancelled: queued jobs replaced by a newer submit.
    uint64_t dropped_stale = 0; // Ran, but a newer job of the key had been submitted.
    uint64_t heap_rebuilds = 0; // Re-prioritizations of the pool queue (and dead-entry purges).
    std::chrono::nanoseconds run_time{0};    // Total time in run(), all workers.
    std::chrono::nanoseconds wasted_work{0}; // run() time of jobs whose result was dropped.
    std::chrono::nanoseconds last_completion_time{0}; // Main-thread time of the last frame's call.
    std::chrono::nanoseconds max_completion_time{0};
    std::chrono::nanoseconds total_completion_time{0};
};

// What submit() hands back: enough to recognise the job's result or cancel it. Plain value; its
// token is thread-safe.
struct JobTicket {
    JobKey key;
    uint64_t generation = 0; // 0: rejected (the system is shutting down).
    CancellationToken token;
};

// Owns the worker threads. The thread that constructs a JobSystem is its main thread.
class JobSystem {
public:
    // Main thread. Starts the pool workers and the I/O thread. The system may hold fewer threads
    // than asked for when the OS refuses one (a thread limit, no memory for a stack): see
    // start_error() and worker_count().
    explicit JobSystem(const JobSystemCreateInfo& info = {});
    // Main thread. Cancels queued jobs, stops running ones, joins; see the file comment.
    ~JobSystem();
    JobSystem(const JobSystem&) = delete;
    JobSystem& operator=(const JobSystem&) = delete;

    // Thread-safe: any thread, also from inside run() or complete(). Takes ownership; see the key
    // rule. Never blocks on running jobs.
    JobTicket submit(std::unique_ptr<Job> job);
    // Thread-safe. submit() for many jobs under one lock and one wake-up, in vector order (what a
    // streaming frame does). Tickets are in the same order.
    std::vector<JobTicket> submit_batch(std::vector<std::unique_ptr<Job>> jobs);
    // Thread-safe. Cancels every job of `key` submitted so far: drops the queued one, tells the
    // running one to stop and discards finished results. Returns whether there was any.
    bool cancel(const JobKey& key);
    // Thread-safe. cancel() for every key.
    void cancel_all();

    // Thread-safe. Moves the viewer that pool priorities are measured from. Cheap: re-scoring
    // happens lazily on the next pop, and only when the viewer moved or turned past the thresholds.
    void set_viewer(const Viewer& viewer);

    // Main thread only. Completes finished jobs within the budget (see the file comment).
    CompletionStats process_completions(const CompletionBudget& budget = {});
    // The new main thread: the calling one. Its owner moves it between threads (a game created its
    // engine on a loading thread); the old thread no longer uses it, and the owner's own
    // synchronisation (a join, a mutex) orders the two.
    void adopt_main_thread() { m_main_thread = std::this_thread::get_id(); }

    // Thread-safe. While paused no job starts (running ones continue); submits still queue.
    void pause();
    void resume();
    // Thread-safe; never from inside a job, nor while paused with jobs queued (would never return).
    // Blocks until no job is queued or running. Finished results may still await completion.
    void wait_idle();

    // Thread-safe.
    JobMetrics metrics() const;
    // Thread-safe. The pool workers that started (fewer than asked where the OS refused some).
    int worker_count() const { return int(m_pool_threads.size()); }
    // Thread-safe. Why the system cannot run jobs ("" when it can): the OS refused the I/O thread
    // or every pool worker. Its owner must not wait for jobs then; destroying it is safe.
    const std::string& start_error() const { return m_start_error; }
    // Thread-safe. How many of the pool workers asked for the OS refused (the system runs on the
    // rest), and its reason ("" when none).
    int refused_workers() const { return m_refused_workers; }
    const std::string& refused_reason() const { return m_refused_reason; }

private:
    struct KeyState {
        uint64_t latest = 0;            // Generation of the newest submission.
        uint64_t cancelled_through = 0; // cancel(key): generations <= this are cancelled.
        std::unique_ptr<Job> queued;    // Newest job not yet started.
        glm::dvec3 queued_position{0.0};
        bool parked = false;   // Pool: `queued` waits for `running`; it has no heap entry.
        uint64_t io_entry = 0; // I/O: the sequence of the m_io_queue entry `queued` holds; 0 none.
        Job* running = nullptr; // Owned by the worker running it.
        uint32_t awaiting = 0; // Finished jobs of this key in m_completions.
        bool idle() const { return !queued && !running && awaiting == 0; }
    };
    enum class Outcome { Ok, Cancelled, Stale };
    struct Wake {
        size_t pool = 0; // Pool workers to wake.
        bool io = false;
    };
    // unordered_map keeps element addresses stable until erasure, and a key's state is not erased
    // while a job of it runs or awaits completion: workers and completions hold it by pointer.
    struct Finished {
        std::unique_ptr<Job> job;
        KeyState* state = nullptr;
    };
    struct IoEntry {
        JobKey key;
        uint64_t sequence = 0; // Live while the key's io_entry equals it.
    };
    JobTicket submit_nolock(std::unique_ptr<Job> job, const glm::dvec3& position, std::unique_ptr<Job>& replaced,
                            Wake& wake);
    void decide_wake_nolock(Wake& wake) const;
    void notify(const Wake& wake);
    void worker_main(JobLane lane, int worker_index);
    bool has_work_nolock(JobLane lane) const;
    std::unique_ptr<Job> pop_job_nolock(JobLane lane, KeyState*& state);
    std::unique_ptr<Job> finish_run_nolock(std::unique_ptr<Job> job, KeyState& state);
    std::unique_ptr<Job> pop_completion(Outcome& outcome);
    Outcome classify_nolock(const Job& job, const KeyState& state) const;
    void count_dropped_nolock(const Job& job, Outcome outcome);
    std::unique_ptr<Job> cancel_nolock(KeyState& state);
    void enqueue_pool_nolock(const JobKey& key, KeyState& state);
    void erase_if_idle_nolock(const JobKey& key, const KeyState& state);
    void notify_if_idle_nolock();
    bool is_live_nolock(const JobKey& key, uint64_t generation) const;
    std::chrono::nanoseconds now() const;

    JobSystemCreateInfo m_info;
    std::thread::id m_main_thread;

    mutable std::mutex m_mutex;
    std::condition_variable m_pool_cv;
    std::condition_variable m_io_cv;
    std::condition_variable m_idle_cv;
    std::atomic<bool> m_stopping{false}; // Read without the lock by JobContext.
    bool m_paused = false;
    size_t m_pool_waiting = 0; // Threads asleep on each lane's condition variable.
    size_t m_io_waiting = 0;

    std::unordered_map<JobKey, KeyState, JobKeyHash> m_keys;
    PriorityJobQueue m_pool_queue;
    std::deque<IoEntry> m_io_queue;
    std::deque<Finished> m_completions;
    Viewer m_viewer;
    uint64_t m_viewer_epoch = 0;
    uint64_t m_next_generation = 0;
    uint64_t m_next_sequence = 0;
    JobMetrics m_counters; // Gauges and counters, all under m_mutex.

    std::vector<std::thread> m_pool_threads;
    std::thread m_io_thread;
    std::string m_start_error, m_refused_reason; // Set in the constructor only.
    int m_refused_workers = 0;
};

} // namespace vx::engine
