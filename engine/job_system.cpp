#include "engine/job_system.h"

#include <algorithm>
#include <string>
#include <system_error>

#include "world/base/assert.h"

namespace vx::engine {
namespace {

using Clock = std::chrono::steady_clock;

int default_worker_count() {
    const unsigned hw = std::thread::hardware_concurrency();
    return hw > 1 ? int(hw) - 1 : 1;
}

std::chrono::nanoseconds steady_now() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch());
}

} // namespace

JobSystem::JobSystem(const JobSystemCreateInfo& info)
    : m_info(info), m_main_thread(std::this_thread::get_id()), m_paused(info.start_paused) {
    m_pool_queue.set_view_weight(std::max(0.0, info.view_weight));
    const int workers = std::min(info.worker_count > 0 ? info.worker_count : default_worker_count(), kMaxWorkerThreads);
    m_pool_threads.reserve(size_t(workers));
    // std::thread reports a refused thread (EAGAIN: a thread limit, or no memory for its stack)
    // by throwing std::system_error: caught here, at the boundary, and kept as a reason. The I/O
    // thread starts first, so a shortage costs pool workers before the one store lane.
    try {
        m_io_thread = std::thread([this] { worker_main(JobLane::Io, -1); });
    } catch (const std::system_error& e) {
        m_start_error = std::string("the OS refused the I/O thread: ") + e.what();
        return;
    }
    for (int i = 0; i < workers; ++i) {
        try {
            m_pool_threads.emplace_back([this, i] { worker_main(JobLane::Pool, i); });
        } catch (const std::system_error& e) {
            m_refused_workers = workers - i;
            m_refused_reason = e.what();
            break;
        }
    }
    if (m_pool_threads.empty())
        m_start_error = "the OS refused every worker thread (" + std::to_string(workers) + " asked for): " +
                        m_refused_reason;
}

JobSystem::~JobSystem() {
    VX_ASSERT_MSG(std::this_thread::get_id() == m_main_thread, "JobSystem destroyed off its main thread");
    std::vector<std::unique_ptr<Job>> unstarted;
    {
        std::lock_guard lock(m_mutex);
        m_stopping.store(true, std::memory_order_release);
        for (auto& [key, state] : m_keys) {
            if (state.queued) {
                unstarted.push_back(std::move(state.queued));
                ++m_counters.cancelled;
            }
            state.parked = false;
        }
        m_counters.queued = 0;
        m_pool_queue.clear();
        m_io_queue.clear();
    }
    m_pool_cv.notify_all();
    m_io_cv.notify_all();
    unstarted.clear();
    for (std::thread& t : m_pool_threads)
        t.join();
    if (m_io_thread.joinable()) // Not where the OS refused it.
        m_io_thread.join();
    // Every thread is gone: finished results are discarded without complete().
    m_counters.cancelled += m_completions.size();
    for (const Finished& f : m_completions)
        m_counters.wasted_work += f.job->m_run_time;
    m_completions.clear();
    m_keys.clear();
}

JobTicket JobSystem::submit(std::unique_ptr<Job> job) {
    VX_ASSERT(job != nullptr);
    const glm::dvec3 position = job->priority_position(); // User code: outside the lock.
    std::unique_ptr<Job> replaced;
    JobTicket ticket;
    Wake wake;
    {
        std::lock_guard lock(m_mutex);
        ticket = submit_nolock(std::move(job), position, replaced, wake);
        decide_wake_nolock(wake);
    }
    notify(wake);
    return ticket; // `replaced` is destroyed here, outside the lock.
}

std::vector<JobTicket> JobSystem::submit_batch(std::vector<std::unique_ptr<Job>> jobs) {
    std::vector<glm::dvec3> positions;
    positions.reserve(jobs.size());
    for (const std::unique_ptr<Job>& job : jobs) {
        VX_ASSERT(job != nullptr);
        positions.push_back(job->priority_position());
    }
    std::vector<JobTicket> tickets(jobs.size());
    std::vector<std::unique_ptr<Job>> replaced(jobs.size());
    Wake wake;
    {
        std::lock_guard lock(m_mutex);
        for (size_t i = 0; i < jobs.size(); ++i)
            tickets[i] = submit_nolock(std::move(jobs[i]), positions[i], replaced[i], wake);
        decide_wake_nolock(wake);
    }
    notify(wake);
    return tickets;
}

// The key rule (see the header). Jobs to destroy go to `replaced`; lanes to wake are added to `wake`.
JobTicket JobSystem::submit_nolock(std::unique_ptr<Job> job, const glm::dvec3& position,
                                   std::unique_ptr<Job>& replaced, Wake& wake) {
    const JobKey key = job->key();
    JobTicket ticket{key, 0, job->token()};
    ++m_counters.submitted;
    if (m_stopping.load(std::memory_order_relaxed)) {
        ++m_counters.cancelled;
        replaced = std::move(job);
        return ticket;
    }
    ticket.generation = job->m_generation = ++m_next_generation;
    KeyState& state = m_keys[key];
    state.latest = ticket.generation;
    if (state.running)
        state.running->m_abandoned.store(true, std::memory_order_release);
    if (state.queued) {
        replaced = std::move(state.queued);
        ++m_counters.cancelled;
        ++m_counters.replaced;
        if (lane_of(key.kind) == JobLane::Pool && !state.parked)
            m_pool_queue.note_dead([this](const QueueEntry& e) { return is_live_nolock(e.key, e.generation); });
    } else {
        ++m_counters.queued;
    }
    state.queued = std::move(job);
    state.queued_position = position;
    if (lane_of(key.kind) == JobLane::Io) {
        // A write inherits the replaced job's entry; a load goes to the back (see the header).
        // The entry left behind is dead: its sequence is no longer the key's.
        if (state.io_entry == 0 || key.kind == JobKind::Load) {
            state.io_entry = ++m_next_sequence;
            m_io_queue.push_back({key, state.io_entry});
            wake.io = true;
        }
    } else if (state.running) {
        state.parked = true;
    } else {
        enqueue_pool_nolock(key, state);
        ++wake.pool;
    }
    return ticket;
}

// Decides under the lock which lanes need a wake-up; notify() sends them after the unlock. Only
// sleeping threads are woken, and none while paused: a notify that finds a waiter costs a futex
// syscall and a context switch, and a paused worker would only go back to sleep. No wake-up is
// lost: a worker counts itself as waiting under the lock before it sleeps.
void JobSystem::decide_wake_nolock(Wake& wake) const {
    if (m_paused) {
        wake = {};
        return;
    }
    wake.pool = std::min(wake.pool, m_pool_waiting);
    wake.io = wake.io && m_io_waiting > 0;
}

void JobSystem::notify(const Wake& wake) {
    if (wake.pool > 1)
        m_pool_cv.notify_all();
    else if (wake.pool == 1)
        m_pool_cv.notify_one();
    if (wake.io)
        m_io_cv.notify_one();
}

void JobSystem::enqueue_pool_nolock(const JobKey& key, KeyState& state) {
    state.parked = false;
    m_pool_queue.push(key, state.queued->m_generation, ++m_next_sequence, state.queued_position);
}

bool JobSystem::cancel(const JobKey& key) {
    std::unique_ptr<Job> dropped;
    bool any = false;
    {
        std::lock_guard lock(m_mutex);
        auto it = m_keys.find(key);
        if (it == m_keys.end())
            return false;
        any = true; // Entries exist only while a job of the key is queued, running or finished.
        dropped = cancel_nolock(it->second);
        erase_if_idle_nolock(key, it->second);
        notify_if_idle_nolock();
    }
    return any;
}

void JobSystem::cancel_all() {
    std::vector<std::unique_ptr<Job>> dropped;
    {
        std::lock_guard lock(m_mutex);
        for (auto& [key, state] : m_keys)
            if (std::unique_ptr<Job> job = cancel_nolock(state))
                dropped.push_back(std::move(job));
        std::erase_if(m_keys, [](const auto& kv) { return kv.second.idle(); });
        notify_if_idle_nolock();
    }
}

std::unique_ptr<Job> JobSystem::cancel_nolock(KeyState& state) {
    state.cancelled_through = state.latest;
    if (state.running)
        state.running->m_abandoned.store(true, std::memory_order_release);
    std::unique_ptr<Job> dropped = std::move(state.queued);
    if (dropped) {
        ++m_counters.cancelled;
        --m_counters.queued;
        // The queue entry is dead now; a pop skips it (and a purge may drop it early).
        if (lane_of(dropped->key().kind) == JobLane::Pool && !state.parked)
            m_pool_queue.note_dead([this](const QueueEntry& e) { return is_live_nolock(e.key, e.generation); });
    }
    state.parked = false;
    state.io_entry = 0; // Its I/O entry, if any, is dead now.
    return dropped;
}

void JobSystem::set_viewer(const Viewer& viewer) {
    std::lock_guard lock(m_mutex);
    const double moved = glm::length(viewer.position - m_viewer.position);
    const double lf = glm::length(viewer.forward) * glm::length(m_viewer.forward);
    const double cos_turn = lf > 0.0 ? glm::dot(viewer.forward, m_viewer.forward) / lf : -1.0;
    if (moved < m_info.reprioritize_distance && cos_turn >= m_info.reprioritize_cos)
        return; // Small moves keep the current order: re-scoring costs O(queued).
    m_viewer = viewer;
    m_pool_queue.set_viewer(viewer, ++m_viewer_epoch);
}

void JobSystem::pause() {
    std::lock_guard lock(m_mutex);
    m_paused = true;
}

void JobSystem::resume() {
    {
        std::lock_guard lock(m_mutex);
        m_paused = false;
    }
    m_pool_cv.notify_all();
    m_io_cv.notify_all();
}

void JobSystem::wait_idle() {
    std::unique_lock lock(m_mutex);
    VX_ASSERT_MSG(!m_paused || m_counters.queued == 0, "wait_idle while paused would never return");
    m_idle_cv.wait(lock, [this] { return m_counters.queued == 0 && m_counters.in_flight == 0; });
}

JobMetrics JobSystem::metrics() const {
    std::lock_guard lock(m_mutex);
    JobMetrics m = m_counters;
    m.awaiting_completion = m_completions.size();
    m.heap_rebuilds = m_pool_queue.rebuild_count();
    return m;
}

void JobSystem::notify_if_idle_nolock() {
    if (m_counters.queued == 0 && m_counters.in_flight == 0)
        m_idle_cv.notify_all();
}

void JobSystem::erase_if_idle_nolock(const JobKey& key, const KeyState& state) {
    if (state.idle())
        m_keys.erase(key);
}

bool JobSystem::is_live_nolock(const JobKey& key, uint64_t generation) const {
    auto it = m_keys.find(key);
    return it != m_keys.end() && it->second.queued && it->second.queued->m_generation == generation;
}

std::chrono::nanoseconds JobSystem::now() const { return m_info.clock ? m_info.clock() : steady_now(); }

} // namespace vx::engine
