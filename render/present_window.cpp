#include "render/present_window.h"

// volk.h (through vk_common.h) defines VK_VERSION_1_0, so glfw3.h declares its Vulkan functions.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

namespace vx::render {

Result<std::vector<const char*>> window_instance_extensions() {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names || count == 0) {
        const char* why = nullptr;
        glfwGetError(&why);
        return Error{std::string("GLFW has no Vulkan surface support: ") + (why ? why : "glfwInit not called?")};
    }
    return std::vector<const char*>(names, names + count);
}

Result<VkSurfaceKHR> create_window_surface(VkInstance instance, void* window) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(instance, static_cast<GLFWwindow*>(window), nullptr, &surface);
    if (r != VK_SUCCESS)
        return Error{std::string("glfwCreateWindowSurface failed: ") + vk_result_name(r)};
    return surface;
}

VkExtent2D window_framebuffer_extent(void* window) {
    auto* w = static_cast<GLFWwindow*>(window);
    if (glfwGetWindowAttrib(w, GLFW_ICONIFIED))
        return {0, 0};
    int width = 0, height = 0;
    glfwGetFramebufferSize(w, &width, &height);
    return {uint32_t(width > 0 ? width : 0), uint32_t(height > 0 ? height : 0)};
}

} // namespace vx::render
