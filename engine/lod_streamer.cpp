#include "engine/lod_streamer.h"

#include <algorithm>
#include <cmath>

#include "engine/box_difference.h"
#include "world/base/assert.h"
#include "world/base/log.h"

namespace vx::engine {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

namespace {
// Swaps and checks done per update() whatever the budget says, so the cut keeps moving on a
// machine too busy to leave time (each is a few hash lookups; a swap is 9 sink calls).
constexpr int kMinSteps = 64;
// Chunks drawn per update by the queue (refinements and coarsenings; roots coming into view are
// drawn whatever the count): each is a BLAS build in the next frame (30-50 us of recording on the
// H200 host), so a chunk crossing's swaps spread over a few frames instead of spiking one (a swap
// is atomic, so a refine of 8 may pass the count by 7). Flying at 100 blocks/s needs about 14 a
// frame on average (sandbox defaults, 4,096 blocks).
constexpr int kMaxDraws = 32;
// Coarse chunks whose data is requested per update whatever the budget (a request is a job or
// two; a box slab of a level is hundreds, spread over frames).
constexpr int kMinRequests = 32;
} // namespace

LodStreamer::LodStreamer(const ChunkGenerator& generator, ChunkStore* store, LodMeshSink& downstream,
                         const LodViewSettings& settings, const BlockRegistry& registry)
    : m_generator(generator), m_store(store), m_down(downstream), m_settings(settings), m_registry(registry) {
    if (m_store && m_store->supports_lod()) { // Before any job: the store is still this thread's.
        Result<std::vector<LodCoord>> stale = m_store->list_lod_dirty();
        if (!stale)
            VX_LOG_WARN("listing stale coarse chunks failed (%s): stored ones are used as they are",
                        stale.error().c_str());
        else if (!stale->empty())
            m_stale = std::make_shared<const LodDirtySet>(stale->begin(), stale->end());
    }
}

LodStreamer::~LodStreamer() = default;

void LodStreamer::attach(JobSystem& jobs, const World& blocks) {
    m_jobs = &jobs;
    m_blocks = &blocks;
}

// ---- The view: boxes, kept chunks, roots ---------------------------------------------------

void LodStreamer::move_view(const glm::dvec3& viewer) {
    const ChunkCoord c0 = chunk_of(BlockPos(int64_t(std::floor(viewer.x)), int64_t(std::floor(viewer.y)),
                                            int64_t(std::floor(viewer.z))));
    if (m_view && m_view->center(0) == c0)
        return;
    // Built at the centre of the viewer's chunk: the cut changes only when the viewer changes
    // chunk (distances are then off by at most half a chunk, within the view distance's slack).
    const BlockPos o = chunk_origin(c0);
    const glm::dvec3 centre = glm::dvec3(o) + glm::dvec3(kChunkSize * 0.5);
    std::optional<LodView> old = std::move(m_view);
    m_view.emplace(centre, m_settings);
    const LodView& v = *m_view;
    const int top = v.top_level();
    const bool first = !old;
    // Coarse data: each level's box, by what it gained and lost.
    for (int k = 1; k <= top; ++k) {
        const ChunkCoord a = v.center(k), b = first ? a : old->center(k);
        if (!first && a == b)
            continue;
        for_each_in_difference(a, b, first, v.half_width(k), v.half_height(k),
                               [&](ChunkCoord c) { keep({k, c}); });
        if (!first)
            for_each_in_difference(b, a, false, v.half_width(k), v.half_height(k),
                                   [&](ChunkCoord c) { m_to_release.push_back({k, c}); });
    }
    // Whether a chunk refines depends on the finer box: the parents of what entered or left it
    // are looked at again.
    for (int k = 0; k < top; ++k) {
        const ChunkCoord a = v.center(k), b = first ? a : old->center(k);
        if (!first && a == b)
            continue;
        auto parent = [&](ChunkCoord c) { enqueue(lod_parent({k, c})); };
        for_each_in_difference(a, b, first, v.half_width(k), v.half_height(k), parent);
        if (!first)
            for_each_in_difference(b, a, false, v.half_width(k), v.half_height(k), parent);
    }
    std::vector<LodCoord> roots;
    v.roots(roots);
    std::unordered_set<LodCoord, LodCoordHash> now(roots.begin(), roots.end());
    std::vector<LodCoord> changed;
    for (LodCoord r : roots)
        if (!m_roots.contains(r))
            changed.push_back(r); // Came into view: drawn at once when ready (kept, so usually).
    for (LodCoord r : m_roots)
        if (!now.contains(r))
            changed.push_back(r); // Left it: what is drawn under it goes at once.
    m_roots = std::move(now);
    for (LodCoord r : changed) // Outside the draw budget: a root waiting in the queue is a hole.
        process(r);
    m_holes_dirty = true;
}

void LodStreamer::keep(LodCoord c) {
    auto [it, inserted] = m_coarse.try_emplace(c);
    it->second.kept = true;
    if (inserted) { // Requested in update(), within the budget: a box slab is hundreds of jobs.
        ++m_metrics.kept[size_t(c.level)];
        m_to_request.push_back(c);
    }
}

void LodStreamer::release(LodCoord c) {
    auto it = m_coarse.find(c);
    if (it == m_coarse.end())
        return;
    Node& n = it->second;
    n.kept = false;
    if (drawn(c))
        return; // Dropped when undrawn (undraw()).
    if (n.data == Data::Requested && n.submitted) {
        m_jobs->cancel(lod_job_key(c, JobKind::Load));
        m_jobs->cancel(lod_job_key(c, JobKind::Generate));
        --m_metrics.pending_data;
    }
    if (n.mesh_pending) {
        m_jobs->cancel(lod_job_key(c, JobKind::Mesh));
        --m_metrics.pending_meshes;
    }
    if (n.data == Data::Present)
        m_metrics.block_bytes[size_t(c.level)] -= n.chunk.memory_bytes();
    --m_metrics.kept[size_t(c.level)];
    m_coarse.erase(it);
}

// ---- Coarse data and meshes ----------------------------------------------------------------

void LodStreamer::request_data(LodCoord c, Node& n) {
    n.data = Data::Requested;
    n.submitted = true;
    ++m_metrics.pending_data;
    if (m_stale && m_stale->contains(c)) {
        std::unique_ptr<const LodOverlay> overlay = edited_under(c);
        const bool save = !overlay && !m_marked_here.contains(c); // Nothing unsaved in it.
        m_batch.push_back(
            std::make_unique<LodDeriveJob>(events(), c, *m_store, m_generator, m_registry, m_stale, save,
                                           std::move(overlay)));
        return;
    }
    auto generate = std::make_unique<LodGenerateJob>(events(), c, m_generator, m_registry, m_viewer);
    if (m_store && m_store->supports_lod())
        m_batch.push_back(std::make_unique<LodLoadJob>(events(), c, *m_store, m_generator, m_registry,
                                                       std::move(generate),
                                                       edited_under(c))); // Read only if its record is damaged.
    else
        m_batch.push_back(std::move(generate));
}

void LodStreamer::request_mesh(LodCoord c, Node& n) {
    if (!n.mesh_pending)
        ++m_metrics.pending_meshes;
    VX_ASSERT(n.data == Data::Present);
    n.mesh_pending = true;
    n.mesh_stale = false;
    m_batch.push_back(std::make_unique<LodMeshJob>(events(), c, n.chunk, m_registry, m_viewer));
}

void LodStreamer::on_lod_data(LodCoord c, std::optional<Chunk> chunk, const std::string& error) {
    auto it = m_coarse.find(c);
    if (it == m_coarse.end() || it->second.data != Data::Requested)
        return; // Released meanwhile.
    Node& n = it->second;
    --m_metrics.pending_data;
    if (n.reload_on_arrival) { // Made stale while this load ran: load it again.
        n.reload_on_arrival = false;
        request_data(c, n);
        return;
    }
    if (!chunk) {
        // Nothing invented: the chunk above (or a hole, for a root) stays until a retry works.
        n.data = Data::Failed;
        ++m_metrics.data_failures;
        const int doublings = std::min<int>(n.failures, 6);
        n.failures = uint8_t(std::min<int>(n.failures + 1, 255));
        const double wait_s = std::min(60.0, double(1 << doublings));
        n.retry_at = m_last_now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait_s));
        m_retry.emplace_back(c, n.retry_at);
        m_holes_dirty = true; // A root's hole is now a failed one: settled() compares the counts.
        if (n.failures == 1)
            VX_LOG_WARN("coarse chunk %d:%d,%d,%d not made (%s); retrying in %.0f s", c.level, c.chunk.x, c.chunk.y,
                        c.chunk.z, error.c_str(), wait_s);
        return;
    }
    n.data = Data::Present;
    n.failures = 0;
    n.chunk = std::move(*chunk);
    if (std::exchange(n.merge_children, false))
        merge_children(c, n);
    m_metrics.block_bytes[size_t(c.level)] += n.chunk.memory_bytes();
    if (n.chunk.is_empty()) { // Air: nothing to mesh, nothing to draw.
        const bool was_ready = n.meshed; // Reloaded (reload()): drawn, maybe.
        n.mesh.reset();
        n.meshed = true;
        if (drawn(c))
            m_down.on_lod_mesh(c, empty_mesh());
        else if (!was_ready)
            became_ready(c);
        return;
    }
    request_mesh(c, n);
}

void LodStreamer::on_lod_meshed(LodCoord c, ChunkMesh mesh) {
    auto it = m_coarse.find(c);
    if (it == m_coarse.end() || !it->second.mesh_pending)
        return;
    Node& n = it->second;
    n.mesh_pending = false;
    --m_metrics.pending_meshes;
    if (n.mesh_stale) { // An edit arrived while it ran.
        request_mesh(c, n);
        return;
    }
    const bool was_ready = n.meshed;
    n.mesh = mesh.empty() ? nullptr : std::make_unique<ChunkMesh>(std::move(mesh));
    n.meshed = true;
    if (drawn(c))
        m_down.on_lod_mesh(c, n.mesh ? *n.mesh : empty_mesh());
    else if (!was_ready)
        became_ready(c);
}

void LodStreamer::on_lod_saved(LodCoord c, const std::string& error) {
    if (!error.empty())
        VX_LOG_ERROR("saving coarse chunk %d:%d,%d,%d failed: %s", c.level, c.chunk.x, c.chunk.y, c.chunk.z,
                     error.c_str());
}

void LodStreamer::retry_failed(Clock::time_point now) {
    std::erase_if(m_retry, [&](const std::pair<LodCoord, Clock::time_point>& e) {
        auto it = m_coarse.find(e.first);
        if (it == m_coarse.end() || it->second.data != Data::Failed || it->second.retry_at != e.second)
            return true;
        if (now < e.second)
            return false;
        request_data(e.first, it->second);
        m_holes_dirty = true; // No longer failed: being made again.
        return true;
    });
}

// ---- Level 0, from the ChunkStreamer ---------------------------------------------------------

void LodStreamer::on_mesh(ChunkCoord c, const ChunkMesh& mesh, std::span<const int> changed_slices) {
    const bool fresh = m_fine.insert_or_assign(c, &mesh).second;
    const LodCoord l{0, c};
    if (drawn(l))
        m_down.on_mesh(c, mesh, changed_slices);
    else if (fresh)
        became_ready(l);
}

void LodStreamer::on_unload(ChunkCoord c) {
    m_fine.erase(c);
    const LodCoord l{0, c};
    if (!drawn(l))
        return;
    // Its mesh is going: the nearest ready ancestor takes its place (boxes nest, so normally the
    // parent); with none, the chunk leaves a hole until one is ready.
    const int top = top_level();
    for (LodCoord a = l; a.level < top;) {
        a = lod_parent(a);
        if (ready(a)) {
            clear_below(a);
            draw(a);
            ++m_metrics.swaps;
            return;
        }
    }
    undraw(l);
    ++m_metrics.forced_drops;
}

// ---- The drawn cut ---------------------------------------------------------------------------

bool LodStreamer::ready(LodCoord c) const {
    if (c.level == 0)
        return m_fine.contains(c.chunk);
    auto it = m_coarse.find(c);
    return it != m_coarse.end() && it->second.meshed;
}

const ChunkMesh* LodStreamer::mesh_of(LodCoord c) const {
    if (c.level == 0) {
        auto it = m_fine.find(c.chunk);
        return it == m_fine.end() ? nullptr : it->second;
    }
    auto it = m_coarse.find(c);
    if (it == m_coarse.end() || !it->second.meshed)
        return nullptr;
    return it->second.mesh ? it->second.mesh.get() : &empty_mesh();
}

int LodStreamer::below(LodCoord c) const {
    auto it = m_below.find(c);
    return it == m_below.end() ? 0 : it->second;
}

bool LodStreamer::under_root(LodCoord c) const {
    const int top = top_level();
    return c.level <= top && m_roots.contains(lod_ancestor(c, top));
}

bool LodStreamer::target_leaf(LodCoord c) const {
    if (m_view->refines(c))
        return false;
    return c.level == top_level() ? m_roots.contains(c) : m_view->refines(lod_parent(c)) && under_root(c);
}

void LodStreamer::enqueue(LodCoord c) {
    if (m_queued.insert(c).second)
        m_queue.push_back(c);
}

void LodStreamer::became_ready(LodCoord c) {
    enqueue(c); // A root or a coarsening target may draw now...
    if (c.level < top_level())
        enqueue(lod_parent(c)); // ... or the parent's refinement may be complete.
}

void LodStreamer::draw(LodCoord c) {
    ++m_draws;
    m_drawn.insert(c);
    for (LodCoord a = c; a.level < top_level();) {
        a = lod_parent(a);
        ++m_below[a];
    }
    ++m_metrics.drawn[size_t(c.level)];
    m_holes_dirty = true;
    if (c.level == 0)
        m_down.on_mesh(c.chunk, *m_fine.at(c.chunk), {});
    else
        m_down.on_lod_mesh(c, *mesh_of(c));
}

void LodStreamer::undraw(LodCoord c) {
    m_drawn.erase(c);
    for (LodCoord a = c; a.level < top_level();) {
        a = lod_parent(a);
        auto it = m_below.find(a);
        if (--it->second == 0)
            m_below.erase(it);
    }
    --m_metrics.drawn[size_t(c.level)];
    m_holes_dirty = true;
    if (c.level == 0) {
        m_down.on_unload(c.chunk);
        return;
    }
    m_down.on_lod_unload(c);
    auto it = m_coarse.find(c);
    if (it != m_coarse.end() && !it->second.kept)
        release(c); // Left its box while drawn: its data goes now.
}

void LodStreamer::clear_below(LodCoord c) {
    if (c.level == 0 || below(c) == 0)
        return;
    for (int i = 0; i < kLodChildren; ++i) {
        const LodCoord ch = lod_child(c, i);
        if (drawn(ch))
            undraw(ch);
        else
            clear_below(ch);
    }
}

void LodStreamer::process(LodCoord c) {
    const int top = top_level();
    if (!under_root(c)) { // Beyond the view (or above the top level): nothing drawn here.
        if (c.level <= top && drawn(c))
            undraw(c);
        else if (c.level <= top)
            clear_below(c);
        return;
    }
    if (drawn(c)) {
        if (m_view->refines(c)) {
            for (int i = 0; i < kLodChildren; ++i)
                if (!ready(lod_child(c, i)))
                    return; // became_ready() of the last child brings c back.
            undraw(c);
            for (int i = 0; i < kLodChildren; ++i)
                draw(lod_child(c, i));
            for (int i = 0; i < kLodChildren; ++i)
                enqueue(lod_child(c, i)); // They may refine further.
            ++m_metrics.swaps;
            return;
        }
        LodCoord a = c; // The target chunk covering c.
        while (a.level < top && !m_view->refines(lod_parent(a)))
            a = lod_parent(a);
        if (a != c)
            enqueue(a);
        return;
    }
    for (LodCoord a = c; a.level < top;) {
        a = lod_parent(a);
        if (drawn(a))
            return; // Covered from above; a's own processing refines it.
    }
    if (below(c) > 0) {
        if (target_leaf(c) && ready(c)) { // Coarsen: everything under c goes in this update.
            clear_below(c);
            draw(c);
            ++m_metrics.swaps;
        }
        return;
    }
    if (c.level == top && ready(c)) { // An uncovered root: coarse first, refined from there.
        draw(c);
        enqueue(c);
    }
}

void LodStreamer::count_holes() {
    uint32_t holes = 0, failed = 0;
    for (LodCoord r : m_roots) {
        if (drawn(r) || below(r) != 0)
            continue;
        ++holes;
        auto it = m_coarse.find(r);
        failed += uint32_t(it != m_coarse.end() && it->second.data == Data::Failed);
    }
    m_metrics.holes = holes;
    m_metrics.failed_holes = failed;
    m_metrics.root_chunks = uint32_t(m_roots.size());
    m_holes_dirty = false;
}

void LodStreamer::update(const glm::dvec3& viewer, Clock::time_point now, Clock::time_point deadline) {
    m_viewer = viewer;
    m_last_now = now;
    move_view(viewer);
    retry_failed(now);
    apply_edits();
    m_draws = 0;
    for (int steps = 0; !m_queue.empty(); ++steps) {
        if (steps >= kMinSteps && Clock::now() >= deadline)
            break;
        if (m_draws >= kMaxDraws)
            break; // The rest next frame: each draw is a BLAS build in the next frame.
        const LodCoord c = m_queue.front();
        m_queue.pop_front();
        m_queued.erase(c);
        process(c);
    }
    // Chunks that left their box: their data and meshes go within what is left of the budget (a
    // slab is hundreds of frees and cancels); one back in its box since stays.
    for (int n = 0; !m_to_release.empty(); ++n) {
        if (n >= kMinRequests && Clock::now() >= deadline)
            break;
        const LodCoord c = m_to_release.front();
        m_to_release.pop_front();
        if (!m_view->in_box(c))
            release(c);
    }
    // New box chunks' data, nearest level first as they were listed, within what is left.
    for (int n = 0; !m_to_request.empty(); ++n) {
        if (n >= kMinRequests && Clock::now() >= deadline)
            break;
        const LodCoord c = m_to_request.front();
        m_to_request.pop_front();
        auto it = m_coarse.find(c);
        if (it != m_coarse.end() && it->second.data == Data::Requested && !it->second.submitted)
            request_data(c, it->second);
    }
    if (!m_batch.empty())
        m_jobs->submit_batch(std::exchange(m_batch, {}));
    if (m_holes_dirty)
        count_holes();
    m_metrics.top_level = top_level();
}

bool LodStreamer::settled() const {
    return m_view && m_queue.empty() && m_batch.empty() && m_to_request.empty() && m_to_release.empty() &&
           m_edited.empty() && m_metrics.holes == m_metrics.failed_holes && m_metrics.pending_data == 0 &&
           m_metrics.pending_meshes == 0;
}

LodMetrics LodStreamer::metrics() const { return m_metrics; }

const Chunk* LodStreamer::coarse_chunk(LodCoord c) const {
    auto it = m_coarse.find(c);
    return it != m_coarse.end() && it->second.data == Data::Present ? &it->second.chunk : nullptr;
}

} // namespace vx::engine
