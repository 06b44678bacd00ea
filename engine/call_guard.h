#pragma once
// Calls into vx::Engine from two threads at once are refused (vx.h, Threads: one thread at a
// time). Two unsynchronised calls raced on the streamer's maps and the heap: SIGSEGV or "corrupted
// size vs. prev_size" within seconds. The guard claims the engine for the calling thread for the
// length of one call; a call from another thread meanwhile gets an error and touches nothing. A
// nested call on the same thread (a log handler asking for stats() inside update()) passes.
// Cost: one uncontended compare-exchange and one store per call.

#include <atomic>
#include <string>
#include <thread>

#include "world/base/result.h"

namespace vx::engine {

// The engine's claim: the thread inside a call now (none: default id), and whether a refusal was
// logged yet (once per engine: a game that breaks the rule in a loop must not flood its log).
struct CallOwner {
    std::atomic<std::thread::id> busy{};
    std::atomic<bool> refusal_logged{false};
};

// Any thread. Claims `owner` for this call, or refuses (operator bool false, error()).
class CallGuard {
public:
    CallGuard(CallOwner& owner, const char* call);
    ~CallGuard();
    CallGuard(const CallGuard&) = delete;
    CallGuard& operator=(const CallGuard&) = delete;

    explicit operator bool() const { return m_ok; }
    Status error() const;

private:
    CallOwner& m_owner;
    const char* m_call;
    bool m_ok = true;
    bool m_claimed = false; // Released on destruction (false for a nested call or a refusal).
};

} // namespace vx::engine
