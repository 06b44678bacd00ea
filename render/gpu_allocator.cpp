#include "render/gpu_allocator.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

#include "world/base/assert.h"
#include "world/base/log.h"

namespace vx::render {

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

GpuAllocator::GpuAllocator(VkPhysicalDevice pd, VkDevice device, VkDeviceSize block_size, bool debug_names,
                           FaultInjection* faults)
    : m_device(device), m_block_size(block_size), m_debug_names(debug_names), m_faults(faults) {
    vkGetPhysicalDeviceMemoryProperties(pd, &m_props);
}

GpuAllocator::~GpuAllocator() {
    for (Block& b : m_blocks)
        if (b.memory)
            vkFreeMemory(m_device, b.memory, nullptr);
}

int GpuAllocator::find_memory_type(uint32_t type_bits, MemoryUse use) const {
    VkMemoryPropertyFlags required = 0, preferred = 0;
    switch (use) {
    case MemoryUse::Device: preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT; break;
    case MemoryUse::Upload:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        break;
    case MemoryUse::Readback:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    int fallback = -1;
    for (uint32_t i = 0; i < m_props.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i)))
            continue;
        const VkMemoryPropertyFlags f = m_props.memoryTypes[i].propertyFlags;
        if ((f & required) != required)
            continue;
        if ((f & preferred) == preferred)
            return int(i);
        if (fallback < 0)
            fallback = int(i);
    }
    return fallback;
}

int GpuAllocator::new_block(uint32_t pool, uint32_t memory_type, VkDeviceSize size) {
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &flags};
    ai.allocationSize = size;
    ai.memoryTypeIndex = memory_type;
    // More than the heap holds is invalid usage (VUID-vkAllocateMemory-pAllocateInfo-01713), not
    // a failure the driver reports: refused here. A discrete GPU's maxBufferSize (1 TiB on an
    // H100) is far past its memory.
    const VkDeviceSize heap = m_props.memoryHeaps[m_props.memoryTypes[memory_type].heapIndex].size;
    if (size > heap) {
        VX_LOG_ERROR("GPU allocator: %llu bytes is more than the memory heap holds (%llu bytes)",
                     (unsigned long long)size, (unsigned long long)heap);
        return -1;
    }
    Block b;
    if (vkAllocateMemory(m_device, &ai, nullptr, &b.memory) != VK_SUCCESS) {
        VX_LOG_ERROR("GPU allocator: vkAllocateMemory of %llu bytes failed", (unsigned long long)size);
        return -1;
    }
    // Out of host memory mapping a new block (a game running long meets it): the allocation
    // fails as when vkAllocateMemory does, and the caller reports it (it was a VK_CHECK abort).
    const bool host_visible = m_props.memoryTypes[memory_type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    if (host_visible && !map_block(b.memory, &b.mapped)) {
        vkFreeMemory(m_device, b.memory, nullptr);
        return -1;
    }
    b.size = size;
    b.pool = pool;
    b.add_range(0, size);
    size_t index = 0;
    while (index < m_blocks.size() && m_blocks[index].memory)
        ++index;
    if (index == m_blocks.size())
        m_blocks.emplace_back();
    if (m_debug_names)
        name_block(b.memory, index, pool, memory_type, size);
    m_blocks[index] = std::move(b);
    return int(index);
}

bool GpuAllocator::map_block(VkDeviceMemory memory, void** mapped) {
    VkResult r = m_faults ? m_faults->take("vkMapMemory") : VK_SUCCESS; // Test hook.
    if (r == VK_SUCCESS)
        r = vkMapMemory(m_device, memory, 0, VK_WHOLE_SIZE, 0, mapped);
    if (r == VK_SUCCESS)
        return true;
    VX_LOG_ERROR("GPU allocator: vkMapMemory of a new block failed (%s)", vk_result_name(r));
    *mapped = nullptr;
    return false;
}

// Which block a validation message is about: index, type, kind, size.
void GpuAllocator::name_block(VkDeviceMemory memory, size_t index, uint32_t pool, uint32_t memory_type,
                              VkDeviceSize size) {
    char name[96];
    std::snprintf(name, sizeof name, "vx memory block %zu (type %u, %s, %llu KiB)", index, memory_type,
                  pool % 2 ? "images" : "buffers", (unsigned long long)(size >> 10));
    VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    ni.objectType = VK_OBJECT_TYPE_DEVICE_MEMORY;
    ni.objectHandle = uint64_t(memory);
    ni.pObjectName = name;
    (void)vkSetDebugUtilsObjectNameEXT(m_device, &ni); // Out of host memory: only the name is missing.
}

void GpuAllocator::Block::add_range(VkDeviceSize offset, VkDeviceSize bytes) {
    free.emplace(offset, bytes);
    by_size.emplace(bytes, offset);
}

void GpuAllocator::Block::erase_range(std::map<VkDeviceSize, VkDeviceSize>::iterator it) {
    by_size.erase({it->second, it->first});
    free.erase(it);
}

bool GpuAllocator::carve(Block& b, VkDeviceSize size, VkDeviceSize align, VkDeviceSize& out_offset) {
    // Best fit: the smallest ranges that hold `size` are tried first (a few, as aligning their
    // start may leave too little); offsets and sizes are multiples of 16, so any range of
    // size + align - 16 bytes holds it whatever its start.
    auto fits = [&](std::pair<VkDeviceSize, VkDeviceSize> r) { return align_up(r.second, align) + size <= r.second + r.first; };
    auto it = b.by_size.lower_bound({size, 0});
    for (int tries = 0; it != b.by_size.end() && tries < 4 && !fits(*it); ++tries)
        ++it;
    if (it == b.by_size.end() || !fits(*it))
        it = b.by_size.lower_bound({size + align - 16, 0});
    if (it == b.by_size.end())
        return false;
    const VkDeviceSize offset = it->second, end = it->second + it->first;
    const VkDeviceSize start = align_up(offset, align);
    b.erase_range(b.free.find(offset));
    // Split the range into [offset, start) and [start + size, end).
    if (start > offset)
        b.add_range(offset, start - offset);
    if (start + size < end)
        b.add_range(start + size, end - start - size);
    out_offset = start;
    return true;
}

Allocation GpuAllocator::allocate(const VkMemoryRequirements& req, MemoryUse use, bool for_image, bool budgeted) {
    const int type = find_memory_type(req.memoryTypeBits, use);
    if (type < 0) {
        VX_LOG_ERROR("GPU allocator: no memory type fits (bits 0x%x)", req.memoryTypeBits);
        return {};
    }
    const uint32_t pool = uint32_t(type) * 2 + (for_image ? 1 : 0);
    const VkDeviceSize size = align_up(std::max<VkDeviceSize>(req.size, 1), 16);
    const VkDeviceSize align = std::max<VkDeviceSize>(req.alignment, 16);
    if (budgeted && m_budget > 0 && m_budgeted_used + size > m_budget)
        return {}; // The caller reports it (a chunk not drawn), as it would a full device.
    Allocation a;
    for (uint32_t i = 0; i < m_blocks.size() && !a.valid(); ++i) {
        Block& b = m_blocks[i];
        if (b.memory && b.pool == pool && b.size - b.used >= size && carve(b, size, align, a.offset))
            a.memory = b.memory, a.block = i;
    }
    if (!a.valid()) {
        const int i = new_block(pool, uint32_t(type), std::max(m_block_size, align_up(size, 1 << 20)));
        if (i < 0 || !carve(m_blocks[size_t(i)], size, align, a.offset))
            return {};
        a.memory = m_blocks[size_t(i)].memory;
        a.block = uint32_t(i);
    }
    Block& b = m_blocks[a.block];
    b.used += size;
    ++b.live;
    a.size = size;
    a.budgeted = budgeted;
    if (budgeted)
        m_budgeted_used += size;
    a.mapped = b.mapped ? static_cast<char*>(b.mapped) + a.offset : nullptr;
    return a;
}

void GpuAllocator::free(const Allocation& a) {
    if (!a.valid())
        return;
    VX_ASSERT(a.block < m_blocks.size() && m_blocks[a.block].memory == a.memory);
    Block& b = m_blocks[a.block];
    // Coalesce with the next and the previous range.
    VkDeviceSize offset = a.offset, size = a.size;
    auto next = b.free.lower_bound(offset);
    if (next != b.free.end() && offset + size == next->first) {
        size += next->second;
        auto after = std::next(next);
        b.erase_range(next);
        next = after;
    }
    if (next != b.free.begin()) {
        auto prev = std::prev(next);
        if (prev->first + prev->second == offset) {
            offset = prev->first;
            size += prev->second;
            b.erase_range(prev);
        }
    }
    b.add_range(offset, size);
    b.used -= a.size;
    --b.live;
    if (a.budgeted)
        m_budgeted_used -= a.size;
    if (b.live > 0)
        return;
    const auto same_pool = std::count_if(m_blocks.begin(), m_blocks.end(),
                                         [&](const Block& o) { return o.memory && o.pool == b.pool; });
    if (same_pool > 1) {
        vkFreeMemory(m_device, b.memory, nullptr);
        b = Block{};
    }
}

AllocatorStats GpuAllocator::stats() const {
    AllocatorStats s;
    for (const Block& b : m_blocks) {
        if (!b.memory)
            continue;
        ++s.blocks;
        s.block_bytes += b.size;
        s.used_bytes += b.used;
        s.allocations += b.live;
    }
    s.budgeted_bytes = m_budgeted_used;
    return s;
}

} // namespace vx::render
