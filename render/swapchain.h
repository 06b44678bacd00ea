#pragma once
// The window's swapchain: an sRGB output format when the surface offers one, FIFO with vsync and
// MAILBOX (else IMMEDIATE, else FIFO) without, and recreation when the window's framebuffer size
// changes or the surface reports VK_ERROR_OUT_OF_DATE_KHR / VK_SUBOPTIMAL_KHR. A minimised window
// (0x0 framebuffer) gets no swapchain: the caller skips the frame. Each image has its own
// "rendering done" semaphore, since a present has no fence telling when its wait has finished.
// Main thread only.

#include <cstdint>
#include <span>
#include <vector>

#include "render/context.h"

namespace vx::render {

// The pure choices, apart so tests can exercise them without a window.
VkSurfaceFormatKHR choose_surface_format(std::span<const VkSurfaceFormatKHR> formats);
VkPresentModeKHR choose_present_mode(std::span<const VkPresentModeKHR> modes, bool vsync);
// The surface's current extent when it dictates one, else the framebuffer size clamped to the
// surface's limits. 0x0 when either is empty (minimised).
VkExtent2D choose_extent(const VkSurfaceCapabilitiesKHR& caps, VkExtent2D framebuffer);
bool is_srgb_format(VkFormat format);

class Swapchain {
public:
    // `ctx` must have been created with a window. Chooses the format and present mode; the
    // swapchain itself is made by the first recreate().
    Swapchain(Context& ctx, bool vsync);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    // The surface's formats and present modes were read; false (out of memory, a lost surface:
    // logged, Context::last_create_failure): the swapchain cannot be made.
    bool valid() const { return m_valid; }
    Swapchain& operator=(const Swapchain&) = delete;

    // True when a frame for a window framebuffer of `framebuffer` pixels needs recreate() first.
    bool stale(VkExtent2D framebuffer) const;
    // (Re)creates the swapchain for `framebuffer` pixels. Waits for the device to go idle (rare:
    // resizes). False when the extent is 0x0 (minimised): nothing is created.
    bool recreate(VkExtent2D framebuffer);

    // Acquires the next image, signalling `acquired`. VK_SUCCESS or VK_SUBOPTIMAL_KHR: `*index`
    // is valid (suboptimal marks the swapchain stale); VK_ERROR_OUT_OF_DATE_KHR: nothing was
    // acquired and the swapchain is stale; VK_ERROR_DEVICE_LOST: nothing was acquired and the
    // context is lost.
    VkResult acquire(VkSemaphore acquired, uint32_t* index);
    // Queues image `index` for presentation once render_done(index) is signalled. Out of date or
    // suboptimal marks the swapchain stale. False: the device was lost (the context is marked).
    bool present(uint32_t index);
    // The present mode for later swapchains (choose_present_mode over the surface's modes); a
    // change marks the swapchain stale, so the next frame recreates it.
    void set_vsync(bool vsync);

    VkFormat format() const { return m_format.format; }
    VkPresentModeKHR present_mode() const { return m_mode; }
    VkExtent2D extent() const { return m_extent; }
    VkImage image(uint32_t index) const { return m_images[index]; }
    VkSemaphore render_done(uint32_t index) const { return m_render_done[index]; }
    uint32_t image_count() const { return uint32_t(m_images.size()); }
    // Images may be copied from (TRANSFER_SRC usage), for captures.
    bool can_capture() const { return m_capture; }
    uint64_t recreations() const { return m_recreations; }

private:
    void destroy_semaphores();

    Context* m_ctx;
    bool query_surface(bool vsync);
    bool m_valid = false;
    VkSurfaceFormatKHR m_format{};
    VkPresentModeKHR m_mode = VK_PRESENT_MODE_FIFO_KHR;
    std::vector<VkPresentModeKHR> m_modes; // The surface's.
    VkSwapchainKHR m_swapchain = VK_NULL_HANDLE;
    VkExtent2D m_extent{0, 0};
    VkExtent2D m_framebuffer{0, 0}; // The window size it was made for.
    std::vector<VkImage> m_images;
    std::vector<VkSemaphore> m_render_done;
    bool m_out_of_date = false;
    bool m_capture = false;
    uint64_t m_recreations = 0;
};

} // namespace vx::render
