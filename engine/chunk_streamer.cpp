// ChunkStreamer: construction and shutdown, the viewer's update (what to request, unload or
// evict), edits, saves and queries. Its jobs' side is in chunk_streamer_jobs.cpp.
#include "engine/chunk_streamer.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <tuple>

#include "engine/box_difference.h"
#include "engine/cpu_time.h"
#include "engine/stream_jobs.h"
#include "world/base/log.h"
#include "world/coords.h"

namespace vx::engine {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

namespace {

int64_t distance2(ChunkCoord a, ChunkCoord b) {
    const glm::i64vec3 d = glm::i64vec3(a - b);
    return d.x * d.x + d.y * d.y + d.z * d.z;
}
} // namespace

ChunkStreamer::ChunkStreamer(const ChunkGenerator& generator, ChunkStore* store, MeshSink& sink,
                             const StreamingSettings& settings, const BlockRegistry& registry)
    : m_generator(generator), m_store(store), m_sink(sink), m_settings(settings), m_world(registry) {
    JobSystemCreateInfo info;
    info.worker_count = settings.worker_count;
    m_jobs = std::make_unique<JobSystem>(info);
    // Two rings (viewer and lookahead) plus the unload margin: room reserved up front so the hash
    // tables never rehash thousands of chunks in the middle of a frame.
    const int r = settings.view_radius + 2, rv = settings.view_radius_vertical + 2;
    const size_t expected = 3 * size_t(2 * r + 1) * size_t(2 * r + 1) * size_t(2 * rv + 1);
    m_chunks.reserve(expected);
    m_world.reserve_chunks(expected);
    m_mesh_candidates.reserve(expected / 4);
    m_ahead_candidates.reserve(expected / 4);
}

ChunkStreamer::~ChunkStreamer() {
    // Once: after a flush requested with nothing handed to the store since (the engine's
    // shutdown flushes first), another would only repeat it, and with the server away wait
    // another connect timeout for the same error.
    // Without threads (the OS refused them: JobSystem::start_error) nothing was loaded, so
    // nothing can be edited or unsaved, and no thread would run the flush.
    // A request whose flush is still queued is waited for: resetting the jobs would drop its
    // saves unrun, and the edits with them.
    if (m_store && m_jobs->start_error().empty()) {
        Status s;
        if (m_dirty_count > 0 || m_saves != m_saves_at_request)
            s = flush();
        else if (m_last_request != 0 && m_saves_done->state(m_last_request) == SaveState::Pending)
            s = wait_saved(m_last_request);
        if (!s)
            VX_LOG_ERROR("saving the world on shutdown failed: %s", s.error().c_str());
    }
    m_jobs.reset(); // Joins the workers before any state below goes away.
}

bool ChunkStreamer::near(ChunkCoord c, ChunkCoord center, int extra) const {
    const glm::ivec3 d = glm::abs(c - center);
    return std::max(d.x, d.z) <= m_settings.view_radius + extra && d.y <= m_settings.view_radius_vertical + extra;
}

bool ChunkStreamer::in_view(ChunkCoord c) const { return near(c, m_center, 0); }

bool ChunkStreamer::wants_mesh(ChunkCoord c) const { return near(c, m_center, 0) || near(c, m_lead, 0); }

bool ChunkStreamer::in_loaded_ring(ChunkCoord c) const { return near(c, m_center, 1) || near(c, m_lead, 1); }

bool ChunkStreamer::beyond_unload(ChunkCoord c) const {
    const int m = m_settings.unload_margin + 1;
    return !near(c, m_center, m) && !near(c, m_lead, m);
}

void ChunkStreamer::update(const glm::dvec3& position, const glm::dvec3& forward, Clock::time_point now) {
    update_viewer(position, forward, nullptr, now);
}

void ChunkStreamer::update(const glm::dvec3& position, const glm::dvec3& forward, const glm::dvec3& velocity,
                           Clock::time_point now) {
    update_viewer(position, forward, &velocity, now);
}

void ChunkStreamer::update_viewer(const glm::dvec3& given, const glm::dvec3& forward, const glm::dvec3* velocity,
                                  Clock::time_point now) {
    // Kept 2^17 blocks inside the world's edge (the facade refuses viewers beyond it): a box
    // reaching INT32_MAX chunks made the region walk's `x <= hi.x` always true, looping forever.
    // fmax first, so NaN becomes the low end rather than undefined in the int64 conversion.
    constexpr double kLo = double(world::kWorldMinBlock + world::kEdgeMarginBlocks);
    constexpr double kHi = double(world::kWorldMaxBlock - world::kEdgeMarginBlocks);
    const glm::dvec3 position(std::fmin(std::fmax(given.x, kLo), kHi), std::fmin(std::fmax(given.y, kLo), kHi),
                              std::fmin(std::fmax(given.z, kLo), kHi));
    const Clock::time_point t0 = Clock::now();
    const std::chrono::nanoseconds cpu0 = thread_cpu_time();
    // Work stops 5% short of the budget: the checks themselves and the bookkeeping after the
    // last one must fit too (measured on a quiet 16-core host, p99 sat on the budget otherwise).
    const Clock::time_point deadline = t0 + m_settings.frame_budget * 19 / 20;
    m_jobs->set_viewer({position, forward});
    if (!m_have_center || now < m_last_tick)
        m_last_tick = now; // Store ticks count from the first update (the caller's clock has any epoch).
    // Velocity from the last frames (exponentially smoothed), so meshes are ready where the
    // viewer is heading before it gets there.
    const double dt = std::chrono::duration<double>(now - m_prev_time).count();
    const glm::dvec3 step = position - m_prev_position;
    if (velocity)
        m_velocity = *velocity; // The game knows better than an estimate.
    else if (!m_have_center || dt <= 1e-4 || dt >= 1.0 || glm::length(step) > 2.0 * kChunkSize)
        m_velocity = glm::dvec3(0.0); // First frame, a stall or a teleport: no prediction.
    else
        m_velocity = 0.8 * m_velocity + 0.2 * step / dt;
    m_prev_position = position;
    m_prev_time = now;
    m_last_now = now;
    auto chunk_at = [](const glm::dvec3& p) {
        return chunk_of(BlockPos(int64_t(std::floor(p.x)), int64_t(std::floor(p.y)), int64_t(std::floor(p.z))));
    };
    const ChunkCoord center = chunk_at(position);
    // Never look further ahead than the view radius itself. A finite velocity times the
    // lookahead may overflow (1e308 blocks/s): then only its direction counts.
    glm::dvec3 ahead = m_velocity * m_settings.lookahead_s;
    const double reach = double(m_settings.view_radius * kChunkSize);
    const double length = glm::length(ahead);
    if (!std::isfinite(length))
        ahead = world::unit_direction(m_velocity) * reach;
    else if (length > reach)
        ahead *= reach / length;
    const ChunkCoord lead = chunk_at(position + ahead);
    if (!m_have_center || center != m_center || lead != m_lead) {
        const ChunkCoord old_center = m_center, old_lead = m_lead;
        const bool first = !m_have_center;
        m_center = center;
        m_lead = lead;
        m_have_center = true;
        refresh_region(old_center, old_lead, first, now);
    }
    // Completions get most of the budget, counted from the start of the frame (the request pass
    // above is part of it); what is left schedules new meshes.
    CompletionBudget budget;
    budget.min_count = 4; // Progress under any budget (the request pass may have used it all).
    budget.time = std::max(std::chrono::nanoseconds(0),
                           std::chrono::duration_cast<std::chrono::nanoseconds>(
                               t0 + m_settings.frame_budget * 7 / 10 - Clock::now()));
    m_jobs->process_completions(budget);
    retry_failed(now);
    poll_store_changes();
    // Meshes stop an eighth early: unloads, evictions and saves after them fit in the budget too.
    schedule_meshes(deadline - m_settings.frame_budget / 8);
    unload_far(now, deadline);
    enforce_memory_cap(deadline);
    save_dirty(now, false);
    if (m_store && now - m_last_tick >= std::chrono::duration<double>(m_settings.store_tick_s)) {
        m_last_tick = now;
        m_jobs->submit(std::make_unique<StoreSyncJob>(events(), *m_store));
    }
    m_last_update = Clock::now() - t0;
    m_last_update_cpu = thread_cpu_time() - cpu0;
}

void ChunkStreamer::refresh_region(ChunkCoord old_center, ChunkCoord old_lead, bool first, Clock::time_point now) {
    // Each box (around the viewer and around the lookahead point) visits only the chunks it gained
    // or lost: a one-chunk move is one slab, a teleport the whole box. That suffices because every
    // chunk of the loaded ring exists in m_chunks (requested or present) from the frame it enters
    // the ring until it leaves the ring, and chunks are only created inside it.
    const int r = m_settings.view_radius, rv = m_settings.view_radius_vertical;
    const int m = m_settings.unload_margin + 1;
    std::vector<std::unique_ptr<Job>> jobs;
    auto enter_ring = [&](ChunkCoord c) { // Requested again if it was dropped: no silent holes.
        if (!m_chunks.contains(c))
            jobs.push_back(request_data(c));
    };
    auto enter_view = [&](ChunkCoord c) { // Loaded chunks that now want a mesh.
        auto it = m_chunks.find(c);
        if (it != m_chunks.end() && it->second.data == Data::Present && !it->second.has_mesh)
            queue_mesh(c);
    };
    auto count_meshed = [&](ChunkCoord c, int sign) { // Keeps m_view_meshed relative to m_center.
        auto it = m_chunks.find(c);
        if (it != m_chunks.end() && it->second.has_mesh && !it->second.mesh_pending)
            m_view_meshed += size_t(sign); // Wraps back for -1: exact in unsigned arithmetic.
    };
    auto leave_ring = [&](ChunkCoord c) { // Memory-cap candidates.
        if (m_settings.memory_cap_bytes == 0 || in_loaded_ring(c))
            return;
        if (auto it = m_chunks.find(c); it != m_chunks.end())
            note_evictable(c, it->second);
    };
    auto leave_unload = [&](ChunkCoord c) {
        if (beyond_unload(c))
            note_left(c, now);
    };
    const ChunkCoord from[2] = {old_center, old_lead}, to[2] = {m_center, m_lead};
    for (int i = 0; i < 2; ++i) {
        if (!first && from[i] == to[i])
            continue;
        if (i == 1 && m_lead == m_center && (first || old_lead == old_center))
            continue; // The same box as the viewer's, done above.
        for_each_in_difference(to[i], from[i], first, r + 1, rv + 1, enter_ring);
        for_each_in_difference(to[i], from[i], first, r, rv, enter_view);
        if (i == 0)
            for_each_in_difference(to[i], from[i], first, r, rv, [&](ChunkCoord c) { count_meshed(c, 1); });
        if (first)
            continue;
        if (i == 0)
            for_each_in_difference(from[i], to[i], false, r, rv, [&](ChunkCoord c) { count_meshed(c, -1); });
        for_each_in_difference(from[i], to[i], false, r + 1, rv + 1, leave_ring);
        for_each_in_difference(from[i], to[i], false, r + m, rv + m, leave_unload);
    }
    if (!jobs.empty())
        m_jobs->submit_batch(std::move(jobs));
    m_evict_sorted = false; // Distances changed.
}

void ChunkStreamer::note_left(ChunkCoord c, Clock::time_point now) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end())
        return;
    // A chunk not loaded (its load or generation still queued, or failed) holds nothing to keep:
    // once it is a chunk past the unload radius it goes at once. Kept for the delay, its load
    // stayed ahead of the new view's in the FIFO I/O lane (4 teleports: 3277 loads of places
    // left). The chunk of slack keeps a viewer jittering on a border from cancelling its loads.
    const int slack = m_settings.unload_margin + 2;
    if (it->second.data != Data::Present && !near(c, m_center, slack) && !near(c, m_lead, slack)) {
        drop(c, it->second);
        ++m_unloaded;
        return;
    }
    // (Re)starts its unload delay; an older queue entry of the chunk goes stale.
    it->second.outside = true;
    it->second.outside_since = now;
    m_outside.push_back({c, now});
}

void ChunkStreamer::note_evictable(ChunkCoord c, ChunkState& s) {
    if (s.evict_listed)
        return;
    s.evict_listed = true;
    m_evict.push_back(c);
    m_evict_sorted = false;
    if (m_evict.size() <= 2 * m_chunks.size() + 64)
        return;
    // Entries of dropped chunks (and duplicates left by their reloaded successors) pile up while
    // under the cap: compact, amortized over as many pushes as there are chunks.
    auto less = [](ChunkCoord a, ChunkCoord b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(m_evict.begin(), m_evict.end(), less);
    m_evict.erase(std::unique(m_evict.begin(), m_evict.end()), m_evict.end());
    std::erase_if(m_evict, [this](ChunkCoord q) {
        auto it = m_chunks.find(q);
        return it == m_chunks.end() || !it->second.evict_listed;
    });
}

Status ChunkStreamer::set_block(BlockPos p, BlockId id) {
    if (!in_world(p))
        return Error{"position outside the world"};
    const ChunkCoord c = chunk_of(p);
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Present)
        return Error{"chunk " + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) +
                     " is not loaded"};
    const EditResult r = m_edits.apply(m_world, p, id, [this](ChunkCoord q) -> ChunkMesh* {
        auto s = m_chunks.find(q);
        if (s == m_chunks.end())
            return nullptr;
        if (s->second.mesh_pending)
            s->second.mesh_stale = true; // Its snapshot predates this edit.
        ChunkState& q_state = s->second;
        if (!q_state.has_mesh || q_state.mesh_pending)
            return nullptr;
        if (!q_state.mesh) // An empty mesh gains its first quads: give it storage.
            q_state.mesh = std::make_unique<ChunkMesh>();
        return q_state.mesh.get();
    });
    if (!r.changed)
        return {};
    ChunkState& s = it->second;
    m_block_bytes -= s.bytes;
    s.bytes = m_world.find_chunk(c)->memory_bytes();
    m_block_bytes += s.bytes;
    if (m_store && !m_store->read_only())
        s.edits.push_back({local_of(p), id});
    if (m_store && !m_store->read_only() && !s.dirty) {
        s.dirty = true;
        ++m_dirty_count;
        s.dirty_since = m_last_now; // The caller's clock, as save_dirty's `now`.
        m_dirty.push_back({c, s.dirty_since});
    }
    for (const SliceUpdate& u : r.updates)
        m_sink.on_mesh(u.chunk, *m_chunks.at(u.chunk).mesh, std::span<const int>(u.slices.data(), size_t(u.count)));
    m_sink.on_block_edited(p);
    return {};
}

void ChunkStreamer::unload_far(Clock::time_point now, Clock::time_point deadline) {
    // Only chunks that left the unload radius are visited, oldest first (refresh_region queued
    // them), so the cost follows what moved, not how many chunks are loaded. Drops stay within
    // the frame's budget, but at least kMinDrops happen a frame so memory cannot grow without
    // bound while the budget is spent elsewhere.
    constexpr int kMinDrops = 32;
    const auto delay = std::chrono::duration<double>(m_settings.unload_delay_s);
    int dropped = 0;
    while (!m_outside.empty()) {
        const Since e = m_outside.front();
        auto it = m_chunks.find(e.chunk);
        if (it == m_chunks.end() || !it->second.outside || it->second.outside_since != e.time) {
            m_outside.pop_front(); // Dropped, or left again later (a newer entry).
            continue;
        }
        ChunkState& s = it->second;
        if (!beyond_unload(e.chunk)) { // Came back in: the hysteresis kept it.
            s.outside = false;
            m_outside.pop_front();
            continue;
        }
        if (now - e.time < delay)
            return; // Every later entry left later.
        if (dropped >= kMinDrops && Clock::now() >= deadline)
            return;
        m_outside.pop_front();
        drop(e.chunk, s);
        ++m_unloaded;
        ++dropped;
    }
}

void ChunkStreamer::drop(ChunkCoord c, ChunkState& s) {
    // Only jobs that can be in flight are cancelled (each cancel takes the job system's lock):
    // a present chunk's load or generation has completed; a mesh job runs only while pending.
    if (s.data == Data::Requested) {
        m_jobs->cancel({c, JobKind::Load});
        m_jobs->cancel({c, JobKind::Generate});
    }
    if (s.mesh_pending)
        m_jobs->cancel({c, JobKind::Mesh});
    if (s.data == Data::Present) {
        Chunk* chunk = m_world.find_chunk(c);
        if (s.dirty && m_store) { // Saved before it is dropped: the job owns the data now.
            m_jobs->submit(
                std::make_unique<SaveJob>(events(), c, std::move(*chunk), *m_store, std::move(s.edits), s.store_version));
            ++m_saves;
        }
        m_block_bytes -= s.bytes;
        m_world.remove_chunk(c);
    }
    if (s.data == Data::Failed)
        remesh_around(c); // Its neighbours were meshed against air: not what it will hold when back.
    const bool had_data = s.data == Data::Present;
    // Not has_mesh: a mesh outdated by a neighbour's change (remesh_around) is still drawn, and a
    // chunk beyond the meshing ring never gets the new one. Left in the sink it stayed drawn after
    // the chunk went, and the LOD streamer kept a pointer to the freed mesh.
    if (s.in_sink)
        m_sink.on_unload(c);
    set_mesh_flags(c, s, false, false); // Keeps the counts; the sink was told above.
    (s.data == Data::Present ? m_present : s.data == Data::Failed ? m_failed : m_requested) -= 1;
    m_dirty_count -= size_t(s.dirty);
    m_mesh_candidates.erase(c);
    m_ahead_candidates.erase(c);
    m_chunks.erase(c);
    if (had_data && m_observer)
        m_observer->on_chunk_unloaded(c);
}

void ChunkStreamer::save_dirty(Clock::time_point now, bool all) {
    if (!m_store)
        return;
    // Oldest edit first: the first chunk not yet due ends the pass, however many are loaded.
    const auto delay = std::chrono::duration<double>(m_settings.save_delay_s);
    while (!m_dirty.empty()) {
        const Since e = m_dirty.front();
        if (!all && now - e.time < delay)
            return;
        m_dirty.pop_front();
        auto it = m_chunks.find(e.chunk);
        if (it == m_chunks.end() || !it->second.dirty || it->second.dirty_since != e.time)
            continue; // Saved when it was dropped.
        m_jobs->submit(std::make_unique<SaveJob>(events(), e.chunk, *m_world.find_chunk(e.chunk), *m_store,
                                                 it->second.edits, it->second.store_version));
        it->second.dirty = false;
        --m_dirty_count;
        ++m_saves;
    }
}

void ChunkStreamer::enforce_memory_cap(Clock::time_point deadline) {
    if (m_settings.memory_cap_bytes == 0 || m_block_bytes <= m_settings.memory_cap_bytes)
        return;
    // Farthest first, among chunks beyond the loaded ring only (those the view needs stay). The
    // candidates are sorted only while over the cap, and only when the viewer moved or some
    // were added since the last sort.
    if (!m_evict_sorted) {
        std::sort(m_evict.begin(), m_evict.end(),
                  [this](ChunkCoord a, ChunkCoord b) { return distance2(a, m_center) < distance2(b, m_center); });
        m_evict_sorted = true;
    }
    constexpr int kMinEvictions = 32;
    int evicted = 0;
    while (m_block_bytes > m_settings.memory_cap_bytes && !m_evict.empty()) {
        if (evicted >= kMinEvictions && Clock::now() >= deadline)
            return; // The rest next frame.
        const ChunkCoord c = m_evict.back();
        m_evict.pop_back();
        auto it = m_chunks.find(c);
        if (it == m_chunks.end() || !it->second.evict_listed)
            continue; // Dropped meanwhile, or a duplicate entry.
        ChunkState& s = it->second;
        s.evict_listed = false;
        if (s.data != Data::Present || in_loaded_ring(c))
            continue; // Listed again when it arrives (put_chunk) or leaves the ring again.
        drop(c, s);
        ++m_evicted;
        ++evicted;
    }
}

Status ChunkStreamer::flush() {
    return wait_saved(request_save());
}

uint64_t ChunkStreamer::request_save() {
    const uint64_t sequence = m_saves_done->next();
    if (!m_store) {
        m_saves_done->finished(sequence, {}); // Nothing persists: nothing to wait for.
        return sequence;
    }
    if (!m_jobs->start_error().empty()) { // No I/O thread to run the sync: say so, never wait.
        m_saves_done->finished(sequence, Error{"no thread to save on: " + m_jobs->start_error()});
        return sequence;
    }
    save_dirty(m_last_now, true);
    m_saves_at_request = m_saves;
    m_last_request = sequence;
    // Reported on the I/O thread (or by the job's destructor if it never runs).
    auto report = [tracker = m_saves_done, sequence](const Status& s) { tracker->finished(sequence, s); };
    m_jobs->submit(std::make_unique<StoreSyncJob>(events(), *m_store, sequence, std::move(report)));
    return sequence;
}

bool ChunkStreamer::settled() const {
    if (!m_have_center || m_requested > 0)
        return false; // A load or generation in flight (counted: no walk while filling the view).
    const auto delay = std::chrono::duration<double>(m_settings.unload_delay_s);
    for (const auto& [c, s] : m_chunks) {
        // A failed chunk waits for its retry: nothing to do until then. A chunk still drawn out
        // of the boxes is kept current too (queue_mesh).
        if (s.data == Data::Requested ||
            (s.data == Data::Present && (wants_mesh(c) || s.in_sink) && (!s.has_mesh || s.mesh_pending)))
            return false;
        // A chunk beyond the unload radius that is due to go (or not yet noticed) is pending work.
        if (beyond_unload(c) && (!s.outside || m_last_now - s.outside_since >= delay))
            return false;
    }
    return true;
}

StreamingMetrics ChunkStreamer::metrics() const {
    StreamingMetrics m;
    m.loaded = m_present;
    m.pending_data = m_requested;
    // Every chunk of the view exists (requested or present) from the first update on.
    const size_t side = size_t(2 * m_settings.view_radius + 1);
    m.wanted_meshes = m_have_center ? side * side * size_t(2 * m_settings.view_radius_vertical + 1) : 0;
    m.meshed = m_view_meshed;
    m.pending_meshes = m_mesh_pending;
    m.dirty = m_dirty_count;
    m.block_bytes = m_block_bytes;
    m.unloaded = m_unloaded;
    m.evicted = m_evicted;
    m.saves = m_saves;
    m.regenerated_corrupt = m_regenerated;
    m.reloaded = m_reloaded;
    m.load_failures = m_load_failures;
    m.generate_failed = m_failed;
    m.generate_failures = m_generate_failures;
    if (m_store)
        m.store = m_store->health();
    m.jobs = m_jobs->metrics();
    m.last_update_time = m_last_update;
    m.last_update_cpu = m_last_update_cpu;
    return m;
}

const ChunkMesh* ChunkStreamer::mesh(ChunkCoord c) const {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || !it->second.has_mesh)
        return nullptr;
    return it->second.mesh ? it->second.mesh.get() : &empty_mesh();
}

} // namespace vx::engine
