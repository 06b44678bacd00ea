#pragma once
// vx's log: one line per message (no trailing newline), with a level. By default lines go to
// stderr as "vx error: ...", written whole (lines from different threads never interleave). A
// game may take them instead with set_log_handler. Public and self-contained (std only): the
// engine's own code logs through the same hook (world/base/log.h forwards here).

#include <cstdint>
#include <functional>
#include <string_view>

namespace vx {

enum class LogLevel : uint8_t {
    Error,   // Something failed: a save, a chunk, a GPU allocation. The engine carries on.
    Warning, // Degraded but handled: a corrupt record regenerated, a store reconnecting.
};

// Receives one line at a time; the view is valid only during the call.
using LogHandler = std::function<void(LogLevel level, std::string_view line)>;

// Thread-safe. Sends every later line to `handler` (empty: back to stderr). The handler is called
// from any of the engine's threads (main, workers, I/O), one call at a time (calls are
// serialised, so it needs no lock of its own for its state); once set_log_handler returns, the
// previous handler is never called again. It must not block for long (it holds up the thread
// that logged). A line it logs itself, and a line it throws for (caught), go to stderr.
void set_log_handler(LogHandler handler);

} // namespace vx
