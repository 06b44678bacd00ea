#pragma once
// The engine's log (the hook and its levels: <vx/log.h>). Thread-safe: each call formats one
// line and hands it whole to the game's handler, or writes it to stderr in one write under a
// lock, so lines from different threads never interleave.

#include <vx/log.h>

namespace vx {

// Thread-safe. Formats `format` (printf) into one line (cut at 4 KiB) and logs it at `level`.
void log_line(LogLevel level, const char* format, ...) __attribute__((format(printf, 2, 3)));

} // namespace vx

#define VX_LOG_ERROR(...) ::vx::log_line(::vx::LogLevel::Error, __VA_ARGS__)
#define VX_LOG_WARN(...) ::vx::log_line(::vx::LogLevel::Warning, __VA_ARGS__)
