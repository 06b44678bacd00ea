#pragma once
// Vulkan command boilerplate as free functions (niagara's barrier builders), and staging uploads.
// Main thread only.

#include <cstddef>

#include "render/resources.h"

namespace vx::render {

// A global memory barrier (synchronization2).
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// A layout transition of a single-mip colour image (synchronization2).
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access);

// A device-local buffer holding `bytes` of `data`, uploaded through a staging buffer with a
// one-shot submission (waits). `usage` gets TRANSFER_DST added. Empty Buffer on out-of-memory.
Buffer upload_buffer(Context& ctx, const void* data, size_t bytes, VkBufferUsageFlags usage, const char* name);

// Per-frame staging: appends data to a host-visible buffer that lives for one frame and records
// the copies into device buffers. Call flush() before the frame's command buffer is submitted;
// the staging buffer is then retired with the frame.
class StagingBatch {
public:
    explicit StagingBatch(Context& ctx) : m_ctx(&ctx) {}
    // Queues a copy of `bytes` from `data` into `dst` at `dst_offset`.
    void add(const Buffer& dst, VkDeviceSize dst_offset, const void* data, size_t bytes);
    // Records all queued copies into `cmd` (no barrier); returns false when nothing was queued.
    bool record(VkCommandBuffer cmd);

private:
    struct Copy {
        VkBuffer dst;
        VkDeviceSize dst_offset, src_offset, size;
    };
    Context* m_ctx;
    std::vector<unsigned char> m_bytes;
    std::vector<Copy> m_copies;
};

// Round `v` up to a multiple of `a` (a > 0).
inline VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

} // namespace vx::render
