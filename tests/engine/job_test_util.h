#pragma once
// Helpers for job-system tests: one-shot gates, thread-safe recorders and a drain loop. No sleeps:
// tests wait on events, so they never fail because the machine is slow.

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <vector>

#include "engine/job_system.h"

namespace vx::engine::test {

// A one-shot event: wait() blocks until open() was called. Thread-safe.
class Gate {
public:
    void open() {
        {
            std::lock_guard lock(m_mutex);
            m_open = true;
        }
        m_cv.notify_all();
    }
    void wait() {
        std::unique_lock lock(m_mutex);
        m_cv.wait(lock, [this] { return m_open; });
    }
    bool is_open() const {
        std::lock_guard lock(m_mutex);
        return m_open;
    }

private:
    mutable std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_open = false;
};

// An append-only list of ints shared by threads. Thread-safe.
class Recorder {
public:
    void add(int v) {
        std::lock_guard lock(m_mutex);
        m_values.push_back(v);
    }
    std::vector<int> values() const {
        std::lock_guard lock(m_mutex);
        return m_values;
    }

private:
    mutable std::mutex m_mutex;
    std::vector<int> m_values;
};

inline JobKey key_at(int x, int y, int z, JobKind kind = JobKind::Mesh) { return JobKey{world::ChunkCoord(x, y, z), kind}; }

// The centre of a chunk in world block coordinates (Job::priority_position's default).
inline glm::dvec3 chunk_centre(int x, int y, int z) {
    return glm::dvec3(x * 32.0 + 16.0, y * 32.0 + 16.0, z * 32.0 + 16.0);
}

inline std::unique_ptr<Job> make_job(JobKey key, std::function<void(JobContext&)> run,
                                     std::function<void()> complete = {}) {
    return std::make_unique<FunctionJob>(key, std::move(run), std::move(complete));
}

// Main thread. Waits for all queued work, then completes everything with no budget limit.
inline size_t drain(JobSystem& jobs) {
    jobs.wait_idle();
    CompletionBudget unlimited;
    unlimited.time = std::chrono::hours(1);
    return jobs.process_completions(unlimited).applied;
}

// Main thread. A create-info for deterministic tests: n workers, every viewer change re-scores.
inline JobSystemCreateInfo test_info(int workers, bool paused = false) {
    JobSystemCreateInfo info;
    info.worker_count = workers;
    info.reprioritize_distance = 0.0;
    info.start_paused = paused;
    return info;
}

} // namespace vx::engine::test
