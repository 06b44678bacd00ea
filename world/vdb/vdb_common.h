#pragma once
// Internal helpers of vx_vdb shared by its translation units. No OpenVDB types here.

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "world/base/result.h"

namespace vx::vdb::detail {

// `context: what` folded onto one line (OpenVDB messages may hold newlines and colour escapes).
// Thread-safe.
Error make_error(std::string_view context, std::string_view what);

// A temporary file name beside `path`, unique per process and call. Thread-safe.
std::string temp_path_beside(const std::string& path);

// Renames `from` over `to` (atomic on one file system); removes `from` on failure. Thread-safe.
Status replace_file(const std::string& from, const std::string& to);

// Runs `f` in the calling thread with OpenVDB's TBB parallelism confined to a one-slot arena, so
// an import starts no worker threads: it cannot fail to create one (under a memory limit, where a
// failure inside a destructor would terminate the process) and does not compete with the engine's
// workers. Exceptions from `f` propagate. Thread-safe.
void run_in_calling_thread(const std::function<void()>& f);

// Calls `f` (which must catch its own exceptions) through run_in_calling_thread and returns its
// result; an exception from TBB itself becomes an error. Thread-safe.
template <class R, class F> R serial(F&& f) {
    std::optional<R> out;
    try {
        run_in_calling_thread([&] { out.emplace(f()); });
    } catch (...) {
    }
    if (!out)
        return R(Error{"cannot run the OpenVDB reader (TBB arena failed)"});
    return std::move(*out);
}

} // namespace vx::vdb::detail
