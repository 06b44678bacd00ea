#pragma once
// Assertions that stay on in release builds (cheap invariants), and debug-only ones for hot loops.

#include <cstdio>
#include <cstdlib>

#include "world/base/log.h"

namespace vx {

// Prints the failed condition with its location and aborts. Thread-safe.
[[noreturn]] inline void assert_fail(const char* cond, const char* file, int line, const char* msg) {
    std::fprintf(stderr, "vx: assertion failed: %s (%s:%d)%s%s\n", cond, file, line, msg ? ": " : "",
                 msg ? msg : "");
    std::fflush(stderr);
    std::abort();
}

} // namespace vx

#define VX_ASSERT(cond)                                                                                      \
    do {                                                                                                     \
        if (!(cond)) [[unlikely]]                                                                            \
            ::vx::assert_fail(#cond, __FILE__, __LINE__, nullptr);                                           \
    } while (0)

#define VX_ASSERT_MSG(cond, msg)                                                                             \
    do {                                                                                                     \
        if (!(cond)) [[unlikely]]                                                                            \
            ::vx::assert_fail(#cond, __FILE__, __LINE__, msg);                                               \
    } while (0)

// For API edges: logs and returns `ret` instead of aborting (godot_voxel ZN_ASSERT_RETURN_V).
#define VX_ASSERT_RETURN(cond, ret)                                                                          \
    do {                                                                                                     \
        if (!(cond)) [[unlikely]] {                                                                          \
            ::vx::log_line(::vx::LogLevel::Error, "check failed: %s (%s:%d)", #cond, __FILE__, __LINE__);     \
            return ret;                                                                                      \
        }                                                                                                    \
    } while (0)

#ifdef NDEBUG
#define VX_DEBUG_ASSERT(cond) ((void)0)
#else
#define VX_DEBUG_ASSERT(cond) VX_ASSERT(cond)
#endif
