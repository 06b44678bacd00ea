#pragma once
// Jobs of the vx job system: the unit of work a JobSystem runs off the main thread.
//
// A job is a snapshot: it owns every input it reads (a chunk copy plus its apron, a file path, a
// seed) and never points into the live World, which only the main thread touches (Luanti
// MeshMakeData; godot_voxel IThreadedTask). Its life:
//   submit (any thread) -> queued -> run(JobContext&) on a worker -> complete() on the main thread,
// unless it is cancelled, replaced by a newer job for the same key, or its result goes stale.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>

#include <glm/glm.hpp>

#include "world/coords.h"

namespace vx::engine {

// What a job does. Together with a chunk it forms the job's key (at most one job in flight per key).
enum class JobKind : uint8_t {
    Load,     // Read a chunk record from disk. I/O lane.
    Save,     // Write a chunk record to disk. I/O lane.
    Generate, // Generate terrain for a chunk. Pool.
    Mesh,     // Mesh a chunk snapshot. Pool.
    Light,    // Compute lighting for a chunk snapshot. Pool.
    Task,     // Any other CPU work keyed by a chunk. Pool.
    IoTask,   // Any other disk work keyed by a chunk. I/O lane.
};
inline constexpr int kJobKindCount = 7;

// Where a kind runs. Pool: the worker threads, by priority. Io: one dedicated thread, one job at a
// time, in submission order (disk access is serial so reads and writes of a chunk never race).
enum class JobLane : uint8_t { Pool, Io };

// Thread-safe (pure).
constexpr JobLane lane_of(JobKind kind) {
    return (kind == JobKind::Load || kind == JobKind::Save || kind == JobKind::IoTask) ? JobLane::Io
                                                                                      : JobLane::Pool;
}
// Thread-safe (pure). A short lowercase name for logs.
const char* job_kind_name(JobKind kind);

// Identity of a job: a chunk and what is done to it. Plain value. Thread-safe (pure).
struct JobKey {
    world::ChunkCoord chunk{0};
    JobKind kind = JobKind::Task;
    uint8_t level = 0; // Level of detail of `chunk` (world/lod/lod_coords.h); 0: blocks.

    bool operator==(const JobKey&) const = default;
};

// Thread-safe (pure).
struct JobKeyHash {
    size_t operator()(const JobKey& k) const noexcept {
        return world::ChunkCoordHash{}(k.chunk) ^ (size_t(k.kind) * 0x9E3779B97F4A7C15ull) ^
               (size_t(k.level) * 0xC2B2AE3D27D4EB4Full);
    }
};

// A shared cancellation flag. Copies share the flag, so one token may cancel a group of jobs (for
// example every job of a region being unloaded). Thread-safe.
class CancellationToken {
public:
    CancellationToken() : m_flag(std::make_shared<std::atomic<bool>>(false)) {}

    // Thread-safe. Idempotent; a cancelled token never becomes uncancelled.
    void cancel() const { m_flag->store(true, std::memory_order_release); }
    // Thread-safe.
    bool is_cancelled() const { return m_flag->load(std::memory_order_acquire); }

private:
    std::shared_ptr<std::atomic<bool>> m_flag;
};

class Job;

// What a running job may ask of the system. Handed to Job::run; valid only during that call.
// Not thread-safe: used by the one worker running the job. Tests may construct one to run a job
// by itself.
class JobContext {
public:
    JobContext(const Job& job, const std::atomic<bool>& stopping, int worker_index)
        : m_job(job), m_stopping(stopping), m_worker_index(worker_index) {}

    // True once the job's token is cancelled, a newer job for the same key was submitted (this
    // result would be dropped as stale), or the JobSystem is shutting down. Long jobs poll it
    // between steps and return early; whatever they return is then discarded. Cheap (atomic loads).
    bool is_cancelled() const;
    // 0..workers-1 for pool workers; -1 for the I/O lane. For per-worker scratch memory.
    int worker_index() const { return m_worker_index; }

private:
    const Job& m_job;
    const std::atomic<bool>& m_stopping;
    int m_worker_index;
};

// Base class of all jobs. Subclasses own their inputs and outputs.
// Construction and submission: any thread. run(): one worker thread, at most once. complete():
// the main thread, at most once, only after run() returned and only if the result is still wanted.
// A job is destroyed on whichever thread drops it (worker, main, or the submitting thread when it
// replaces a queued job): destructors must be thread-agnostic.
class Job {
public:
    // Thread-safe. The token defaults to a fresh one; pass a shared token to cancel jobs as a group.
    Job(JobKey key, CancellationToken token = {}) : m_key(key), m_token(std::move(token)) {}
    virtual ~Job() = default;
    Job(const Job&) = delete;
    Job& operator=(const Job&) = delete;

    // Worker thread. Does the work on the job's own snapshot; polls ctx.is_cancelled() when long.
    // Must not throw (vx code throws no exceptions; an escaping one terminates the program).
    virtual void run(JobContext& ctx) = 0;
    // Main thread. Applies the result (e.g. stores a mesh, uploads it). Must re-check that its
    // target still exists: the chunk may have been unloaded since submission. May submit jobs.
    virtual void complete() = 0;

    // Worker thread, once, right after run() returned. A follow-up job to submit, or null (the
    // default): e.g. a load that found nothing hands its chunk to a generate job, so a miss
    // reaches the pool without a hop through the main thread. The system submits the follow-up
    // under the same lock that hands this job's result to the main thread, and only if that
    // result is still wanted (not cancelled, not stale): cancelling this job before it finishes
    // cancels the follow-up too. The follow-up needs a key of its own (it would otherwise make
    // this job's result stale).
    virtual std::unique_ptr<Job> take_continuation() { return nullptr; }

    // Any thread, called once at submission. The point whose distance to the viewer orders pool
    // jobs, in world block coordinates. Default: the centre of the key's chunk.
    virtual glm::dvec3 priority_position() const;

    // Thread-safe.
    const JobKey& key() const { return m_key; }
    // Thread-safe.
    const CancellationToken& token() const { return m_token; }
    // Thread-safe. Set by JobSystem::submit; 0 before. Globally unique and increasing.
    uint64_t generation() const { return m_generation; }

private:
    friend class JobSystem;
    friend class JobContext;

    JobKey m_key;
    CancellationToken m_token;
    uint64_t m_generation = 0;               // Written under the system lock before the job is shared.
    std::atomic<bool> m_abandoned{false};    // Newer submit or cancel(key): stop early.
    std::chrono::nanoseconds m_run_time{0};  // Wall time of run(); for the wasted-work metric.
};

// A job built from two callables, for small jobs and tests. Same thread rules as Job.
class FunctionJob final : public Job {
public:
    FunctionJob(JobKey key, std::function<void(JobContext&)> run_fn, std::function<void()> complete_fn,
                CancellationToken token = {})
        : Job(key, std::move(token)), m_run(std::move(run_fn)), m_complete(std::move(complete_fn)) {}

    void run(JobContext& ctx) override {
        if (m_run)
            m_run(ctx);
    }
    void complete() override {
        if (m_complete)
            m_complete();
    }

private:
    std::function<void(JobContext&)> m_run;
    std::function<void()> m_complete;
};

} // namespace vx::engine
