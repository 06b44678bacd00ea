#include "render/commands.h"

#include <algorithm>
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

bool StagingRing::begin(VkDeviceSize bytes) {
    VX_ASSERT(m_copies.empty());
    Buffer& b = m_buffers[m_ctx->frame_slot()];
    if (b.size() < bytes) {
        BufferCreateInfo bi;
        bi.size = std::max(bytes, b.size() + b.size() / 2);
        bi.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
        bi.memory = MemoryUse::Upload;
        bi.name = "frame staging";
        b = Buffer::create(*m_ctx, bi);
        if (!b.valid() && bi.size > bytes) { // Room for what is asked, not for the growth.
            bi.size = bytes;
            b = Buffer::create(*m_ctx, bi);
        }
        if (!b.valid())
            return false; // Logged by Buffer::create.
    }
    m_used = 0;
    m_reserved = bytes;
    return true;
}

void* StagingRing::add(const Buffer& dst, VkDeviceSize dst_offset, VkDeviceSize bytes) {
    const VkDeviceSize at = align_up(m_used, 16);
    VX_ASSERT_MSG(at + bytes <= m_reserved, "staging beyond what begin() reserved");
    m_used = at + bytes;
    m_copies.push_back({dst.handle(), dst_offset, at, bytes});
    return static_cast<unsigned char*>(m_buffers[m_ctx->frame_slot()].mapped()) + at;
}

bool StagingRing::record(VkCommandBuffer cmd) {
    if (m_copies.empty())
        return false;
    const VkBuffer src = m_buffers[m_ctx->frame_slot()].handle();
    for (const Copy& c : m_copies) {
        VkBufferCopy region{c.src_offset, c.dst_offset, c.size};
        vkCmdCopyBuffer(cmd, src, c.dst, 1, &region);
    }
    m_copies.clear();
    return true;
}

} // namespace vx::render
