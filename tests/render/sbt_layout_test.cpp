// The shader binding table's layout (render/rt_pipeline.h): every region starts at a multiple of
// shaderGroupBaseAlignment in device-address space and lies inside the buffer, whatever the
// buffer's own address. The table used to start at the buffer's address, aligned only as far as
// the allocation's offset within its memory block (VUID-vkCmdTraceRaysKHR-
// pRayGenShaderBindingTable-03682 when a block's base address is not so aligned).
#include <gtest/gtest.h>

#include "render/rt_pipeline.h"

namespace vx::render {
namespace {

struct Props {
    uint32_t handle, handle_alignment, base; // shaderGroupHandleSize, ...HandleAlignment, ...BaseAlignment.
};

TEST(SbtLayout, RegionsAreBaseAlignedInsideTheBufferAtAnyAddress) {
    // lavapipe and NVIDIA (32, 32, 64); 256: the largest base alignment Vulkan allows; a handle
    // larger than its alignment.
    const Props props[] = {{32, 32, 64}, {32, 32, 256}, {48, 16, 64}, {16, 16, 32}};
    for (const Props& p : props) {
        const SbtLayout l = sbt_layout(p.handle, p.handle_alignment, p.base);
        EXPECT_EQ(l.stride % p.handle_alignment, 0u);
        EXPECT_GE(l.stride, p.handle);
        EXPECT_EQ(l.raygen_size, l.stride <= p.base ? p.base : l.raygen_size); // Raygen: stride == size.
        EXPECT_GE(l.miss_size, 2 * l.stride);
        // Addresses aligned to 16 (what a buffer of our allocator may get) up to the base.
        for (VkDeviceAddress buffer = 0x10000; buffer < 0x10000 + 2 * p.base; buffer += 16) {
            const VkDeviceAddress start = sbt_start(buffer, p.base);
            const VkDeviceAddress starts[] = {start, start + l.raygen_flat_at, start + l.miss_at, start + l.hit_at};
            for (VkDeviceAddress a : starts)
                EXPECT_EQ(a % p.base, 0u) << "buffer " << buffer << " base " << p.base;
            EXPECT_GE(start, buffer);
            EXPECT_LE(start + l.hit_at + l.hit_size, buffer + l.bytes) << "buffer " << buffer;
            // Regions do not overlap.
            EXPECT_LE(l.raygen_size, l.raygen_flat_at);
            EXPECT_LE(l.raygen_flat_at + l.raygen_size, l.miss_at);
            EXPECT_LE(l.miss_at + l.miss_size, l.hit_at);
        }
    }
}

} // namespace
} // namespace vx::render
