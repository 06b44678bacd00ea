#pragma once
// Internal helpers of vx_vdb shared by its translation units. No OpenVDB types here.

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

} // namespace vx::vdb::detail
