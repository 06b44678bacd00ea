#include "render/swapchain.h"

#include <algorithm>
#include <string>

#include "world/base/log.h"

namespace vx::render {

bool is_srgb_format(VkFormat format) {
    return format == VK_FORMAT_B8G8R8A8_SRGB || format == VK_FORMAT_R8G8B8A8_SRGB ||
           format == VK_FORMAT_A8B8G8R8_SRGB_PACK32;
}

VkSurfaceFormatKHR choose_surface_format(std::span<const VkSurfaceFormatKHR> formats) {
    VX_ASSERT(!formats.empty());
    // sRGB first: the display expects sRGB-encoded values and an _SRGB image encodes on write.
    for (VkFormat want : {VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_UNORM,
                          VK_FORMAT_R8G8B8A8_UNORM})
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
                return f;
    return formats[0];
}

VkPresentModeKHR choose_present_mode(std::span<const VkPresentModeKHR> modes, bool vsync) {
    if (vsync)
        return VK_PRESENT_MODE_FIFO_KHR; // The only mode every surface supports.
    for (VkPresentModeKHR want : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
        if (std::find(modes.begin(), modes.end(), want) != modes.end())
            return want;
    return VK_PRESENT_MODE_FIFO_KHR;
}

VkExtent2D choose_extent(const VkSurfaceCapabilitiesKHR& caps, VkExtent2D framebuffer) {
    if (framebuffer.width == 0 || framebuffer.height == 0)
        return {0, 0};
    if (caps.currentExtent.width != UINT32_MAX) // The surface dictates its size (X11, Win32).
        return caps.currentExtent;
    return {std::clamp(framebuffer.width, caps.minImageExtent.width, caps.maxImageExtent.width),
            std::clamp(framebuffer.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
}

Swapchain::Swapchain(Context& ctx, bool vsync) : m_ctx(&ctx) {
    VX_ASSERT(ctx.surface() != VK_NULL_HANDLE);
    m_valid = query_surface(vsync);
}

// The surface's formats and present modes. Out of memory or a lost surface (a runtime state,
// it was a VK_CHECK abort): false, logged by create_call. VK_INCOMPLETE (the list grew between
// the calls) keeps the first n entries.
bool Swapchain::query_surface(bool vsync) {
    const VkPhysicalDevice pd = m_ctx->physical_device();
    const VkSurfaceKHR surface = m_ctx->surface();
    auto ok = [](VkResult r) { return r == VK_SUCCESS || r == VK_INCOMPLETE; };
    const char* formats_call = "vkGetPhysicalDeviceSurfaceFormatsKHR";
    uint32_t n = 0;
    if (!ok(m_ctx->create_call(formats_call,
                               [&] { return vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr); })))
        return false;
    std::vector<VkSurfaceFormatKHR> formats(n);
    if (!ok(m_ctx->create_call(formats_call, [&] {
            return vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data());
        })) || n == 0)
        return false;
    m_format = choose_surface_format(std::span(formats).first(n));
    const char* modes_call = "vkGetPhysicalDeviceSurfacePresentModesKHR";
    if (!ok(m_ctx->create_call(modes_call,
                               [&] { return vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr); })))
        return false;
    m_modes.resize(n);
    if (!ok(m_ctx->create_call(modes_call, [&] {
            return vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, m_modes.data());
        })))
        return false;
    m_modes.resize(n);
    m_mode = choose_present_mode(m_modes, vsync);
    return true;
}

void Swapchain::set_vsync(bool vsync) {
    const VkPresentModeKHR mode = choose_present_mode(m_modes, vsync);
    if (mode == m_mode)
        return;
    m_mode = mode;
    m_out_of_date = true;
}

Swapchain::~Swapchain() {
    if (!m_swapchain)
        return;
    m_ctx->wait_idle();
    destroy_semaphores();
    vkDestroySwapchainKHR(m_ctx->device(), m_swapchain, nullptr);
}

void Swapchain::destroy_semaphores() {
    for (VkSemaphore s : m_render_done)
        vkDestroySemaphore(m_ctx->device(), s, nullptr);
    m_render_done.clear();
}

bool Swapchain::stale(VkExtent2D framebuffer) const {
    return !m_swapchain || m_out_of_date || framebuffer.width != m_framebuffer.width ||
           framebuffer.height != m_framebuffer.height;
}

bool Swapchain::recreate(VkExtent2D framebuffer) {
    VkSurfaceCapabilitiesKHR caps;
    if (!m_ctx->check_device(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(m_ctx->physical_device(), m_ctx->surface(), &caps),
                             "vkGetPhysicalDeviceSurfaceCapabilitiesKHR"))
        return false; // A lost surface: the caller reports the lost context.
    const VkExtent2D extent = choose_extent(caps, framebuffer);
    if (extent.width == 0 || extent.height == 0)
        return false;
    // The frame is blitted in. Context::can_present() turns such a surface down at create; one
    // whose caps changed since is a surface this renderer cannot use (a lost context).
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return m_ctx->check_device(VK_ERROR_SURFACE_LOST_KHR, "surface without TRANSFER_DST usage");
    // Frames in flight may still blit into or present the old images: wait (resizes are rare).
    m_ctx->wait_idle();
    if (m_ctx->lost())
        return false; // The caller reports it; the renderer must be recreated.

    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = m_ctx->surface();
    ci.minImageCount = caps.minImageCount + 1; // One more than the minimum: acquire rarely blocks.
    if (caps.maxImageCount > 0)
        ci.minImageCount = std::min(ci.minImageCount, caps.maxImageCount);
    ci.imageFormat = m_format.format;
    ci.imageColorSpace = m_format.colorSpace;
    ci.imageExtent = extent;
    ci.imageArrayLayers = 1;
    m_capture = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    ci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | (m_capture ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE; // One queue renders and presents.
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & ci.compositeAlpha)) // Lowest supported bit otherwise.
        ci.compositeAlpha = VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    ci.presentMode = m_mode;
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = m_swapchain;
    VkSwapchainKHR fresh = VK_NULL_HANDLE;
    // Out of memory, a lost surface, a window another API holds: reported as a lost context.
    if (!m_ctx->check_device(vkCreateSwapchainKHR(m_ctx->device(), &ci, nullptr, &fresh), "vkCreateSwapchainKHR"))
        return false;
    if (m_swapchain)
        vkDestroySwapchainKHR(m_ctx->device(), m_swapchain, nullptr);
    m_swapchain = fresh;
    m_ctx->set_name(m_swapchain, VK_OBJECT_TYPE_SWAPCHAIN_KHR, "swapchain");

    // Out of host or device memory here is reported as a lost context, as for the swapchain
    // itself (it aborted): the game recreates the renderer, its world and edits kept.
    uint32_t n = 0;
    m_images.clear();
    destroy_semaphores();
    if (!m_ctx->check_device(vkGetSwapchainImagesKHR(m_ctx->device(), m_swapchain, &n, nullptr),
                             "vkGetSwapchainImagesKHR"))
        return false;
    m_images.resize(n);
    if (!m_ctx->check_device(vkGetSwapchainImagesKHR(m_ctx->device(), m_swapchain, &n, m_images.data()),
                             "vkGetSwapchainImagesKHR")) {
        m_images.clear();
        return false;
    }
    for (uint32_t i = 0; i < n; ++i) {
        VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore s = VK_NULL_HANDLE;
        // Through create_call: an injected failure makes no semaphore (check_device alone
        // replaced the result of one made: a leak at destroy).
        const char* call = "vkCreateSemaphore (swapchain)";
        auto create = [&] { return vkCreateSemaphore(m_ctx->device(), &si, nullptr, &s); };
        if (!m_ctx->check_device(m_ctx->create_call(call, create), call))
            return false;
        m_render_done.push_back(s);
        const std::string name = "swapchain image " + std::to_string(i);
        m_ctx->set_name(m_images[i], VK_OBJECT_TYPE_IMAGE, name.c_str());
        m_ctx->set_name(s, VK_OBJECT_TYPE_SEMAPHORE, (name + " done").c_str());
    }
    m_extent = extent;
    m_framebuffer = framebuffer;
    m_out_of_date = false;
    ++m_recreations;
    return true;
}

// Out of date and suboptimal are the swapchain's to handle; anything else (a lost device or
// surface, out of memory) marks the context lost.
static VkResult swapchain_result(Context& ctx, VkResult r, const char* what) {
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR && r != VK_ERROR_OUT_OF_DATE_KHR)
        ctx.check_device(r, what);
    return r;
}

VkResult Swapchain::acquire(VkSemaphore acquired, uint32_t* index) {
    VX_ASSERT(m_swapchain);
    const VkResult r = swapchain_result(
        *m_ctx, vkAcquireNextImageKHR(m_ctx->device(), m_swapchain, UINT64_MAX, acquired, VK_NULL_HANDLE, index),
        "vkAcquireNextImageKHR");
    if (r == VK_SUBOPTIMAL_KHR || r == VK_ERROR_OUT_OF_DATE_KHR)
        m_out_of_date = true;
    return r;
}

bool Swapchain::present(uint32_t index) {
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &m_render_done[index];
    pi.swapchainCount = 1;
    pi.pSwapchains = &m_swapchain;
    pi.pImageIndices = &index;
    const VkResult r = swapchain_result(*m_ctx, vkQueuePresentKHR(m_ctx->queue(), &pi), "vkQueuePresentKHR");
    if (r == VK_SUBOPTIMAL_KHR || r == VK_ERROR_OUT_OF_DATE_KHR)
        m_out_of_date = true;
    return r == VK_SUCCESS || r == VK_SUBOPTIMAL_KHR || r == VK_ERROR_OUT_OF_DATE_KHR; // Else: context lost.
}

} // namespace vx::render
