// SceneAccel: the life of cold chunks after their build. A cold BLAS is built with
// ALLOW_COMPACTION; its compacted size is queried right after the build, read back when the frame
// slot comes round again (its fence has signalled by then, so the read never waits), and the BLAS
// is copied into a buffer of that size (VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR); the
// original retires with the frame that copies it. Also: hot chunks cooling down, and the memory
// tally.
#include <algorithm>

#include "render/scene_accel.h"
#include "world/base/log.h"

namespace vx::render {

void SceneAccel::record_compactions(VkCommandBuffer cmd) {
    CompactionQueries& q = m_queries[m_ctx->frame_slot()];
    if (q.chunks.empty())
        return;
    const uint32_t n = uint32_t(q.chunks.size());
    std::vector<uint64_t> sizes(n);
    // The queries were written by this slot's previous frame, which begin_frame has waited for.
    // A device lost after begin_frame's wait shows here first: no compaction this frame.
    if (!m_ctx->check_device(vkGetQueryPoolResults(m_ctx->device(), q.pool, 0, n, n * sizeof(uint64_t), sizes.data(),
                                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
                             "vkGetQueryPoolResults (compaction)")) {
        q.chunks.clear();
        return;
    }
    for (uint32_t i = 0; i < n; ++i) {
        const auto [c, serial] = q.chunks[i];
        auto it = m_chunks.find(c);
        if (it == m_chunks.end())
            continue; // Removed since.
        ChunkGpu& g = it->second;
        // Rebuilt (or being rebuilt, or turned hot) since: the query is about a BLAS now gone.
        if (g.build_serial != serial || g.hot || g.pending != Pending::None || !g.blas.valid() || sizes[i] == 0)
            continue;
        char name[96];
        std::snprintf(name, sizeof name, "BLAS chunk %d,%d,%d L%d (compacted)", c.chunk.x, c.chunk.y, c.chunk.z,
                      c.level);
        AccelStruct compact =
            AccelStruct::create(*m_ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, sizes[i], name, true);
        if (!compact.valid())
            continue; // Out of memory: the uncompacted BLAS stays (still correct, only larger).
        VkCopyAccelerationStructureInfoKHR ci{VK_STRUCTURE_TYPE_COPY_ACCELERATION_STRUCTURE_INFO_KHR};
        ci.src = g.blas.handle();
        ci.dst = compact.handle();
        ci.mode = VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR;
        vkCmdCopyAccelerationStructureKHR(cmd, &ci);
        g.blas = std::move(compact); // The original retires with this frame, after the copy read it.
        sync_instance(c, g);
        retally(g);
        ++m_stats.blas_compactions;
    }
    q.chunks.clear();
}

void SceneAccel::record_compaction_queries(VkCommandBuffer cmd) {
    if (m_built_cold.empty())
        return;
    CompactionQueries& q = m_queries[m_ctx->frame_slot()];
    VX_ASSERT(q.chunks.empty()); // record_compactions() consumed this slot's last queries.
    const uint32_t n = uint32_t(m_built_cold.size());
    if (q.capacity < n) {
        // The pool is idle: its last frame has completed and its results were read this frame.
        if (q.pool)
            vkDestroyQueryPool(m_ctx->device(), q.pool, nullptr);
        q.capacity = std::max({n, 2 * q.capacity, 64u});
        VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        ci.queryType = VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR;
        ci.queryCount = q.capacity;
        q.pool = VK_NULL_HANDLE;
        const char* name = "BLAS compacted sizes";
        const VkResult r = m_ctx->allocation_injected(name) ? VK_ERROR_OUT_OF_HOST_MEMORY // Test hook.
                                                            : vkCreateQueryPool(m_ctx->device(), &ci, nullptr, &q.pool);
        if (r != VK_SUCCESS) {
            // Out of memory (it aborted): compaction only saves memory, so these chunks keep
            // their build size and the frame goes on; a later build tries again.
            VX_LOG_WARN("renderer: no query pool for BLAS compaction (%s): %u chunks stay uncompacted",
                        vk_result_name(r), n);
            q.pool = VK_NULL_HANDLE;
            q.capacity = 0;
            m_built_cold.clear();
            return;
        }
        m_ctx->set_name(q.pool, VK_OBJECT_TYPE_QUERY_POOL, name);
    }
    std::vector<VkAccelerationStructureKHR> handles;
    handles.reserve(n);
    for (world::LodCoord c : m_built_cold) {
        const ChunkGpu& g = m_chunks.at(c); // Nothing removes chunks between the builds and here.
        handles.push_back(g.blas.handle());
        q.chunks.emplace_back(c, g.build_serial);
    }
    vkCmdResetQueryPool(cmd, q.pool, 0, n);
    vkCmdWriteAccelerationStructuresPropertiesKHR(cmd, n, handles.data(),
                                                  VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR, q.pool, 0);
    m_built_cold.clear();
}

void SceneAccel::demote_idle_hot_chunks() {
    // At most this many cold rebuilds a frame, so the chunks of one edit burst cool down over a
    // few frames instead of in one spike.
    // Hot chunks wait in m_hot_queue by the frame of their last edit, oldest first: a frame looks
    // only at those due (and stale entries), never at every chunk.
    constexpr uint32_t kMaxPerFrame = 64;
    uint32_t n = 0;
    for (size_t left = m_hot_queue.size(); left > 0 && n < kMaxPerFrame; --left) {
        const auto [c, frame] = m_hot_queue.front();
        if (m_frame - frame < m_info.hot_frames)
            break;
        m_hot_queue.pop_front();
        auto it = m_chunks.find(c);
        if (it == m_chunks.end())
            continue;
        ChunkGpu& g = it->second;
        if (!g.hot || g.last_edit_frame != frame)
            continue; // Cold already, or edited again since (a later entry).
        if (g.pending != Pending::None) {
            m_hot_queue.emplace_back(c, frame); // Being built: a later frame cools it down.
            continue;
        }
        g.cooling_from = std::make_unique<SlotLayout>(g.layout);
        g.hot = false;
        g.layout = SlotLayout::exact(g.mesh);
        g.pending = Pending::Build;
        g.dirty.set();
        queue(c, g);
        retally(g);
        ++n;
    }
}

void SceneAccel::count_memory() {
    // The chunks' shares are kept up to date as they change (retally): O(1) here.
    m_memory = {};
    m_memory.blas = m_total.blas;
    m_memory.vertices = m_total.vertices;
    m_memory.quads = m_total.quads;
    m_memory.quad_count = m_total.quad_count;
    m_stats.triangles = m_total.triangles;
    m_stats.hot_chunks = m_total.hot;
    m_stats.failed_chunks = m_total.failed;
    m_stats.level_instances = m_instances.level_counts();
    m_stats.level_gpu_bytes = m_level_bytes;
    for (const FrameData& f : m_frames)
        m_memory.tlas += f.tlas.size() + f.instances.size() + f.table.size();
    m_memory.scratch = m_scratch.size();
    m_memory.indices = m_indices.size();
}

} // namespace vx::render
