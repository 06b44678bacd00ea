#pragma once
// CPU time of the calling thread: the work a main-thread call did, without the time the OS gave
// other threads (update() budgets and Stats::update_cpu_ms). Thread-safe.

#include <chrono>
#include <ctime>

namespace vx::engine {

inline std::chrono::nanoseconds thread_cpu_time() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

} // namespace vx::engine
