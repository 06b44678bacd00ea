// SceneAccel: the frame's chunk uploads and BLAS builds and refits (record_builds): pending chunks
// planned and sized, the frame's batch fitted to the staging and scratch budget, chunk buffers
// allocated (or the chunk failed), and every build of the frame recorded in one call.
#include <algorithm>
#include <cstdio>
#include <span>
#include <utility>
#include <vector>

#include "render/scene_accel.h"
#include "render/scene_accel_budget.h"
#include "world/base/assert.h"
#include "world/base/log.h"

namespace vx::render {

// A pending chunk and what building it this frame asks of the shared buffers.
struct SceneAccel::PendingBuild {
    world::LodCoord c;
    ChunkGpu* g; // Element pointers survive rehashing.
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    VkDeviceSize staging = 0; // staging_bytes().
    VkDeviceSize scratch = 0; // Build or update scratch, aligned up to its offset alignment.
};

struct SceneAccel::BuildBatch {
    std::vector<VkAccelerationStructureGeometryKHR> geometries;
    std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
    std::vector<VkDeviceSize> scratch_sizes;
    std::vector<world::LodCoord> coords; // The chunk of each build.
};

bool SceneAccel::ensure_indices(uint32_t slots) {
    if (slots <= m_index_slots)
        return true;
    // Grow geometrically; the pattern is a prefix of itself, so refits still see the same indices.
    const uint32_t grown = std::max(slots, m_index_slots * 2);
    const std::vector<uint32_t> idx = slot_indices(grown);
    Buffer indices = upload_buffer(*m_ctx, idx.data(), idx.size() * sizeof(uint32_t),
                                   VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                                       VK_BUFFER_USAGE_INDEX_BUFFER_BIT, // The raster pipeline draws with it too.
                                   "slot index pattern");
    if (!indices.valid())
        return false; // Logged by Buffer::create; the old pattern stays.
    m_indices = std::move(indices);
    m_index_slots = grown;
    return true;
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
        if (!m_scratch.valid() && bi.size > bytes) { // Room for what is asked, not for the growth.
            bi.size = bytes;
            m_scratch = Buffer::create(*m_ctx, bi);
        }
        if (!m_scratch.valid())
            return 0; // Logged by Buffer::create; the next call tries again.
    }
    return align_up(m_scratch.address(), align);
}

static VkAccelerationStructureGeometryKHR triangle_geometry(VkDeviceAddress vertices, VkDeviceAddress indices,
                                                            uint32_t slots, bool opaque) {
    VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    // Chunks with transparent blocks are not OPAQUE: shadow rays run the any-hit shader
    // (shaders/shadow.rahit) so transparent blocks pass light; an opaque block's face ends the ray
    // at its first any-hit call. Primary rays are traced with gl_RayFlagsOpaqueEXT and never run
    // it. No duplicate calls: each face tints once. That flag keeps the builder from splitting
    // triangles, which costs trace time (measured on the H200: flat trace +26% on the seed
    // scene), so chunks of opaque blocks only keep OPAQUE geometry.
    g.flags = opaque ? VK_GEOMETRY_OPAQUE_BIT_KHR : VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;
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

static constexpr VkDeviceSize kSlotBytes = kSlotVertexBytes + kSlotQuadBytes;

// Staging a pending chunk needs: all its slots, or the dirty slices' (plus alignment per copy).
VkDeviceSize SceneAccel::staging_bytes(const ChunkGpu& g) const {
    if (g.pending == Pending::Build || g.dirty.all())
        return g.layout.total * kSlotBytes + 32;
    VkDeviceSize bytes = 0;
    for (int s = 0; s < world::kSliceCount; ++s)
        if (g.dirty.test(size_t(s)))
            bytes += g.layout.capacity[s] * kSlotBytes + 32;
    return bytes;
}

void SceneAccel::fail_chunk(world::LodCoord c, ChunkGpu& g, VkDeviceSize bytes) {
    if (!m_logged_failure)
        VX_LOG_ERROR("renderer: out of GPU memory for chunk %d,%d,%d of level %d (%llu bytes): not drawn; further "
                     "failures are only counted (RenderStats::failed_chunks)",
                     c.chunk.x, c.chunk.y, c.chunk.z, c.level, (unsigned long long)bytes);
    m_logged_failure = true;
    g.vertices.reset();
    g.quads.reset();
    g.blas.reset();
    g.mesh = world::ChunkMesh{};
    g.slots.clear();
    g.failed = true;
    g.hot = false;
    g.pending = Pending::None;
    g.dirty.reset();
    drop_instance(g);
    retally(g);
}

// A cool-down rebuild is only an optimisation: without memory for it the chunk stays hot, its
// BLAS, buffers and mesh as they were, and cools down later.
void SceneAccel::cool_down_failed(world::LodCoord c, ChunkGpu& g) {
    g.hot = true;
    g.layout = *g.cooling_from;
    g.cooling_from.reset();
    g.pending = Pending::None;
    g.dirty.reset();
    m_hot_queue.emplace_back(c, g.last_edit_frame);
    retally(g);
}

// New buffers and BLAS for a build; on failure the chunk is dropped from the scene (not drawn),
// unless it was a cool-down (cool_down_failed).
bool SceneAccel::allocate_chunk(world::LodCoord c, ChunkGpu& g,
                                const VkAccelerationStructureBuildSizesInfoKHR& sizes) {
    const VkDeviceSize slots = g.layout.total;
    const VkBufferUsageFlags input =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    Buffer vertices =
        Buffer::create(*m_ctx, {slots * kSlotVertexBytes, input, MemoryUse::Device, 0, "chunk vertices", true});
    Buffer quads = Buffer::create(*m_ctx, {slots * kSlotQuadBytes,
                                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           MemoryUse::Device, 0, "chunk quads", true});
    char name[96];
    std::snprintf(name, sizeof name, "BLAS chunk %d,%d,%d L%d%s", c.chunk.x, c.chunk.y, c.chunk.z, c.level,
                  g.hot ? " (hot)" : "");
    AccelStruct blas = AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                                           sizes.accelerationStructureSize, name, true);
    if (!vertices.valid() || !quads.valid() || !blas.valid()) {
        if (g.cooling_from)
            cool_down_failed(c, g);
        else
            fail_chunk(c, g, slots * kSlotBytes + sizes.accelerationStructureSize);
        return false; // What was allocated retires with the locals.
    }
    g.cooling_from.reset();
    g.vertices = std::move(vertices); // The old ones retire with this frame.
    g.quads = std::move(quads);
    g.blas = std::move(blas);
    return true;
}

void SceneAccel::upload_chunk(ChunkGpu& g, bool whole) {
    const SlotLayout& l = g.layout;
    if (whole || g.dirty.all()) {
        auto* v = static_cast<float*>(m_staging.add(g.vertices, 0, l.total * kSlotVertexBytes));
        auto* q = static_cast<world::Quad*>(m_staging.add(g.quads, 0, l.total * kSlotQuadBytes));
        if (!g.hot) {
            g.slots.clear();
            fill_slots(l, g.mesh, v, q);
        } else {
            // A build lays the slots out afresh; a refit of every slice keeps what it can.
            if (whole || g.slots.empty())
                g.slots.assign(l, g.mesh);
            else
                for (int s = 0; s < world::kSliceCount; ++s)
                    g.slots.update_slice(l, g.mesh, s);
            g.slots.write_all(l, v, q);
        }
        m_stats.upload_bytes += l.total * kSlotBytes;
        return;
    }
    VX_ASSERT(g.hot && !g.slots.empty()); // Only a refit uploads part of a chunk.
    for (int s = 0; s < world::kSliceCount; ++s) {
        if (!g.dirty.test(size_t(s)) || l.capacity[s] == 0)
            continue;
        void* v = m_staging.add(g.vertices, l.start[s] * kSlotVertexBytes, l.capacity[s] * kSlotVertexBytes);
        void* q = m_staging.add(g.quads, l.start[s] * kSlotQuadBytes, l.capacity[s] * kSlotQuadBytes);
        g.slots.update_slice(l, g.mesh, s);
        g.slots.write_slice(l, s, static_cast<float*>(v), static_cast<world::Quad*>(q));
        m_stats.upload_bytes += l.capacity[s] * kSlotBytes;
    }
}

static VkAccelerationStructureBuildGeometryInfoKHR blas_info(bool hot, bool build) {
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                 (hot ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR
                      : VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR);
    info.mode = build ? VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR : VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR;
    info.geometryCount = 1;
    return info;
}

SceneAccel::PendingBuild SceneAccel::plan_chunk(world::LodCoord c, ChunkGpu& g) const {
    PendingBuild p{c, &g};
    p.staging = staging_bytes(g);
    VkDeviceSize scratch_bytes = g.update_scratch;
    if (g.pending == Pending::Build) {
        VkAccelerationStructureBuildGeometryInfoKHR info = blas_info(g.hot, true);
        const VkAccelerationStructureGeometryKHR shape = triangle_geometry(0, 0, g.layout.total, g.opaque);
        info.pGeometries = &shape;
        const uint32_t triangles = 2 * g.layout.total;
        vkGetAccelerationStructureBuildSizesKHR(m_ctx->device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                                &triangles, &p.sizes);
        scratch_bytes = p.sizes.buildScratchSize;
    }
    p.scratch = align_up(scratch_bytes, m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment);
    return p;
}

void SceneAccel::prepare_chunk(const PendingBuild& p, BuildBatch& batch) {
    const world::LodCoord c = p.c;
    ChunkGpu& g = *p.g;
    const uint32_t slots = g.layout.total;
    const bool build = g.pending == Pending::Build;
    VkAccelerationStructureBuildGeometryInfoKHR info = blas_info(g.hot, build);
    const uint32_t triangles = 2 * slots;
    if (build) {
        if (!allocate_chunk(c, g, p.sizes))
            return;
        g.update_scratch = p.sizes.updateScratchSize;
        g.build_serial = m_next_serial++;
        g.refits_since_build = 0;
        ++m_stats.blas_builds;
    } else {
        info.srcAccelerationStructure = g.blas.handle();
        ++g.refits_since_build;
        ++m_stats.blas_refits;
    }
    upload_chunk(g, build);
    batch.geometries.push_back(triangle_geometry(g.vertices.address(), m_indices.address(), slots, g.opaque));
    info.dstAccelerationStructure = g.blas.handle();
    batch.infos.push_back(info); // pGeometries is set in record_blas_builds.
    batch.ranges.push_back({triangles, 0, 0, 0});
    batch.scratch_sizes.push_back(p.scratch);
    batch.coords.push_back(c);
    g.pending = Pending::None;
    g.dirty.reset();
}

void SceneAccel::record_blas_builds(VkCommandBuffer cmd, BuildBatch& batch) {
    if (batch.infos.empty())
        return;
    const VkDeviceSize align = m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment;
    VkDeviceSize total = 0;
    std::vector<VkDeviceSize> offsets;
    for (VkDeviceSize s : batch.scratch_sizes) { // Aligned already (plan_chunk).
        offsets.push_back(total);
        total += s;
    }
    // allocate_batch made room for at least these (the chunks that failed since only take less).
    const VkDeviceAddress base = scratch(total + align);
    VX_ASSERT(base != 0);
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_ptrs;
    for (size_t i = 0; i < batch.infos.size(); ++i) {
        batch.infos[i].pGeometries = &batch.geometries[i]; // The vector may have moved while filling.
        batch.infos[i].scratchData.deviceAddress = base + offsets[i];
        range_ptrs.push_back(&batch.ranges[i]);
    }
    vkCmdBuildAccelerationStructuresKHR(cmd, uint32_t(batch.infos.size()), batch.infos.data(), range_ptrs.data());
}

bool SceneAccel::record_builds(VkCommandBuffer cmd) {
    m_stats = {};
    ++m_frame;
    // Work of earlier frames (traces reading chunk buffers, builds writing BLASes and scratch)
    // must finish before this frame overwrites them or copies them into compacted BLASes.
    memory_barrier(cmd,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR |
                       VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                       VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
    record_compactions(cmd);
    demote_idle_hot_chunks();
    std::vector<world::LodCoord> later;
    std::vector<PendingBuild> pending = take_pending(later);
    size_t first = 0, count = 0;
    uint32_t max_slots = 0;
    const bool room = pending.empty() || allocate_batch(pending, first, count);
    for (size_t i = first; room && i < first + count; ++i)
        max_slots = std::max(max_slots, pending[i].g->layout.total);
    // Out of memory for the frame's own buffers: every pending chunk stays pending, in order.
    if (!room || !ensure_indices(max_slots)) {
        for (PendingBuild& p : pending)
            queue(p.c, *p.g);
        m_pending.insert(m_pending.end(), later.begin(), later.end());
        return false;
    }
    for (size_t i = 0; i < first; ++i) // Too large alone, while later chunks fit.
        fail_alone(pending[i]);
    BuildBatch batch;
    batch.geometries.reserve(count);
    for (size_t i = first; i < first + count; ++i)
        prepare_chunk(pending[i], batch);
    for (size_t i = first + count; i < pending.size(); ++i) // Later frames, in the same order.
        queue(pending[i].c, *pending[i].g);
    m_pending.insert(m_pending.end(), later.begin(), later.end());
    if (m_staging.record(cmd))
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR |
                           VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                       VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    record_blas_builds(cmd, batch);
    for (world::LodCoord c : batch.coords) {
        ChunkGpu& g = m_chunks.at(c);
        if (!g.hot) {
            // Cold: never refitted, so the vertices are needed only by this build; they retire
            // with this frame. The compacted-size query follows the build (record_compaction_queries).
            g.vertices.reset();
            g.mesh = world::ChunkMesh{};
            m_built_cold.push_back(c);
        }
        sync_instance(c, g);
        retally(g);
    }
    return true;
}

// The queued chunks still pending, in queue order, up to those past this frame's limits: the
// rest stay listed, unread, in `later` (a scene sent whole is not sized again every frame). One
// whose staging or scratch alone exceeds the device's largest buffer can never be built: it
// fails now, for itself.
std::vector<SceneAccel::PendingBuild> SceneAccel::take_pending(std::vector<world::LodCoord>& later) {
    std::vector<PendingBuild> pending;
    const VkDeviceSize largest = m_ctx->max_buffer_size();
    const VkDeviceSize align = m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment;
    VkDeviceSize staging = 0, scratch_bytes = 0;
    for (size_t i = 0; i < m_pending.size(); ++i) {
        if (staging > m_staging_limit || scratch_bytes > m_scratch_limit) {
            later.assign(m_pending.begin() + ptrdiff_t(i), m_pending.end());
            break;
        }
        const world::LodCoord c = m_pending[i];
        auto it = m_chunks.find(c);
        if (it == m_chunks.end() || !it->second.queued)
            continue; // Removed since, or listed twice (removed and set again).
        ChunkGpu& g = it->second;
        g.queued = false;
        if (g.pending == Pending::None)
            continue;
        PendingBuild p = plan_chunk(c, g);
        if (largest && (p.staging > largest || p.scratch + align > largest)) {
            fail_alone(p);
            continue;
        }
        staging += p.staging;
        scratch_bytes += p.scratch;
        pending.push_back(p);
    }
    m_pending.clear();
    return pending;
}

// This frame's builds: pending[first, first + count), the longest run from `first` within the
// staging and scratch limits (at least one chunk), with the staging ring and the scratch buffer
// grown to hold them. An allocation that fails halves the limit it hit (remembered: later
// frames start there, and it doubles back up after each frame that fits) and a shorter run is
// tried, instead of the whole batch again next frame. A chunk that fails alone is skipped and
// fails for itself (pending[0, first)), as when its own buffers cannot be allocated; a second
// one means memory is short for all, whatever the size: false, and the frame fails with every
// chunk kept pending.
bool SceneAccel::allocate_batch(std::span<const PendingBuild> pending, size_t& first, size_t& count) {
    const VkDeviceSize align = m_ctx->as_properties().minAccelerationStructureScratchOffsetAlignment;
    uint32_t alone = 0;
    for (first = 0; first < pending.size();) {
        VkDeviceSize staging = 0, scratch_bytes = align; // Slack to align the scratch's base.
        for (count = 0; first + count < pending.size(); ++count) {
            const PendingBuild& p = pending[first + count];
            if (count > 0 && (staging + p.staging > m_staging_limit || scratch_bytes + p.scratch > m_scratch_limit))
                break;
            staging += p.staging;
            scratch_bytes += p.scratch;
        }
        const bool staged = m_staging.begin(staging);
        if (staged && scratch(scratch_bytes)) {
            m_staging_limit = std::min(frame_build_cap(*m_ctx), 2 * m_staging_limit);
            m_scratch_limit = std::min(frame_build_cap(*m_ctx), 2 * m_scratch_limit);
            return true;
        }
        if (!staged)
            m_staging_limit = std::max<VkDeviceSize>(staging / 2, 1);
        else
            m_scratch_limit = std::max<VkDeviceSize>(scratch_bytes / 2, 1);
        if (count > 1)
            continue;
        if (++alone == 2) {
            // Not a matter of size: the next frame starts from the full budget again.
            m_staging_limit = m_scratch_limit = frame_build_cap(*m_ctx);
            return false;
        }
        ++first;
    }
    count = 0; // The last chunk failed alone: nothing else to build this frame.
    return true;
}

// Not built, as when its own buffers cannot be allocated: dropped from the scene and counted,
// or, for a cool-down rebuild, left hot as it was.
void SceneAccel::fail_alone(const PendingBuild& p) {
    if (p.g->cooling_from)
        cool_down_failed(p.c, *p.g);
    else
        fail_chunk(p.c, *p.g, p.staging + p.sizes.accelerationStructureSize);
}

} // namespace vx::render
