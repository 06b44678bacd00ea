// SceneAccel: the per-frame top-level acceleration structure.
#include <algorithm>
#include <cstring>

#include "render/scene_accel.h"

namespace vx::render {

static VkAccelerationStructureGeometryKHR instance_geometry(VkDeviceAddress instances) {
    VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
    g.geometry.instances.arrayOfPointers = VK_FALSE;
    g.geometry.instances.data.deviceAddress = instances;
    return g;
}

bool SceneAccel::record_tlas(VkCommandBuffer cmd, world::BlockPos camera_block) {
    // Sorted coordinates: the instance order (and so the image) does not depend on hash order.
    std::vector<std::pair<world::ChunkCoord, ChunkGpu*>> chunks;
    chunks.reserve(m_chunks.size());
    for (auto& [c, g] : m_chunks)
        if (g.blas.valid()) // Not chunks whose memory ran out.
            chunks.emplace_back(c, &g);
    std::sort(chunks.begin(), chunks.end(), [](const auto& a, const auto& b) {
        return std::tie(a.first.x, a.first.y, a.first.z) < std::tie(b.first.x, b.first.y, b.first.z);
    });
    const uint32_t count = uint32_t(chunks.size());
    m_stats.instances = count;

    FrameData& f = m_frames[m_ctx->frame_slot()];
    VkAccelerationStructureGeometryKHR geom = instance_geometry(0);
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &geom;
    if (!f.tlas.valid() || count > f.capacity) {
        f.capacity = std::max(count, std::max(64u, f.capacity * 2));
        VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
        vkGetAccelerationStructureBuildSizesKHR(m_ctx->device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                                &f.capacity, &sizes);
        f.tlas_scratch = sizes.buildScratchSize;
        // One at a time: the first that fails is logged (Buffer::create), and the next frame
        // tries again (the TLAS is left invalid).
        f.tlas = AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
                                     sizes.accelerationStructureSize, "TLAS");
        if (f.tlas.valid())
            f.instances = Buffer::create(*m_ctx, {f.capacity * sizeof(VkAccelerationStructureInstanceKHR),
                                                  VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
                                                  MemoryUse::Upload, 16, "TLAS instances"});
        if (f.tlas.valid() && f.instances.valid())
            f.table = Buffer::create(*m_ctx, {f.capacity * sizeof(uint64_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                              MemoryUse::Upload, 16, "chunk table"});
        if (!f.tlas.valid() || !f.instances.valid() || !f.table.valid()) {
            f.tlas.reset();
            return false;
        }
    }

    auto* inst = static_cast<VkAccelerationStructureInstanceKHR*>(f.instances.mapped());
    auto* table = static_cast<uint64_t*>(f.table.mapped());
    for (uint32_t i = 0; i < count; ++i) {
        // 64-bit difference first, then float: exact while the chunk is within 2^24 blocks of the camera.
        const world::BlockPos rel = world::chunk_origin(chunks[i].first) - camera_block;
        VkAccelerationStructureInstanceKHR& d = inst[i];
        d = {};
        d.transform.matrix[0][0] = d.transform.matrix[1][1] = d.transform.matrix[2][2] = 1.f;
        d.transform.matrix[0][3] = float(rel.x);
        d.transform.matrix[1][3] = float(rel.y);
        d.transform.matrix[2][3] = float(rel.z);
        d.instanceCustomIndex = i;
        d.mask = 0xFF;
        d.instanceShaderBindingTableRecordOffset = 0;
        d.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
        d.accelerationStructureReference = chunks[i].second->blas.address();
        table[i] = chunks[i].second->quads.address();
    }
    m_draw_list.clear();
    for (const auto& [c, g] : chunks)
        m_draw_list.push_back({c, g->quads.address(), g->layout.total});
    geom = instance_geometry(f.instances.address());
    info.dstAccelerationStructure = f.tlas.handle();
    info.scratchData.deviceAddress = scratch(f.tlas_scratch + m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment);
    if (!info.scratchData.deviceAddress)
        return false;
    const VkAccelerationStructureBuildRangeInfoKHR range{count, 0, 0, 0};
    const VkAccelerationStructureBuildRangeInfoKHR* range_ptr = &range;
    vkCmdBuildAccelerationStructuresKHR(cmd, 1, &info, &range_ptr);
    return true;
}

} // namespace vx::render
