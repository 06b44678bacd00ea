#pragma once
// Internal helpers of vx_vdb shared by its translation units. No OpenVDB types here.

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "world/base/result.h"
#include "world/base/file_replace.h"
#include "world/vdb/vdb_volume.h"

namespace vx::vdb::detail {

// A length for messages: "%.6g". Thread-safe.
std::string format_length(double v);

// Voxel edge of a grid whose voxels are cubes (edges within 1e-6 relative), else 0. Thread-safe.
double uniform_voxel(const glm::dvec3& voxel_size);

// The checks of VolumeImportOptions that need no grid; one-line errors. Thread-safe.
Status check_volume_options(const VolumeImportOptions& o);

// `context: what` folded onto one line (OpenVDB messages may hold newlines and colour escapes,
// and, from a damaged file, garbage): control bytes and runs of spaces become one space, and
// `what` is cut at 240 characters ("..." marks the cut). Thread-safe.
Error make_error(std::string_view context, std::string_view what);

// "" when `path` is a regular file (through links), else "cannot read 'PATH': no such file" or
// "...: not a file" (a folder, a device). Thread-safe.
std::string unreadable_file(const std::string& path);

// Temporaries beside a path and their rename over it: world/base/file_replace.h.
using world::create_temp_beside;
using world::replace_file;

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
