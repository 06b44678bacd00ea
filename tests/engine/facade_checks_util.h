#pragma once
// Helpers shared by the facade's checks (facade_checks_test.cpp, facade_stored_world_test.cpp,
// facade_png_test.cpp): their world paths, a small engine's create info, and a call's error.

#include <string>
#include <utility>

#include <vx/vx.h>

#include "facade_test_util.h"

namespace vx::test {

inline std::string checks_world(const char* name) { return vx::test::temp_world_path("vx_facade_checks_test", name); }

inline vx::EngineCreateInfo tiny_info(vx::WorldSource source) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 1;
    return info;
}

// The error of `r`, or "" when it succeeded.
template <typename T>
std::string error_of(const T& r) {
    return r ? std::string() : r.error();
}

} // namespace vx::test
