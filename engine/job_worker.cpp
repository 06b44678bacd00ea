// JobSystem: the worker loop (both lanes) and main-thread completion.

#include "engine/job_system.h"

#include "world/base/assert.h"

namespace vx::engine {
namespace {

std::chrono::nanoseconds elapsed_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0);
}

} // namespace

bool JobSystem::has_work_nolock(JobLane lane) const {
    return lane == JobLane::Pool ? !m_pool_queue.empty() : !m_io_queue.empty();
}

// Pops the next live job of a lane and takes it out of its key's slot; null if only dead entries
// were left.
std::unique_ptr<Job> JobSystem::pop_job_nolock(JobLane lane, KeyState*& state) {
    state = nullptr;
    // One map lookup per entry: the liveness check remembers the state it found.
    auto live = [this, &state](const JobKey& key, uint64_t generation) {
        auto it = m_keys.find(key);
        if (it == m_keys.end() || !it->second.queued || it->second.queued->m_generation != generation)
            return false;
        state = &it->second;
        return true;
    };
    if (lane == JobLane::Pool) {
        QueueEntry e;
        if (!m_pool_queue.pop([&](const QueueEntry& q) { return live(q.key, q.generation); }, e))
            return nullptr;
    } else {
        auto io_live = [this, &state](const IoEntry& e) {
            auto it = m_keys.find(e.key);
            if (it == m_keys.end() || !it->second.queued || it->second.io_entry != e.sequence)
                return false;
            state = &it->second;
            return true;
        };
        while (!m_io_queue.empty() && !io_live(m_io_queue.front()))
            m_io_queue.pop_front();
        if (m_io_queue.empty())
            return nullptr;
        m_io_queue.pop_front();
        state->io_entry = 0;
    }
    VX_ASSERT_MSG(state->running == nullptr, "two jobs of one key would run at once");
    --m_counters.queued;
    return std::move(state->queued);
}

void JobSystem::worker_main(JobLane lane, int worker_index) {
    std::condition_variable& cv = lane == JobLane::Pool ? m_pool_cv : m_io_cv;
    size_t& waiting = lane == JobLane::Pool ? m_pool_waiting : m_io_waiting;
    std::unique_lock lock(m_mutex);
    for (;;) {
        while (!m_stopping.load(std::memory_order_relaxed) && (m_paused || !has_work_nolock(lane))) {
            ++waiting; // Lets submitters skip notifying when no one sleeps.
            cv.wait(lock);
            --waiting;
        }
        if (m_stopping.load(std::memory_order_relaxed))
            return;
        KeyState* state = nullptr;
        std::unique_ptr<Job> job = pop_job_nolock(lane, state);
        if (!job) {
            notify_if_idle_nolock();
            continue;
        }
        if (job->token().is_cancelled() || job->m_generation <= state->cancelled_through) {
            ++m_counters.cancelled; // Cancelled before it started: never runs.
            erase_if_idle_nolock(job->key(), *state);
            notify_if_idle_nolock();
            lock.unlock();
            job.reset();
            lock.lock();
            continue;
        }
        state->running = job.get(); // From here until finish_run_nolock, `state` stays valid.
        ++m_counters.in_flight;
        lock.unlock();

        JobContext ctx(*job, m_stopping, worker_index);
        const auto t0 = std::chrono::steady_clock::now();
        job->run(ctx);
        job->m_run_time = elapsed_since(t0); // Published to other threads by the lock below.
        std::unique_ptr<Job> next = job->take_continuation();
        const glm::dvec3 next_position = next ? next->priority_position() : glm::dvec3(0.0);
        VX_ASSERT_MSG(!next || !(next->key() == job->key()), "a continuation needs a key of its own");

        lock.lock();
        const bool wanted = classify_nolock(*job, *state) == Outcome::Ok;
        std::unique_ptr<Job> dropped = finish_run_nolock(std::move(job), *state);
        std::unique_ptr<Job> next_replaced;
        Wake wake;
        if (next && wanted) {
            // Same lock as the hand-over above: no moment where neither job is queued (wait_idle),
            // and a cancel of the parent after this point finds the follow-up queued.
            submit_nolock(std::move(next), next_position, next_replaced, wake);
            decide_wake_nolock(wake);
        }
        if (dropped || next || next_replaced || wake.pool > 0 || wake.io) {
            lock.unlock();
            notify(wake);
            dropped.reset();
            next.reset(); // Not wanted: destroyed unrun, never counted (it was never submitted).
            next_replaced.reset();
            lock.lock();
        }
    }
}

// Bookkeeping after run(): hands a wanted result to the main thread, counts an unwanted one, and
// releases a job of the same key that was parked behind this one. Returns the job to destroy.
std::unique_ptr<Job> JobSystem::finish_run_nolock(std::unique_ptr<Job> job, KeyState& state) {
    const JobKey key = job->key();
    VX_ASSERT(state.running == job.get());
    state.running = nullptr;
    --m_counters.in_flight;
    m_counters.run_time += job->m_run_time;

    const Outcome outcome = classify_nolock(*job, state);
    if (outcome == Outcome::Ok) {
        ++state.awaiting;
        m_completions.push_back({std::move(job), &state});
    } else {
        count_dropped_nolock(*job, outcome);
    }
    if (state.parked && state.queued) {
        enqueue_pool_nolock(key, state);
        if (!m_paused && m_pool_waiting > 0) // This worker may pick another job: wake a sleeper.
            m_pool_cv.notify_one();
    }
    erase_if_idle_nolock(key, state);
    notify_if_idle_nolock();
    return job; // Null when handed over.
}

JobSystem::Outcome JobSystem::classify_nolock(const Job& job, const KeyState& state) const {
    if (m_stopping.load(std::memory_order_relaxed) || job.token().is_cancelled() ||
        job.m_generation <= state.cancelled_through)
        return Outcome::Cancelled;
    if (job.m_generation != state.latest)
        return Outcome::Stale;
    return Outcome::Ok;
}

void JobSystem::count_dropped_nolock(const Job& job, Outcome outcome) {
    if (outcome == Outcome::Cancelled)
        ++m_counters.cancelled;
    else
        ++m_counters.dropped_stale;
    m_counters.wasted_work += job.m_run_time;
}

CompletionStats JobSystem::process_completions(const CompletionBudget& budget) {
    VX_ASSERT_MSG(std::this_thread::get_id() == m_main_thread, "process_completions off the main thread");
    CompletionStats stats;
    const std::chrono::nanoseconds start = now();
    while (stats.applied < budget.max_count && (stats.applied < budget.min_count || now() - start < budget.time)) {
        Outcome outcome = Outcome::Ok;
        std::unique_ptr<Job> job = pop_completion(outcome);
        if (!job)
            break;
        if (outcome == Outcome::Ok) {
            job->complete(); // May submit: the lock is not held.
            ++stats.applied;
        } else {
            ++stats.discarded;
        }
        job.reset();
    }
    stats.time_used = now() - start;
    std::lock_guard lock(m_mutex);
    m_counters.completed += stats.applied;
    stats.remaining = m_completions.size();
    m_counters.last_completion_time = stats.time_used;
    m_counters.max_completion_time = std::max(m_counters.max_completion_time, stats.time_used);
    m_counters.total_completion_time += stats.time_used;
    return stats;
}

// Takes the oldest finished job and decides, under the lock, whether it is still wanted: a newer
// submit or a cancel may have come since it finished running.
std::unique_ptr<Job> JobSystem::pop_completion(Outcome& outcome) {
    std::lock_guard lock(m_mutex);
    if (m_completions.empty())
        return nullptr;
    std::unique_ptr<Job> job = std::move(m_completions.front().job);
    KeyState& state = *m_completions.front().state;
    m_completions.pop_front();
    --state.awaiting;
    outcome = classify_nolock(*job, state);
    if (outcome != Outcome::Ok)
        count_dropped_nolock(*job, outcome);
    erase_if_idle_nolock(job->key(), state);
    return job;
}

} // namespace vx::engine
