#pragma once
// Shared by the renderer's and the engine's tests: the Vulkan device they ask for, lavapipe
// ("cpu") unless $VX_TEST_DEVICE names another choice (auto, gpu, an index), so the same test
// programs run on a GPU machine (docs/render_report/scripts/device_env.sh).
#include <cstdlib>

namespace vx::test {

inline const char* test_device() {
    const char* env = std::getenv("VX_TEST_DEVICE");
    return env ? env : "cpu";
}

} // namespace vx::test
