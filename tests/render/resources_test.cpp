#include <algorithm>
#include <cstring>
#include <numeric>

#include "render/commands.h"
#include "render_test_util.h"

namespace vx::render {
namespace {

using ResourcesTest = test::RenderTest;

VkDeviceSize largest_heap(const Context& ctx) {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(ctx.physical_device(), &props);
    VkDeviceSize largest = 0;
    for (uint32_t i = 0; i < props.memoryHeapCount; ++i)
        largest = std::max(largest, props.memoryHeaps[i].size);
    return largest;
}

// A request for more than any heap holds fails in the allocator, before vkAllocateMemory (asking
// for more than a heap's size is invalid usage, VUID-vkAllocateMemory-pAllocateInfo-01713: the
// validation layer flagged it on an H100, whose maxBufferSize, 1 TiB, lets such a buffer
// through). The allocator still serves the next request.
TEST_F(ResourcesTest, AnAllocationLargerThanTheHeapFailsWithoutAskingTheDriver) {
    Buffer probe = Buffer::create(*m_ctx, {64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, 0, "probe"});
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(m_ctx->device(), probe.handle(), &req);
    GpuAllocator alloc(m_ctx->physical_device(), m_ctx->device(), 1 << 20);
    VkMemoryRequirements huge = req;
    huge.size = largest_heap(*m_ctx) + 1;
    Allocation a = alloc.allocate(huge, MemoryUse::Device, false);
    EXPECT_FALSE(a.valid());
    Allocation small = alloc.allocate(req, MemoryUse::Device, false);
    EXPECT_TRUE(small.valid());
    alloc.free(small);
    EXPECT_EQ(m_ctx->validation_errors(), 0u);
}

TEST_F(ResourcesTest, AllocatorHonoursAlignmentAndNeverOverlaps) {
    Buffer probe = Buffer::create(*m_ctx, {64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, 0, "probe"});
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(m_ctx->device(), probe.handle(), &req);
    GpuAllocator alloc(m_ctx->physical_device(), m_ctx->device(), 1 << 20); // 1 MiB blocks.
    std::vector<Allocation> live;
    const VkDeviceSize sizes[] = {16, 1000, 4096, 300000, 700000, 3 << 20, 256, 77};
    const VkDeviceSize aligns[] = {16, 256, 4096, 64, 256, 256, 1024, 16};
    for (int round = 0; round < 3; ++round)
        for (int i = 0; i < 8; ++i) {
            VkMemoryRequirements r = req;
            r.size = sizes[i];
            r.alignment = aligns[i];
            Allocation a = alloc.allocate(r, MemoryUse::Device, false);
            ASSERT_TRUE(a.valid());
            EXPECT_EQ(a.offset % aligns[i], 0u);
            EXPECT_GE(a.size, sizes[i]);
            for (const Allocation& b : live) {
                if (b.memory == a.memory) {
                    EXPECT_TRUE(a.offset + a.size <= b.offset || b.offset + b.size <= a.offset);
                }
            }
            live.push_back(a);
            if (i % 3 == 2) { // Free every other live allocation to fragment the blocks.
                alloc.free(live[live.size() / 2]);
                live.erase(live.begin() + ptrdiff_t(live.size() / 2));
            }
        }
    EXPECT_EQ(alloc.stats().allocations, live.size());
    for (const Allocation& a : live)
        alloc.free(a);
    const AllocatorStats s = alloc.stats();
    EXPECT_EQ(s.allocations, 0u);
    EXPECT_EQ(s.used_bytes, 0u);
    EXPECT_LE(s.blocks, 1u); // Empty blocks are released except the last of the pool.
}

TEST_F(ResourcesTest, UploadAndReadBackRoundTrip) {
    std::vector<uint32_t> data(10000);
    std::iota(data.begin(), data.end(), 7u);
    const size_t bytes = data.size() * 4;
    Buffer gpu = upload_buffer(*m_ctx, data.data(), bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "round trip");
    ASSERT_TRUE(gpu.valid());
    EXPECT_NE(gpu.address(), 0u);
    Buffer back = Buffer::create(*m_ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0, "back"});
    ASSERT_NE(back.mapped(), nullptr);
    m_ctx->submit_now([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, gpu.handle(), back.handle(), 1, &region);
    });
    EXPECT_EQ(std::memcmp(back.mapped(), data.data(), bytes), 0);
}

// A buffer past the device's largest (maxBufferSize), or one the driver has no memory for, is
// an empty buffer and a log line, never an abort: creation results were VK_CHECKed, so a 4096²
// frame with the light cache (4.8 GB of records) aborted on lavapipe. The validation layer stays
// silent (a create call past maxBufferSize would be invalid usage). A buffer within the limits
// is still made.
TEST_F(ResourcesTest, BuffersTheDeviceCannotMakeAreEmptyNotAborts) {
    ASSERT_GT(m_ctx->max_buffer_size(), 0u);
    // The largest heap + 1: refused before vkAllocateMemory, which must not be asked for more
    // than a heap holds (an H100: maxBufferSize 1 TiB, 80 GiB of memory; the validation layer
    // flagged the 1 TiB request there).
    const VkDeviceSize heap = largest_heap(*m_ctx);
    const VkDeviceSize sizes[] = {m_ctx->max_buffer_size() + 1, VkDeviceSize(5) << 30, VkDeviceSize(1) << 40,
                                  heap + 1};
    for (VkDeviceSize size : sizes) {
        Buffer b = Buffer::create(*m_ctx, {size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, 0, "too large"});
        if (size > m_ctx->max_buffer_size() || size > heap) {
            EXPECT_FALSE(b.valid()) << size;
        }
    }
    AccelStruct as = AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                                         m_ctx->max_buffer_size() + 256, "too large BLAS");
    EXPECT_FALSE(as.valid());
    Buffer fits = Buffer::create(*m_ctx, {4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, 0, "fits"});
    EXPECT_TRUE(fits.valid());
    EXPECT_EQ(m_ctx->validation_errors(), 0u);
}

// A new memory block that cannot be mapped (out of host memory mid-game; it was a VK_CHECK
// abort): the buffer that needed it is empty, as for any allocation the device refuses, and the
// block is freed; once mapping works again the same request gets a mapped buffer.
TEST_F(ResourcesTest, ANewBlockThatCannotBeMappedIsAFailedAllocation) {
    const VkDeviceSize big = VkDeviceSize(80) << 20; // Past the 64 MiB blocks: a block of its own.
    const BufferCreateInfo ci{big, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Upload, 0, "needs a new block"};
    const uint32_t blocks = m_ctx->allocator().stats().blocks;
    m_ctx->inject_result("vkMapMemory", VK_ERROR_MEMORY_MAP_FAILED);
    EXPECT_FALSE(Buffer::create(*m_ctx, ci).valid());
    m_ctx->fail_allocations("vkMapMemory");
    const BufferCreateInfo read{big, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0, "read"};
    EXPECT_FALSE(Buffer::create(*m_ctx, read).valid());
    EXPECT_EQ(m_ctx->allocator().stats().blocks, blocks);
    m_ctx->fail_allocations("");
    Buffer mapped = Buffer::create(*m_ctx, ci);
    ASSERT_TRUE(mapped.valid());
    EXPECT_NE(mapped.mapped(), nullptr);
}

TEST_F(ResourcesTest, DestroyedBuffersRetireUntilTheirFrameCompletes) {
    m_ctx->wait_idle();
    const uint32_t before = m_ctx->allocator().stats().allocations;
    m_ctx->begin_frame();
    {
        Buffer b = Buffer::create(*m_ctx, {1024, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Device, 0, "temp"});
        EXPECT_EQ(m_ctx->allocator().stats().allocations, before + 1);
    } // Destroyed while its frame is being recorded: retired, not freed.
    m_ctx->end_frame();
    EXPECT_EQ(m_ctx->allocator().stats().allocations, before + 1);
    m_ctx->begin_frame(); // The other slot: still not freed.
    m_ctx->end_frame();
    EXPECT_EQ(m_ctx->allocator().stats().allocations, before + 1);
    m_ctx->begin_frame(); // Back to the first slot: its fence has signalled, the list is freed.
    m_ctx->end_frame();
    EXPECT_EQ(m_ctx->allocator().stats().allocations, before);
}

TEST(Validation, MessengerCountsErrors) {
    std::unique_ptr<Context> ctx = test::make_test_context();
    ASSERT_NE(ctx, nullptr);
    EXPECT_EQ(ctx->validation_errors(), 0u);
    // A zero-sized buffer breaks VUID-VkBufferCreateInfo-size-00912: the counter must see it.
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = 0;
    ci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    const VkResult r = vkCreateBuffer(ctx->device(), &ci, nullptr, &buffer);
    EXPECT_GE(ctx->validation_errors(), 1u);
    if (r == VK_SUCCESS)
        vkDestroyBuffer(ctx->device(), buffer, nullptr);
}

} // namespace
} // namespace vx::render
