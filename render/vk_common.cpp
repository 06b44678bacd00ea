#include "render/vk_common.h"

#include <cstdio>
#include <cstdlib>

namespace vx::render {

const char* vk_result_name(VkResult result) {
    switch (result) {
#define VX_CASE(name)                                                                                        \
    case name:                                                                                               \
        return #name;
        VX_CASE(VK_SUCCESS)
        VX_CASE(VK_NOT_READY)
        VX_CASE(VK_TIMEOUT)
        VX_CASE(VK_EVENT_SET)
        VX_CASE(VK_EVENT_RESET)
        VX_CASE(VK_INCOMPLETE)
        VX_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        VX_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        VX_CASE(VK_ERROR_INITIALIZATION_FAILED)
        VX_CASE(VK_ERROR_DEVICE_LOST)
        VX_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        VX_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        VX_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        VX_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        VX_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        VX_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        VX_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        VX_CASE(VK_ERROR_FRAGMENTED_POOL)
        VX_CASE(VK_ERROR_UNKNOWN)
        VX_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        VX_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        VX_CASE(VK_ERROR_FRAGMENTATION)
        VX_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        VX_CASE(VK_PIPELINE_COMPILE_REQUIRED)
        VX_CASE(VK_THREAD_IDLE_KHR)
        VX_CASE(VK_THREAD_DONE_KHR)
        VX_CASE(VK_OPERATION_DEFERRED_KHR)
        VX_CASE(VK_OPERATION_NOT_DEFERRED_KHR)
        VX_CASE(VK_SUBOPTIMAL_KHR)
        VX_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        VX_CASE(VK_ERROR_SURFACE_LOST_KHR)
        VX_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
#undef VX_CASE
    default:
        break;
    }
    static thread_local char buf[32];
    std::snprintf(buf, sizeof buf, "VkResult(%d)", int(result));
    return buf;
}

void vk_check_fail(const char* call, VkResult result, const char* file, int line) {
    std::fprintf(stderr, "vx: Vulkan call failed: %s -> %s (%s:%d)\n", call, vk_result_name(result), file, line);
    std::fflush(stderr);
    std::abort();
}

} // namespace vx::render
