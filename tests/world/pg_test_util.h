#pragma once
// Helpers shared by the PostgreSQL tests (pg_store_test.cpp, pg_listener_test.cpp): the cluster or a
// skip saying why, bounded waits, and a capture of the log's lines.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <vx/log.h>

#include "pg_cluster.h"

namespace vx::world::test {

// The test program's cluster; null, with a line saying why, when PostgreSQL cannot run here.
inline PgCluster* cluster_or_skip() {
    std::string why;
    PgCluster* c = PgCluster::get(&why);
    if (!c)
        std::printf("PostgreSQL tests skipped: %s\n", why.c_str());
    return c;
}

// Waits (bounded) until `done()`; whether it came.
template <class Done> bool wait_until(Done done, double timeout_s) {
    using Clock = std::chrono::steady_clock;
    const auto limit = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (!done() && Clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return done();
}

// Collects the log's lines while alive (vx::set_log_handler); thread-safe.
class LogCapture {
public:
    LogCapture() {
        vx::set_log_handler([this](vx::LogLevel, std::string_view line) {
            std::lock_guard lock(m_mutex);
            m_lines.emplace_back(line);
        });
    }
    ~LogCapture() { vx::set_log_handler(nullptr); }
    // The lines logged so far that hold `text`.
    size_t count(const std::string& text) {
        std::lock_guard lock(m_mutex);
        return size_t(std::count_if(m_lines.begin(), m_lines.end(),
                                    [&](const std::string& l) { return l.find(text) != std::string::npos; }));
    }

private:
    std::mutex m_mutex;
    std::vector<std::string> m_lines;
};

} // namespace vx::world::test

// Skips the test, saying why (the line printed before), when PostgreSQL cannot run here; else
// `cluster` names the test program's cluster. Test thread.
#define VX_NEED_PG()                                                                                                  \
    ::vx::world::test::PgCluster* cluster = ::vx::world::test::cluster_or_skip();                                     \
    if (!cluster)                                                                                                     \
    GTEST_SKIP() << "no PostgreSQL cluster (see the line above)"
