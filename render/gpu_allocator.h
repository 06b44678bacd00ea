#pragma once
// A small GPU memory sub-allocator (VMA is not packaged for Debian 12): large blocks per memory
// type (64 MiB by default, bigger for bigger requests) carved by best fit from free ranges
// indexed by size (O(log ranges) per allocation and free, however fragmented the block: a
// first-fit scan of a list cost O(ranges) and was most of the CPU time of applying chunks once
// tens of thousands were resident), with coalescing. Buffers and images use separate blocks, so bufferImageGranularity never
// matters. Every block may back buffer device addresses; host-visible blocks stay mapped.
// Main thread only (not thread-safe).

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "render/fault_injection.h"
#include "render/vk_common.h"

namespace vx::render {

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0; // Bytes into `memory`.
    VkDeviceSize size = 0;   // Bytes reserved (the request, rounded up).
    void* mapped = nullptr;  // Host pointer to `offset`, or null when not host visible.
    uint32_t block = ~0u;    // Owning block (allocator-internal).
    bool budgeted = false;   // Counted against the allocator's budget (see set_budget).
    bool valid() const { return memory != VK_NULL_HANDLE; }
};

enum class MemoryUse : uint8_t {
    Device,   // Device local; the GPU reads and writes it.
    Upload,   // Host visible + coherent, written by the CPU (staging, per-frame data).
    Readback, // Host visible, preferably cached, read by the CPU.
};

struct AllocatorStats {
    uint32_t blocks = 0;
    VkDeviceSize block_bytes = 0; // Device memory held.
    VkDeviceSize used_bytes = 0;  // Of it, handed out.
    uint32_t allocations = 0;
    VkDeviceSize budgeted_bytes = 0; // Of used_bytes, allocations made with `budgeted`.
};

class GpuAllocator {
public:
    // `debug_names`: name each block for validation messages (needs VK_EXT_debug_utils).
    // `faults`: test hooks (the Context's) that may fail a new block's vkMapMemory; null: none.
    GpuAllocator(VkPhysicalDevice pd, VkDevice device, VkDeviceSize block_size = 64ull << 20,
                 bool debug_names = false, FaultInjection* faults = nullptr);
    ~GpuAllocator();
    GpuAllocator(const GpuAllocator&) = delete;
    GpuAllocator& operator=(const GpuAllocator&) = delete;

    // Reserves memory meeting `req` (size, alignment, type bits). `for_image` keeps images and
    // buffers apart. Returns an invalid Allocation (and logs) when the device is out of memory.
    // `budgeted`: memory that grows with the scene (chunk geometry, BLASes), whose failure the
    // caller survives; it is also refused (invalid, no log line) past the budget.
    Allocation allocate(const VkMemoryRequirements& req, MemoryUse use, bool for_image, bool budgeted = false);
    // Bytes that budgeted allocations may hold in all (rounded sizes); 0: no limit. A knob that
    // makes tests run out of memory the way a full device does, without filling one.
    void set_budget(VkDeviceSize bytes) { m_budget = bytes; }
    // Returns memory to its block; a block left empty is released unless it is the last of its pool.
    void free(const Allocation& a);

    AllocatorStats stats() const;

private:
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0, used = 0;
        void* mapped = nullptr;
        uint32_t pool = 0; // memory type * 2 + for_image
        uint32_t live = 0; // Allocations in it.
        std::map<VkDeviceSize, VkDeviceSize> free;            // Offset -> size; never adjacent (coalesced).
        std::set<std::pair<VkDeviceSize, VkDeviceSize>> by_size; // The same ranges as (size, offset).
        void add_range(VkDeviceSize offset, VkDeviceSize bytes);
        void erase_range(std::map<VkDeviceSize, VkDeviceSize>::iterator it);
    };

    int find_memory_type(uint32_t type_bits, MemoryUse use) const;
    bool carve(Block& b, VkDeviceSize size, VkDeviceSize align, VkDeviceSize& out_offset);
    int new_block(uint32_t pool, uint32_t memory_type, VkDeviceSize size);
    bool map_block(VkDeviceMemory memory, void** mapped);
    void name_block(VkDeviceMemory memory, size_t index, uint32_t pool, uint32_t memory_type, VkDeviceSize size);

    VkDevice m_device;
    VkPhysicalDeviceMemoryProperties m_props{};
    VkDeviceSize m_block_size;
    bool m_debug_names;
    FaultInjection* m_faults;
    VkDeviceSize m_budget = 0, m_budgeted_used = 0;
    std::vector<Block> m_blocks; // Slots of released blocks have memory == VK_NULL_HANDLE.
};

} // namespace vx::render
