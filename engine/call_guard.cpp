#include "engine/call_guard.h"

#include "world/base/log.h"

namespace vx::engine {

CallGuard::CallGuard(CallOwner& owner, const char* call) : m_owner(owner), m_call(call) {
    const std::thread::id me = std::this_thread::get_id();
    std::thread::id seen{};
    // Acquire: this call sees everything the previous owner's calls wrote (the release below).
    if (owner.busy.compare_exchange_strong(seen, me, std::memory_order_acquire, std::memory_order_relaxed)) {
        m_claimed = true;
        return;
    }
    if (seen == me)
        return; // Nested on the thread already inside.
    m_ok = false;
    if (!owner.refusal_logged.exchange(true, std::memory_order_relaxed))
        VX_LOG_ERROR("%s", error().error().c_str());
}

CallGuard::~CallGuard() {
    if (m_claimed)
        m_owner.busy.store(std::thread::id{}, std::memory_order_release);
}

Status CallGuard::error() const {
    return Error{std::string("Engine::") + m_call +
                 " was called while another thread was inside the engine: refused (an Engine is used by one "
                 "thread at a time; order the threads' calls with a mutex or a join)"};
}

} // namespace vx::engine
