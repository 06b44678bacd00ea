#include "render/scene_accel.h"

#include <algorithm>

#include "render/scene_accel_budget.h"
#include "world/base/assert.h"

namespace vx::render {

// A refit keeps the tree built for the old geometry, whose boxes loosen as edits pile up, so
// after max_refits refits in a row a chunk's next update is a rebuild (SceneAccelCreateInfo; default 8). On the
// H200 (`vx bench render --scene seed --sections geometry`, every chunk toggling a block per
// burst, slots kept stable by SlotMap) the traced frame was 1.07x the rebuilt one's after 1
// refit, 1.47x after 10 and 2.7x after 100, while a refit cost 75 us per chunk against 92.5 us
// rebuilt (1024 at once; 64 at once: 2.6 against 5.7 ms, docs/benchmarks.md): 8 keeps the loss
// under about 1.4x for an eighth more update cost.

template <class G> static void mark_dirty(G& g, int slice) {
    VX_ASSERT(slice >= 0 && slice < world::kSliceCount);
    g.dirty.set(size_t(slice));
}

SceneAccel::SceneAccel(Context& ctx, const SceneAccelCreateInfo& info)
    : m_ctx(&ctx), m_staging(ctx), m_info(info), m_staging_limit(frame_build_cap(ctx)),
      m_scratch_limit(frame_build_cap(ctx)) {}

SceneAccel::~SceneAccel() {
    bool pools = false;
    for (const CompactionQueries& q : m_queries)
        pools |= q.pool != VK_NULL_HANDLE;
    if (!pools)
        return;
    m_ctx->wait_idle(); // Query pools have no retire list: destroy them once the GPU is idle.
    for (CompactionQueries& q : m_queries)
        if (q.pool)
            vkDestroyQueryPool(m_ctx->device(), q.pool, nullptr);
}

// `ids`: the blocks of the chunk's quads.
ChunkTraits chunk_traits(std::span<const world::BlockId> ids, const world::BlockRegistry& registry) {
    ChunkTraits t;
    t.opaque = std::all_of(ids.begin(), ids.end(), [&](world::BlockId id) { return registry.is_opaque(id); });
    return t;
}

void SceneAccel::set_chunk(world::LodCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices,
                           ChunkTraits traits) {
    if (mesh.empty()) {
        remove_chunk(c);
        return;
    }
    VX_ASSERT(world::valid_lod_level(c.level));
    auto [it, inserted] = m_chunks.try_emplace(c);
    ChunkGpu& g = it->second;
    g.level = uint8_t(c.level);
    apply_mesh(c, g, inserted, mesh, changed_slices, traits);
    queue(c, g);
    retally(g);
}

void SceneAccel::apply_mesh(world::LodCoord c, ChunkGpu& g, bool inserted, const world::ChunkMesh& mesh,
                            std::span<const int> changed_slices, ChunkTraits traits) {
    const bool fresh = inserted || g.failed;
    const uint64_t hash = mesh_hash(mesh);
    // A refit keeps the build's geometry flags (Vulkan spec): a chunk that gains or loses its
    // last transparent block is rebuilt.
    const bool flags_changed = !fresh && g.opaque != traits.opaque;
    g.opaque = traits.opaque;
    if (!fresh && hash == g.hash && !flags_changed) {
        // The same mesh again (Renderer::render(scene) re-sends every chunk), or again after a
        // batch of edits, each call naming its own slices: a pending refit uploads them all.
        if (g.pending == Pending::Refit)
            for (int s : changed_slices)
                mark_dirty(g, s);
        return;
    }
    g.cooling_from.reset(); // The new mesh decides how it is built.
    g.hash = hash;
    g.quad_count = mesh.quad_count();
    g.failed = false;
    g.mesh = mesh;
    const bool edit = !fresh && !changed_slices.empty();
    if (m_info.allow_refit && (edit || g.hot)) {
        g.last_edit_frame = m_frame;
        m_hot_queue.emplace_back(c, m_frame);
        // A cold BLAS has neither spare slots nor ALLOW_UPDATE: its first edit rebuilds it hot.
        const bool refit = g.hot && !flags_changed && g.blas.valid() && g.pending != Pending::Build && g.layout.fits(mesh) &&
                           g.refits_since_build < m_info.max_refits;
        g.hot = true;
        if (refit) {
            g.pending = Pending::Refit;
            if (changed_slices.empty())
                g.dirty.set();
            for (int s : changed_slices)
                mark_dirty(g, s);
            return;
        }
        g.layout = SlotLayout::for_mesh(mesh);
    } else {
        g.hot = false;
        g.layout = SlotLayout::exact(mesh);
    }
    g.pending = Pending::Build;
    g.dirty.set();
}

void SceneAccel::remove_chunk(world::LodCoord c) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end())
        return;
    forget(it->second);
    m_chunks.erase(it);
}

void SceneAccel::clear() {
    m_chunks.clear();
    m_instances.clear();
    m_pending.clear();
    m_hot_queue.clear();
    m_total = {};
    m_level_bytes.fill(0);
}

void SceneAccel::retain_only(const std::unordered_set<world::LodCoord, world::LodCoordHash>& keep) {
    for (auto it = m_chunks.begin(); it != m_chunks.end();) {
        if (keep.count(it->first)) {
            ++it;
            continue;
        }
        forget(it->second);
        it = m_chunks.erase(it);
    }
}

void SceneAccel::queue(world::LodCoord c, ChunkGpu& g) {
    if (g.pending == Pending::None || g.queued)
        return;
    g.queued = true;
    m_pending.push_back(c);
}

void SceneAccel::retally(ChunkGpu& g) {
    ChunkGpu::Tally t;
    t.blas = g.blas.size();
    t.vertices = g.vertices.size();
    t.quads = g.quads.size();
    if (g.blas.valid()) {
        t.quad_count = g.quad_count;
        t.triangles = g.layout.triangle_count();
    }
    t.hot = g.hot;
    t.failed = g.failed;
    ChunkGpu::Tally& o = g.counted;
    m_level_bytes[g.level] += (t.blas + t.vertices + t.quads) - (o.blas + o.vertices + o.quads);
    m_total.blas += t.blas - o.blas;
    m_total.vertices += t.vertices - o.vertices;
    m_total.quads += t.quads - o.quads;
    m_total.quad_count += t.quad_count - o.quad_count;
    m_total.triangles += t.triangles - o.triangles;
    m_total.hot += t.hot - o.hot;
    m_total.failed += t.failed - o.failed;
    o = t;
}

void SceneAccel::sync_instance(world::LodCoord c, ChunkGpu& g) {
    if (!g.blas.valid()) {
        drop_instance(g);
        return;
    }
    // c's level scales its instance.
    const DrawChunk d{c, g.quads.address(), g.layout.total, g.opaque};
    if (g.instance == TlasInstances::kNone)
        g.instance = m_instances.add(d, g.blas.address());
    else
        m_instances.update(g.instance, d, g.blas.address());
}

void SceneAccel::drop_instance(ChunkGpu& g) {
    if (g.instance == TlasInstances::kNone)
        return;
    if (const std::optional<world::LodCoord> moved = m_instances.remove(g.instance))
        m_chunks.at(*moved).instance = g.instance;
    g.instance = TlasInstances::kNone;
}

void SceneAccel::forget(ChunkGpu& g) {
    drop_instance(g);
    // Unsigned sums: subtracting the chunk's share wraps back exactly.
    m_level_bytes[g.level] -= g.counted.blas + g.counted.vertices + g.counted.quads;
    m_total.blas -= g.counted.blas;
    m_total.vertices -= g.counted.vertices;
    m_total.quads -= g.counted.quads;
    m_total.quad_count -= g.counted.quad_count;
    m_total.triangles -= g.counted.triangles;
    m_total.hot -= g.counted.hot;
    m_total.failed -= g.counted.failed;
    g.counted = {};
}

bool SceneAccel::record_tlas_build(VkCommandBuffer cmd, world::BlockPos camera_block) {
    // One barrier between all BLAS builds (and compaction copies) and what reads them: the
    // compacted-size queries and the TLAS build.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                   VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
    record_compaction_queries(cmd);
    if (!record_tlas(cmd, camera_block))
        return false;
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                   VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    count_memory();
    return true;
}

} // namespace vx::render
