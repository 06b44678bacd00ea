#include "render/present.h"

#include <cstring>

#include "render/commands.h"
#include "render/present_window.h"

namespace vx::render {

Presenter::Presenter(Context& ctx, bool vsync) : m_ctx(&ctx), m_swapchain(ctx, vsync) {
    m_valid = m_swapchain.valid();
    for (uint32_t i = 0; i < kFramesInFlight && m_valid; ++i) {
        VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        m_valid = ctx.create_call("vkCreateSemaphore (image acquired)", [&] {
            return vkCreateSemaphore(ctx.device(), &si, nullptr, &m_acquired[i]);
        }) == VK_SUCCESS;
        ctx.set_name(m_acquired[i], VK_OBJECT_TYPE_SEMAPHORE, i ? "image acquired 1" : "image acquired 0");
    }
}

Presenter::~Presenter() {
    m_ctx->wait_idle();
    for (VkSemaphore s : m_acquired)
        vkDestroySemaphore(m_ctx->device(), s, nullptr);
}

VkFormat Presenter::target_format() const {
    return is_srgb_format(m_swapchain.format()) ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
}

std::optional<VkExtent2D> Presenter::prepare() {
    const VkExtent2D fb = window_framebuffer_extent(m_ctx->window());
    if (fb.width == 0 || fb.height == 0)
        return std::nullopt;
    if (m_swapchain.stale(fb) && !m_swapchain.recreate(fb))
        return std::nullopt;
    return m_swapchain.extent();
}

bool Presenter::acquire() {
    const VkResult r = m_swapchain.acquire(m_acquired[m_ctx->frame_slot()], &m_image);
    return r == VK_SUCCESS || r == VK_SUBOPTIMAL_KHR;
}

bool Presenter::prepare_capture() {
    const VkExtent2D e = m_swapchain.extent();
    if (!m_capture.valid() || m_capture.size() < VkDeviceSize(e.width) * e.height * 4)
        m_capture = Buffer::create(*m_ctx, {VkDeviceSize(e.width) * e.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                            MemoryUse::Readback, 0, "present capture"});
    return m_capture.valid();
}

void Presenter::record_blit(VkCommandBuffer cmd, VkImage target, bool capture) {
    const VkExtent2D e = m_swapchain.extent();
    const VkImage image = m_swapchain.image(m_image);
    // The submission waits on the acquire semaphore at the transfer stage; this barrier chains
    // after that wait (same stage), so the layout change happens once the image is ours.
    image_barrier(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkImageBlit region{};
    region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.srcOffsets[1] = {int32_t(e.width), int32_t(e.height), 1};
    region.dstSubresource = region.srcSubresource;
    region.dstOffsets[1] = region.srcOffsets[1];
    vkCmdBlitImage(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &region, VK_FILTER_NEAREST);
    VkImageLayout layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    if (capture) {
        VX_ASSERT_MSG(m_swapchain.can_capture(), "this surface's images cannot be read back");
        VX_ASSERT_MSG(m_capture.valid() && m_capture.size() >= VkDeviceSize(e.width) * e.height * 4,
                      "record_blit with capture needs prepare_capture() first");
        image_barrier(cmd, image, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {e.width, e.height, 1};
        vkCmdCopyImageToBuffer(cmd, image, layout, m_capture.handle(), 1, &copy);
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
        m_capture_extent = e;
    }
    // The "done" semaphore signal (all commands) makes the writes available to the present.
    image_barrier(cmd, image, layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                  capture ? VK_ACCESS_2_NONE : VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE,
                  VK_ACCESS_2_NONE);
}

FrameSubmitSync Presenter::submit_sync() const {
    return {m_acquired[m_ctx->frame_slot()], VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, m_swapchain.render_done(m_image)};
}

bool Presenter::present() { return m_swapchain.present(m_image); }

RenderImage Presenter::read_capture() const {
    RenderImage img;
    const VkFormat f = m_swapchain.format();
    const bool bgra = f == VK_FORMAT_B8G8R8A8_SRGB || f == VK_FORMAT_B8G8R8A8_UNORM;
    const bool rgba = f == VK_FORMAT_R8G8B8A8_SRGB || f == VK_FORMAT_R8G8B8A8_UNORM;
    if (!m_capture.valid() || (!bgra && !rgba))
        return img;
    img.width = m_capture_extent.width;
    img.height = m_capture_extent.height;
    img.rgba.resize(size_t(img.width) * img.height * 4);
    std::memcpy(img.rgba.data(), m_capture.mapped(), img.rgba.size());
    if (bgra)
        for (size_t i = 0; i < img.rgba.size(); i += 4)
            std::swap(img.rgba[i], img.rgba[i + 2]);
    return img;
}

} // namespace vx::render
