#pragma once
// Test hooks that make Vulkan calls fail as a full or lost device would, by name, so tests can
// reach the error paths of calls a test machine never sees fail (Context::inject_result,
// Context::fail_allocations). Not thread-safe (main thread, as the calls it stands in for).

#include <string>
#include <string_view>

#include "render/vk_common.h"

namespace vx::render {

struct FaultInjection {
    std::string call;                // inject_result: the next call named `call` reads `result`.
    VkResult result = VK_SUCCESS;
    std::string prefix;              // fail_allocations: names starting with it fail (empty: none)
    VkDeviceSize above = 0;          // ... when larger than this many bytes (0: any size).

    // The result inject_result gave the call `what` (consumed), or VK_SUCCESS: none.
    VkResult take_call(std::string_view what) {
        if (call.empty() || call != what)
            return VK_SUCCESS;
        call.clear();
        return result;
    }
    // take_call, else out of host memory when `what` matches fail_allocations' prefix.
    VkResult take(std::string_view what, VkDeviceSize bytes = 0) {
        const VkResult r = take_call(what);
        if (r != VK_SUCCESS)
            return r;
        return allocation(what, bytes) ? VK_ERROR_OUT_OF_HOST_MEMORY : VK_SUCCESS;
    }
    bool allocation(std::string_view name, VkDeviceSize bytes) const {
        return !prefix.empty() && name.starts_with(prefix) && (above == 0 || bytes > above);
    }
};

} // namespace vx::render
