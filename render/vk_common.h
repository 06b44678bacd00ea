#pragma once
// Vulkan access for render/ only: volk (function pointers loaded at run time, so binaries start
// without a Vulkan loader) and VK_CHECK, which is always on (niagara VK_CHECK_FORCE).

#include <volk.h>

namespace vx::render {

// The enum name of a VkResult ("VK_ERROR_DEVICE_LOST"), or "VkResult(<n>)". Thread-safe.
const char* vk_result_name(VkResult result);

// Logs the failed call with file, line and result name, then aborts. Thread-safe.
[[noreturn]] void vk_check_fail(const char* call, VkResult result, const char* file, int line);

} // namespace vx::render

// Never compiled out: a failed Vulkan call that we did not expect to fail is a bug.
#define VK_CHECK(call)                                                                                       \
    do {                                                                                                     \
        const VkResult vx_vk_result_ = (call);                                                               \
        if (vx_vk_result_ != VK_SUCCESS) [[unlikely]]                                                        \
            ::vx::render::vk_check_fail(#call, vx_vk_result_, __FILE__, __LINE__);                           \
    } while (0)

// For creation and memory-binding calls the device may refuse for want of memory: evaluates to
// true on VK_ERROR_OUT_OF_HOST_MEMORY or VK_ERROR_OUT_OF_DEVICE_MEMORY (a runtime failure the
// caller reports: lavapipe refuses any buffer past 4 GiB so), false on success; any other
// failure aborts (a bug).
#define VK_OUT_OF_MEMORY(call)                                                                               \
    ([&]() {                                                                                                 \
        const VkResult vx_vk_result_ = (call);                                                               \
        if (vx_vk_result_ == VK_ERROR_OUT_OF_HOST_MEMORY || vx_vk_result_ == VK_ERROR_OUT_OF_DEVICE_MEMORY)   \
            return true;                                                                                     \
        if (vx_vk_result_ != VK_SUCCESS) [[unlikely]]                                                        \
            ::vx::render::vk_check_fail(#call, vx_vk_result_, __FILE__, __LINE__);                           \
        return false;                                                                                        \
    }())

// For vkAcquireNextImageKHR / vkQueuePresentKHR: VK_SUBOPTIMAL_KHR and VK_ERROR_OUT_OF_DATE_KHR
// are allowed (the swapchain is recreated); any other failure aborts. Evaluates to the result.
#define VK_CHECK_SWAPCHAIN(call)                                                                             \
    ([&]() {                                                                                                 \
        const VkResult vx_vk_result_ = (call);                                                               \
        if (vx_vk_result_ != VK_SUCCESS && vx_vk_result_ != VK_SUBOPTIMAL_KHR &&                              \
            vx_vk_result_ != VK_ERROR_OUT_OF_DATE_KHR) [[unlikely]]                                          \
            ::vx::render::vk_check_fail(#call, vx_vk_result_, __FILE__, __LINE__);                           \
        return vx_vk_result_;                                                                                \
    }())
