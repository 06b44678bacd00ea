#include "render/commands.h"

#include <cstring>

namespace vx::render {

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = 1;
    di.pMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &di);
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &di);
}

Buffer upload_buffer(Context& ctx, const void* data, size_t bytes, VkBufferUsageFlags usage, const char* name) {
    Buffer dst = Buffer::create(ctx, {bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Device, 0, name});
    Buffer staging =
        Buffer::create(ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, 0, "upload staging"});
    if (!dst.valid() || !staging.valid())
        return {};
    std::memcpy(staging.mapped(), data, bytes);
    ctx.submit_now([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
    });
    return dst;
}

void StagingBatch::add(const Buffer& dst, VkDeviceSize dst_offset, const void* data, size_t bytes) {
    if (bytes == 0)
        return;
    const VkDeviceSize src_offset = align_up(m_bytes.size(), 16);
    m_bytes.resize(src_offset + bytes);
    std::memcpy(m_bytes.data() + src_offset, data, bytes);
    m_copies.push_back({dst.handle(), dst_offset, src_offset, bytes});
}

bool StagingBatch::record(VkCommandBuffer cmd) {
    if (m_copies.empty())
        return false;
    Buffer staging = Buffer::create(
        *m_ctx, {m_bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, 0, "frame staging"});
    VX_ASSERT_MSG(staging.valid(), "out of memory for the frame's staging buffer");
    std::memcpy(staging.mapped(), m_bytes.data(), m_bytes.size());
    for (const Copy& c : m_copies) {
        VkBufferCopy region{c.src_offset, c.dst_offset, c.size};
        vkCmdCopyBuffer(cmd, staging.handle(), c.dst, 1, &region);
    }
    m_bytes.clear();
    m_copies.clear();
    // `staging` retires into the current frame's list here, freed once the frame completes.
    return true;
}

} // namespace vx::render
