// The log (world/base/log.h, <vx/log.h>): whole lines from many threads, on stderr and through a
// game's handler; a handler that throws, logs or replaces itself takes nothing down.
#include <atomic>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "world/base/log.h"

namespace {

constexpr int kThreads = 8, kLines = 400;
// Long enough that a line split into pieces would show: 300 characters.
const std::string kPayload(300, 'x');

void log_from_threads() {
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([t] {
            for (int i = 0; i < kLines; ++i)
                VX_LOG_WARN("thread %d line %d %s", t, i, kPayload.c_str());
        });
    for (std::thread& t : threads)
        t.join();
}

// Every line is "thread T line I <payload>", whole, and each (T, I) comes exactly once.
void expect_whole_lines(const std::vector<std::string>& lines, const std::string& prefix) {
    std::set<std::pair<int, int>> seen;
    for (const std::string& line : lines) {
        int t = -1, i = -1;
        char rest[400] = {};
        const std::string body = line.substr(0, prefix.size()) == prefix ? line.substr(prefix.size()) : "";
        ASSERT_EQ(std::sscanf(body.c_str(), "thread %d line %d %399s", &t, &i, rest), 3) << line;
        EXPECT_EQ(std::string(rest), kPayload) << line;
        EXPECT_TRUE(seen.insert({t, i}).second) << line;
    }
    EXPECT_EQ(seen.size(), size_t(kThreads * kLines));
}

TEST(Log, StderrLinesFromThreadsNeverInterleave) {
    testing::internal::CaptureStderr();
    log_from_threads();
    const std::string out = testing::internal::GetCapturedStderr();
    std::vector<std::string> lines;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    expect_whole_lines(lines, "vx warning: ");
}

TEST(Log, HandlerGetsEveryLineOneCallAtATime) {
    std::vector<std::string> lines; // No lock: the calls are serialised.
    std::atomic<int> inside{0}, overlaps{0};
    std::vector<vx::LogLevel> levels;
    vx::set_log_handler([&](vx::LogLevel level, std::string_view line) {
        if (inside.fetch_add(1) != 0)
            ++overlaps;
        lines.emplace_back(line);
        levels.push_back(level);
        inside.fetch_sub(1);
    });
    log_from_threads();
    VX_LOG_ERROR("an error %d", 7);
    vx::set_log_handler(nullptr);
    EXPECT_EQ(overlaps.load(), 0);
    ASSERT_EQ(lines.size(), size_t(kThreads * kLines + 1));
    EXPECT_EQ(lines.back(), "an error 7");
    EXPECT_EQ(levels.back(), vx::LogLevel::Error);
    EXPECT_EQ(levels.front(), vx::LogLevel::Warning);
    lines.pop_back();
    expect_whole_lines(lines, "");

    // Back on stderr once reset.
    testing::internal::CaptureStderr();
    VX_LOG_ERROR("after reset");
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "vx error: after reset\n");
}

TEST(Log, ThrowingHandlerLineGoesToStderr) {
    std::atomic<int> calls{0};
    vx::set_log_handler([&](vx::LogLevel, std::string_view) {
        ++calls;
        throw std::runtime_error("the game's handler failed");
    });
    testing::internal::CaptureStderr();
    std::thread worker([] { VX_LOG_ERROR("from a worker"); });
    worker.join();
    vx::set_log_handler([&](vx::LogLevel, std::string_view) {
        ++calls;
        throw 5; // Not a std::exception.
    });
    VX_LOG_WARN("from main");
    const std::string err = testing::internal::GetCapturedStderr();
    vx::set_log_handler(nullptr);
    EXPECT_EQ(calls.load(), 2);
    EXPECT_EQ(err, "vx error: from a worker\nvx warning: from main\n");
}

TEST(Log, HandlerMayLogAndReplaceItself) {
    std::vector<std::string> got;
    testing::internal::CaptureStderr();
    vx::set_log_handler([&](vx::LogLevel, std::string_view line) {
        got.emplace_back(line);
        VX_LOG_WARN("logged inside: %s", std::string(line).c_str()); // To stderr, no deadlock.
        vx::set_log_handler([&](vx::LogLevel, std::string_view l) { got.push_back("second: " + std::string(l)); });
    });
    VX_LOG_ERROR("one");
    VX_LOG_ERROR("two");
    const std::string err = testing::internal::GetCapturedStderr();
    vx::set_log_handler(nullptr);
    EXPECT_EQ(got, (std::vector<std::string>{"one", "second: two"}));
    EXPECT_EQ(err, "vx warning: logged inside: one\n");
}

TEST(Log, LongLinesAreCut) {
    std::string got;
    vx::set_log_handler([&](vx::LogLevel, std::string_view line) { got = line; });
    const std::string huge(10000, 'y');
    VX_LOG_ERROR("%s", huge.c_str());
    vx::set_log_handler(nullptr);
    EXPECT_EQ(got, std::string(4095, 'y'));
}

} // namespace
