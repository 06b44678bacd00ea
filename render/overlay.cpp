#include "render/overlay.h"

#include <cstring>

#include "render/commands.h"

namespace vx::render {

bool OverlayPass::upload(VkCommandBuffer cmd) {
    const OverlayData& d = m_data;
    const VkDeviceSize bytes = VkDeviceSize(d.width) * d.height * 4;
    if (d.rgba.size() != bytes)
        return false;
    VkImageLayout from = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (!m_atlas.valid() || m_atlas.width() != d.width || m_atlas.height() != d.height) {
        // The old atlas goes to the retire list: frames in flight may still read it.
        m_atlas = Image::create(*m_ctx, {d.width, d.height, m_format,
                                         VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                             VK_IMAGE_USAGE_SAMPLED_BIT,
                                         "overlay atlas", VK_FORMAT_UNDEFINED});
        if (!m_atlas.valid())
            return false;
        from = VK_IMAGE_LAYOUT_UNDEFINED;
    }
    Buffer& staging = m_staging[m_ctx->frame_slot()];
    if (!staging.valid() || staging.size() < bytes)
        staging = Buffer::create(*m_ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, 0,
                                          "overlay staging"});
    if (!staging.valid())
        return false;
    std::memcpy(staging.mapped(), d.rgba.data(), bytes);
    // After the previous frames' blits read the atlas (same queue, earlier in submission order).
    image_barrier(cmd, m_atlas.handle(), from, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {d.width, d.height, 1};
    vkCmdCopyBufferToImage(cmd, staging.handle(), m_atlas.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    image_barrier(cmd, m_atlas.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    m_uploaded_version = d.version;
    return true;
}

void OverlayPass::record(VkCommandBuffer cmd, VkImage dst, VkExtent2D extent) {
    const OverlayData& d = m_data;
    if (d.width == 0 || d.height == 0 || d.rects.empty())
        return;
    if ((!m_atlas.valid() || d.version != m_uploaded_version) && !upload(cmd))
        return;
    std::vector<VkImageBlit> regions;
    regions.reserve(d.rects.size());
    auto inside = [](int32_t x, int32_t y, int32_t w, int32_t h, uint32_t W, uint32_t H) {
        return x >= 0 && y >= 0 && w > 0 && h > 0 && int64_t(x) + w <= int64_t(W) && int64_t(y) + h <= int64_t(H);
    };
    for (const OverlayRect& r : d.rects) {
        if (!inside(r.src_x, r.src_y, r.src_w, r.src_h, d.width, d.height) ||
            !inside(r.dst_x, r.dst_y, r.dst_w, r.dst_h, extent.width, extent.height))
            continue;
        VkImageBlit b{};
        b.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        b.srcOffsets[0] = {r.src_x, r.src_y, 0};
        b.srcOffsets[1] = {r.src_x + r.src_w, r.src_y + r.src_h, 1};
        b.dstSubresource = b.srcSubresource;
        b.dstOffsets[0] = {r.dst_x, r.dst_y, 0};
        b.dstOffsets[1] = {r.dst_x + r.dst_w, r.dst_y + r.dst_h, 1};
        regions.push_back(b);
    }
    if (regions.empty())
        return;
    // The frame's blit into `dst` comes first: write after write on the same image.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdBlitImage(cmd, m_atlas.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, uint32_t(regions.size()), regions.data(), VK_FILTER_NEAREST);
}

} // namespace vx::render
