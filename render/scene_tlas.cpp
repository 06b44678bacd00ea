// SceneAccel: the per-frame top-level acceleration structure.
#include <algorithm>

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
    // The instances persist (m_instances): this frame writes those changed since this slot's
    // last frame, and all of them only when the render origin moves (rarely) or the buffers grow.
    m_instances.follow_camera(camera_block);
    const uint32_t count = m_instances.size();
    m_stats.instances = count;
    m_stats.rebases = m_instances.rebases();

    FrameData& f = m_frames[m_ctx->frame_slot()];
    VkAccelerationStructureGeometryKHR geom = instance_geometry(0);
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &geom;
    bool fresh = false; // New buffers: every entry is written.
    if (!f.tlas.valid() || count > f.capacity) {
        // The capacity changes only once its buffers exist: a failed attempt retried next frame
        // once doubled it again each time (terabytes after a second of failures).
        const bool grow = count > f.capacity || f.capacity == 0; // 0: never made (an empty scene too).
        const uint32_t capacity = grow ? std::max(count, std::max(64u, f.capacity * 2)) : f.capacity;
        VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
        vkGetAccelerationStructureBuildSizesKHR(m_ctx->device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                                &capacity, &sizes);
        f.tlas_scratch = sizes.buildScratchSize;
        // One at a time: the first that fails is logged (Buffer::create), and the next frame
        // tries again (the TLAS is left invalid).
        f.tlas = AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
                                     sizes.accelerationStructureSize, "TLAS");
        if (f.tlas.valid())
            f.instances = Buffer::create(*m_ctx, {capacity * sizeof(VkAccelerationStructureInstanceKHR),
                                                  VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
                                                  MemoryUse::Upload, 16, "TLAS instances"});
        if (f.tlas.valid() && f.instances.valid())
            f.table = Buffer::create(*m_ctx, {capacity * sizeof(uint64_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                              MemoryUse::Upload, 16, "chunk table"});
        if (!f.tlas.valid() || !f.instances.valid() || !f.table.valid()) {
            f.tlas.reset();
            return false;
        }
        f.capacity = capacity;
        fresh = true;
    }
    // The slot's previous frame has completed (begin_frame waited for it): its buffers are free.
    m_stats.instance_writes =
        m_instances.sync(m_ctx->frame_slot(), static_cast<VkAccelerationStructureInstanceKHR*>(f.instances.mapped()),
                         static_cast<uint64_t*>(f.table.mapped()), fresh);
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
