#include "world/base/log.h"

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include <unistd.h>

namespace vx {
namespace {

// Handler calls are serialised by the lock, and set_log_handler takes it too, so a replaced
// handler is never running once the call that replaced it returns.
struct HandlerSlot {
    std::mutex mutex;
    std::shared_ptr<const LogHandler> handler; // Null: stderr. Guarded by mutex.
};
// Never destroyed: destructors of other static objects may still log at exit.
HandlerSlot& slot() {
    static HandlerSlot* s = new HandlerSlot();
    return *s;
}
std::mutex g_stderr_mutex; // One line at a time on stderr.
thread_local bool t_in_handler = false; // This thread is inside the handler (holds the lock).

const char* prefix(LogLevel level) { return level == LogLevel::Error ? "vx error: " : "vx warning: "; }

void write_stderr(LogLevel level, std::string_view line) {
    std::string out = prefix(level);
    out.append(line);
    out.push_back('\n');
    std::lock_guard lock(g_stderr_mutex);
    const char* p = out.data();
    size_t left = out.size();
    while (left > 0) {
        const ssize_t n = ::write(STDERR_FILENO, p, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return; // stderr is gone: nowhere left to say so.
        p += n;
        left -= size_t(n);
    }
}

void dispatch(LogLevel level, std::string_view line) {
    if (t_in_handler) { // The handler logged: it would wait for itself.
        write_stderr(level, line);
        return;
    }
    HandlerSlot& h = slot();
    std::unique_lock lock(h.mutex);
    if (!h.handler) {
        lock.unlock();
        write_stderr(level, line);
        return;
    }
    const std::shared_ptr<const LogHandler> handler = h.handler; // Survives a replacement inside the call.
    t_in_handler = true;
    bool threw = false;
    try {
        (*handler)(level, line);
    } catch (...) { // The game's code: its failure must not take the engine's thread down.
        threw = true;
    }
    t_in_handler = false;
    lock.unlock();
    if (threw)
        write_stderr(level, line);
}

} // namespace

void set_log_handler(LogHandler handler) {
    auto next = handler ? std::make_shared<const LogHandler>(std::move(handler)) : nullptr;
    HandlerSlot& h = slot();
    if (t_in_handler) { // Called from the handler: this thread already holds the lock.
        h.handler = std::move(next);
        return;
    }
    std::lock_guard lock(h.mutex);
    h.handler = std::move(next);
}

void log_line(LogLevel level, const char* format, ...) {
    char buf[4096];
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    if (n < 0)
        return;
    dispatch(level, std::string_view(buf, std::min(size_t(n), sizeof buf - 1)));
}

} // namespace vx
