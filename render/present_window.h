#pragma once
// GLFW glue for presentation: the only render/ file that includes GLFW. `window` is a
// GLFWwindow* passed as void*, so no public header needs GLFW. The caller owns GLFW: it calls
// glfwInit, creates the window with GLFW_CLIENT_API = GLFW_NO_API and polls events.
// Main thread only (GLFW's rule).

#include <vector>

#include "render/vk_common.h"
#include "world/base/result.h"

namespace vx::render {

// Instance extensions GLFW needs for a surface (VK_KHR_surface plus the platform's), or an error
// when GLFW is not initialised or finds no Vulkan support.
Result<std::vector<const char*>> window_instance_extensions();

// A surface for `window` (destroyed by the caller with vkDestroySurfaceKHR).
Result<VkSurfaceKHR> create_window_surface(VkInstance instance, void* window);

// The window's framebuffer size in pixels; 0x0 while it is iconified (minimised).
VkExtent2D window_framebuffer_extent(void* window);

} // namespace vx::render
