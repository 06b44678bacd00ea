#pragma once
// Vulkan command boilerplate as free functions (niagara's barrier builders), and staging uploads.
// Main thread only.

#include <array>
#include <cstddef>
#include <vector>

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

// Per-frame staging: one grow-only host-visible buffer per frame slot (the slot's last frame
// has completed when it is reused), written in place by the caller, then copied into device
// buffers by record(). Main thread only.
class StagingRing {
public:
    explicit StagingRing(Context& ctx) : m_ctx(&ctx) {}
    // Starts this frame's staging with room for `bytes` (plus 16-byte alignment per copy).
    // False (logged) when the buffer cannot grow: nothing may be added this frame.
    bool begin(VkDeviceSize bytes);
    // Reserves `bytes` that will be copied into `dst` at `dst_offset`; returns where to write them.
    void* add(const Buffer& dst, VkDeviceSize dst_offset, VkDeviceSize bytes);
    // Records the copies into `cmd` (no barrier); false when there were none.
    bool record(VkCommandBuffer cmd);

private:
    struct Copy {
        VkBuffer dst;
        VkDeviceSize dst_offset, src_offset, size;
    };
    Context* m_ctx;
    std::array<Buffer, kFramesInFlight> m_buffers;
    VkDeviceSize m_used = 0, m_reserved = 0;
    std::vector<Copy> m_copies;
};

// Round `v` up to a multiple of `a` (a > 0).
inline VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

} // namespace vx::render
