#include "render/tlas_instances.h"

#include <algorithm>

#include "world/base/assert.h"

namespace vx::render {

TlasInstances::TlasInstances(uint32_t frame_slots)
    : m_slots(frame_slots), m_dirty(frame_slots), m_all_dirty(frame_slots, false) {
    VX_ASSERT(frame_slots >= 1 && frame_slots <= 8); // One bit of m_marked per slot.
}

VkAccelerationStructureInstanceKHR TlasInstances::make_instance(world::LodCoord chunk, world::BlockPos origin,
                                                                uint32_t index, VkDeviceAddress blas) {
    VX_ASSERT(world::valid_lod_level(chunk.level));
    // 64-bit difference first, then float: exact while the chunk is within 2^24 blocks of the origin.
    const world::BlockPos rel = world::lod_origin(chunk) - origin;
    VkAccelerationStructureInstanceKHR d{};
    // A power of two: the traversal's world-to-object transform (1 / scale) is exact too.
    const float scale = float(world::lod_cell_size(chunk.level));
    d.transform.matrix[0][0] = d.transform.matrix[1][1] = d.transform.matrix[2][2] = scale;
    d.transform.matrix[0][3] = float(rel.x);
    d.transform.matrix[1][3] = float(rel.y);
    d.transform.matrix[2][3] = float(rel.z);
    d.instanceCustomIndex = index; // The chunk table's entry (the shaders' gl_InstanceCustomIndexEXT).
    d.mask = 0xFF;
    d.instanceShaderBindingTableRecordOffset = 0;
    // Faces wind counter-clockwise about their normal (world::quad_corners), which Vulkan's default
    // facing rule (no FLIP_FACING) takes as front-facing seen from the air side (checked: the
    // glass tests fail with FLIP_FACING). Only trace_through's probes for coincident transparent
    // faces cull by facing, so no other ray sees a difference.
    d.flags = 0;
    d.accelerationStructureReference = blas;
    return d;
}

void TlasInstances::mark(uint32_t i) {
    if (m_marked.size() <= i)
        m_marked.resize(size_t(i) + 1, 0);
    for (uint32_t s = 0; s < m_slots; ++s)
        if (!(m_marked[i] & (1u << s))) {
            m_marked[i] = uint8_t(m_marked[i] | (1u << s));
            m_dirty[s].push_back(i);
        }
}

void TlasInstances::write(uint32_t i) {
    m_instances[i] = make_instance(m_draw[i].coord, m_origin, i, m_instances[i].accelerationStructureReference);
    mark(i);
}

uint32_t TlasInstances::add(const DrawChunk& chunk, VkDeviceAddress blas) {
    VX_ASSERT(world::valid_lod_level(chunk.coord.level));
    const uint32_t i = size();
    m_draw.push_back(chunk);
    ++m_level_counts[size_t(chunk.coord.level)];
    m_instances.push_back(make_instance(chunk.coord, m_origin, i, blas));
    mark(i);
    return i;
}

void TlasInstances::update(uint32_t i, const DrawChunk& chunk, VkDeviceAddress blas) {
    VX_ASSERT(i < size() && m_draw[i].coord == chunk.coord);
    if (m_instances[i].accelerationStructureReference == blas && m_draw[i].quads == chunk.quads &&
        m_draw[i].slots == chunk.slots && m_draw[i].opaque == chunk.opaque)
        return; // A refit: same BLAS, same buffers.
    m_draw[i] = chunk;
    m_instances[i].accelerationStructureReference = blas;
    mark(i);
}

std::optional<world::LodCoord> TlasInstances::remove(uint32_t i) {
    VX_ASSERT(i < size());
    const uint32_t last = size() - 1;
    --m_level_counts[size_t(m_draw[i].coord.level)];
    std::optional<world::LodCoord> moved;
    if (i != last) {
        m_draw[i] = m_draw[last];
        m_instances[i] = m_instances[last];
        write(i); // Its custom index is now i.
        moved = m_draw[i].coord;
    }
    // Entries past the end stay listed: sync() skips them.
    m_draw.pop_back();
    m_instances.pop_back();
    if (m_draw.empty())
        m_origin_free = true;
    return moved;
}

void TlasInstances::clear() {
    m_draw.clear();
    m_level_counts.fill(0);
    m_instances.clear();
    m_origin_free = true;
}

bool TlasInstances::follow_camera(world::BlockPos camera) {
    const world::BlockPos d = camera - m_origin;
    const bool far = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) > kRebaseDistance;
    const bool free = m_origin_free;
    m_origin_free = m_draw.empty();
    if (!far && !(free && d != world::BlockPos(0, 0, 0)))
        return false;
    m_origin = camera;
    if (m_draw.empty())
        return true;
    // Added since the array was last empty, or a real re-base: every instance moves.
    for (uint32_t i = 0; i < size(); ++i)
        m_instances[i] = make_instance(m_draw[i].coord, m_origin, i, m_instances[i].accelerationStructureReference);
    std::fill(m_all_dirty.begin(), m_all_dirty.end(), true);
    if (!free)
        ++m_rebases;
    return true;
}

uint32_t TlasInstances::sync(uint32_t slot, VkAccelerationStructureInstanceKHR* instances, uint64_t* table, bool all) {
    VX_ASSERT(slot < m_slots);
    const uint32_t n = size();
    uint32_t written = 0;
    auto put = [&](uint32_t i) {
        instances[i] = m_instances[i];
        table[i] = m_draw[i].quads;
        ++written;
    };
    const uint8_t bit = uint8_t(1u << slot);
    if (all || m_all_dirty[slot]) {
        for (uint32_t i = 0; i < n; ++i)
            put(i);
        m_all_dirty[slot] = false;
    } else {
        for (uint32_t i : m_dirty[slot])
            if (i < n)
                put(i);
    }
    for (uint32_t i : m_dirty[slot])
        m_marked[i] = uint8_t(m_marked[i] & ~bit);
    m_dirty[slot].clear();
    return written;
}

} // namespace vx::render
