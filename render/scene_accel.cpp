#include "render/scene_accel.h"

#include <algorithm>
#include <cstring>

namespace vx::render {


struct SceneAccel::BuildBatch {
    std::vector<VkAccelerationStructureGeometryKHR> geometries;
    std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
    std::vector<VkDeviceSize> scratch_sizes;
};

SceneAccel::SceneAccel(Context& ctx, bool allow_refit)
    : m_ctx(&ctx), m_staging(ctx), m_allow_refit(allow_refit),
      m_blas_flags(VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                   (allow_refit ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR : 0)) {}

void SceneAccel::set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh) {
    if (mesh.empty()) {
        remove_chunk(c);
        return;
    }
    ChunkGpu& g = m_chunks[c];
    // A refit keeps the tree built for the old geometry, whose boxes loosen as edits pile up, so
    // every kMaxRefits-th update of a chunk is a rebuild. On the H200 a 64-chunk refit costs
    // 2.9 ms against 15.4 ms rebuilt (docs/benchmarks.md): one rebuild in 16 adds about a third
    // to the update cost. The trace-time loss after k refits is not measured yet.
    constexpr uint32_t kMaxRefits = 16;
    const bool refit =
        m_allow_refit && g.blas.valid() && g.layout.fits(mesh) && g.refits_since_build < kMaxRefits;
    if (!refit)
        g.layout = SlotLayout::for_mesh(mesh);
    g.mesh = mesh;
    // A rebuild pending from an earlier set_chunk in the same frame stays a rebuild.
    g.pending = refit && g.pending != Pending::Build ? Pending::Refit : Pending::Build;
}

void SceneAccel::remove_chunk(world::ChunkCoord c) { m_chunks.erase(c); }

void SceneAccel::clear() { m_chunks.clear(); }

void SceneAccel::retain_only(const std::unordered_set<world::ChunkCoord, world::ChunkCoordHash>& keep) {
    std::erase_if(m_chunks, [&](const auto& kv) { return !keep.count(kv.first); });
}

void SceneAccel::ensure_indices(uint32_t slots) {
    if (slots <= m_index_slots)
        return;
    // Grow geometrically; the pattern is a prefix of itself, so refits still see the same indices.
    m_index_slots = std::max(slots, m_index_slots * 2);
    const std::vector<uint32_t> idx = slot_indices(m_index_slots);
    m_indices = upload_buffer(*m_ctx, idx.data(), idx.size() * sizeof(uint32_t),
                              VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
                              "slot index pattern");
    VX_ASSERT_MSG(m_indices.valid(), "out of GPU memory for the index pattern");
}

VkDeviceAddress SceneAccel::scratch(VkDeviceSize bytes) {
    const VkDeviceSize align = m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment;
    if (m_scratch.size() < bytes) {
        BufferCreateInfo bi;
        bi.size = std::max(bytes, m_scratch.size() * 2);
        bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        bi.alignment = align;
        bi.name = "AS scratch";
        m_scratch = Buffer::create(*m_ctx, bi); // The old one retires with this frame.
        VX_ASSERT_MSG(m_scratch.valid(), "out of GPU memory for AS scratch");
    }
    return align_up(m_scratch.address(), align);
}

static VkAccelerationStructureGeometryKHR triangle_geometry(VkDeviceAddress vertices, VkDeviceAddress indices,
                                                            uint32_t slots) {
    VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    auto& t = g.geometry.triangles;
    t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    t.vertexData.deviceAddress = vertices;
    t.vertexStride = 3 * sizeof(float);
    t.maxVertex = 4 * slots - 1;
    t.indexType = VK_INDEX_TYPE_UINT32;
    t.indexData.deviceAddress = indices;
    return g;
}

void SceneAccel::prepare_chunk(world::ChunkCoord c, ChunkGpu& g, BuildBatch& batch) {
    const uint32_t slots = g.layout.total;
    const bool build = g.pending == Pending::Build;
    if (build) {
        const VkBufferUsageFlags input = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                                         VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        g.vertices = Buffer::create(*m_ctx, {slots * kSlotVertexBytes, input, MemoryUse::Device, 0, "chunk vertices"});
        g.quads = Buffer::create(*m_ctx, {slots * kSlotQuadBytes,
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                          MemoryUse::Device, 0, "chunk quads"});
        VX_ASSERT_MSG(g.vertices.valid() && g.quads.valid(), "out of GPU memory for chunk geometry");
    }
    fill_slots(g.layout, g.mesh, static_cast<float*>(m_staging.add(g.vertices, 0, slots * kSlotVertexBytes)),
               static_cast<world::Quad*>(m_staging.add(g.quads, 0, slots * kSlotQuadBytes)));
    g.mesh.clear();

    batch.geometries.push_back(triangle_geometry(g.vertices.address(), m_indices.address(), slots));
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = m_blas_flags;
    info.mode = build ? VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR : VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR;
    info.geometryCount = 1;
    info.pGeometries = &batch.geometries.back();
    const uint32_t triangles = 2 * slots;
    if (build) {
        VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
        vkGetAccelerationStructureBuildSizesKHR(m_ctx->device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                                &triangles, &sizes);
        char name[96];
        std::snprintf(name, sizeof name, "BLAS chunk %d,%d,%d", c.x, c.y, c.z);
        g.blas = AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                                     sizes.accelerationStructureSize, name);
        VX_ASSERT_MSG(g.blas.valid(), "out of GPU memory for a BLAS");
        g.update_scratch = sizes.updateScratchSize;
        batch.scratch_sizes.push_back(sizes.buildScratchSize);
    } else {
        info.srcAccelerationStructure = g.blas.handle();
        batch.scratch_sizes.push_back(g.update_scratch);
    }
    info.dstAccelerationStructure = g.blas.handle();
    batch.infos.push_back(info);
    batch.ranges.push_back({triangles, 0, 0, 0});
    (build ? m_stats.blas_builds : m_stats.blas_refits)++;
    g.refits_since_build = build ? 0 : g.refits_since_build + 1;
    g.pending = Pending::None;
}

void SceneAccel::record_blas_builds(VkCommandBuffer cmd, BuildBatch& batch) {
    if (batch.infos.empty())
        return;
    const VkDeviceSize align = m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment;
    VkDeviceSize total = 0;
    std::vector<VkDeviceSize> offsets;
    for (VkDeviceSize s : batch.scratch_sizes) {
        offsets.push_back(total);
        total += align_up(s, align);
    }
    const VkDeviceAddress base = scratch(total + align);
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_ptrs;
    for (size_t i = 0; i < batch.infos.size(); ++i) {
        batch.infos[i].pGeometries = &batch.geometries[i]; // The vector may have moved while filling.
        batch.infos[i].scratchData.deviceAddress = base + offsets[i];
        range_ptrs.push_back(&batch.ranges[i]);
    }
    vkCmdBuildAccelerationStructuresKHR(cmd, uint32_t(batch.infos.size()), batch.infos.data(), range_ptrs.data());
}

void SceneAccel::record_builds(VkCommandBuffer cmd) {
    m_stats = {};
    // Work of earlier frames (traces reading chunk buffers, builds writing BLASes and scratch)
    // must finish before this frame overwrites them.
    memory_barrier(cmd,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR |
                       VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                       VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
    uint32_t max_slots = 0;
    VkDeviceSize staging_bytes = 0;
    for (auto& [c, g] : m_chunks)
        if (g.pending != Pending::None) {
            max_slots = std::max(max_slots, g.layout.total);
            staging_bytes += g.layout.total * (kSlotVertexBytes + kSlotQuadBytes) + 32;
        }
    ensure_indices(max_slots);

    m_staging.begin(staging_bytes);
    BuildBatch batch;
    batch.geometries.reserve(m_chunks.size());
    for (auto& [c, g] : m_chunks)
        if (g.pending != Pending::None)
            prepare_chunk(c, g, batch);
    if (m_staging.record(cmd))
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR |
                           VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                       VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    record_blas_builds(cmd, batch);
}

void SceneAccel::record_tlas_build(VkCommandBuffer cmd, world::BlockPos camera_block) {
    // One barrier between all BLAS builds and the TLAS build that references them.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
    record_tlas(cmd, camera_block);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    for (auto& [c, g] : m_chunks)
        m_stats.triangles += g.layout.triangle_count();
}

} // namespace vx::render
