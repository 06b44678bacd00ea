#include "engine/save_tracker.h"

#include <algorithm>

namespace vx::engine {

uint64_t SaveTracker::next() {
    std::lock_guard lock(m_mutex);
    return ++m_issued;
}

void SaveTracker::finished(uint64_t sequence, const Status& status) {
    {
        std::lock_guard lock(m_mutex);
        if (status) {
            m_durable = std::max(m_durable, sequence);
            m_failures.erase(m_failures.begin(), m_failures.upper_bound(m_durable)); // Durable now.
        } else {
            if (sequence > m_durable)
                m_failures[sequence] = status.error();
            if (sequence >= m_failed) {
                m_failed = sequence;
                m_error = status.error();
            }
        }
    }
    m_changed.notify_all();
}

SaveState SaveTracker::state_nolock(uint64_t sequence) const {
    if (sequence == 0 || sequence > m_issued)
        return SaveState::Unknown;
    if (sequence <= m_durable)
        return SaveState::Durable;
    if (sequence <= m_failed)
        return SaveState::Failed;
    return SaveState::Pending;
}

SaveState SaveTracker::state(uint64_t sequence) const {
    std::lock_guard lock(m_mutex);
    return state_nolock(sequence);
}

std::string SaveTracker::last_error() const {
    std::lock_guard lock(m_mutex);
    return m_error;
}

Status SaveTracker::wait(uint64_t sequence) const {
    std::unique_lock lock(m_mutex);
    if (sequence == 0 || sequence > m_issued)
        return Error{"unknown save ticket " + std::to_string(sequence) + ": not one this engine's save() returned"};
    m_changed.wait(lock, [&] { return state_nolock(sequence) != SaveState::Pending; });
    if (state_nolock(sequence) == SaveState::Durable)
        return {};
    const auto first = m_failures.lower_bound(sequence); // Failed: one at or after it exists.
    return Error{first != m_failures.end() ? first->second : m_error};
}

uint64_t SaveTracker::durable() const {
    std::lock_guard lock(m_mutex);
    return m_durable;
}

} // namespace vx::engine
