#include "engine/chunk_streamer.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include "engine/stream_jobs.h"
#include "world/base/log.h"

namespace vx::engine {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

namespace {
// CPU time of the calling thread: the work update() does, without time the OS gave others.
std::chrono::nanoseconds thread_cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

const ChunkMesh& empty_mesh() {
    static const ChunkMesh kEmpty;
    return kEmpty;
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
}

ChunkStreamer::~ChunkStreamer() {
    if (m_store) {
        Status s = flush();
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

void ChunkStreamer::update_viewer(const glm::dvec3& position, const glm::dvec3& forward, const glm::dvec3* velocity,
                                  Clock::time_point now) {
    const Clock::time_point t0 = Clock::now();
    const std::chrono::nanoseconds cpu0 = thread_cpu_now();
    const Clock::time_point deadline = t0 + m_settings.frame_budget;
    m_jobs->set_viewer({position, forward});
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
    // Never look further ahead than the view radius itself.
    glm::dvec3 ahead = m_velocity * m_settings.lookahead_s;
    const double reach = double(m_settings.view_radius * kChunkSize);
    if (glm::length(ahead) > reach)
        ahead *= reach / glm::length(ahead);
    const ChunkCoord lead = chunk_at(position + ahead);
    if (!m_have_center || center != m_center || lead != m_lead) {
        m_center = center;
        m_lead = lead;
        m_have_center = true;
        refresh_region(now);
    }
    // Completions get most of the budget; what is left schedules new meshes.
    CompletionBudget budget;
    budget.time = std::chrono::duration_cast<std::chrono::nanoseconds>(m_settings.frame_budget * 3 / 4);
    m_jobs->process_completions(budget);
    schedule_meshes(deadline);
    unload_far(now, deadline);
    enforce_memory_cap();
    save_dirty(now, false);
    if (m_store && now - m_last_tick >= std::chrono::duration<double>(m_settings.store_tick_s)) {
        m_last_tick = now;
        m_jobs->submit(std::make_unique<StoreSyncJob>(events(), *m_store));
    }
    m_last_update = Clock::now() - t0;
    m_last_update_cpu = thread_cpu_now() - cpu0;
}

void ChunkStreamer::refresh_region(Clock::time_point) {
    // Every chunk of the loaded ring is requested (again, if it was dropped: no silent holes),
    // in one batch; loaded chunks that now want a mesh become candidates.
    std::vector<std::unique_ptr<Job>> jobs;
    request_box(m_center, jobs);
    if (m_lead != m_center)
        request_box(m_lead, jobs);
    if (!jobs.empty())
        m_jobs->submit_batch(std::move(jobs));
    // Chunks now beyond the unload radius are found by unload_far's continuous scan.
}

void ChunkStreamer::request_box(ChunkCoord center, std::vector<std::unique_ptr<Job>>& jobs) {
    const int r = m_settings.view_radius + 1, rv = m_settings.view_radius_vertical + 1;
    for (int dy = -rv; dy <= rv; ++dy)
        for (int dz = -r; dz <= r; ++dz)
            for (int dx = -r; dx <= r; ++dx) {
                const ChunkCoord c = center + ChunkCoord(dx, dy, dz);
                auto it = m_chunks.find(c);
                if (it == m_chunks.end())
                    jobs.push_back(request_data(c));
                else if (it->second.data == Data::Present && !it->second.has_mesh && wants_mesh(c))
                    m_mesh_candidates.insert(c);
            }
}

std::unique_ptr<Job> ChunkStreamer::request_data(ChunkCoord c) {
    ChunkState& s = m_chunks[c];
    s.data = Data::Requested;
    if (m_store)
        return std::make_unique<LoadJob>(events(), c, *m_store);
    return std::make_unique<GenerateJob>(events(), c, m_generator);
}

void ChunkStreamer::on_loaded(ChunkCoord c, std::optional<Chunk> chunk, const std::string& problem) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Requested)
        return; // Unloaded meanwhile.
    if (chunk) {
        put_chunk(c, std::move(*chunk));
        return;
    }
    if (!problem.empty()) {
        VX_LOG_WARN("chunk %d,%d,%d: %s; regenerating", c.x, c.y, c.z, problem.c_str());
        ++m_regenerated;
    }
    m_jobs->submit(std::make_unique<GenerateJob>(events(), c, m_generator));
}

void ChunkStreamer::on_generated(ChunkCoord c, Chunk chunk) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Requested)
        return;
    put_chunk(c, std::move(chunk));
}

void ChunkStreamer::put_chunk(ChunkCoord c, Chunk chunk) {
    ChunkState& s = m_chunks[c];
    s.data = Data::Present;
    s.bytes = chunk.memory_bytes();
    m_block_bytes += s.bytes;
    m_world.put_chunk(c, std::move(chunk));
    // This chunk and its face neighbours may now have everything they need to mesh.
    m_mesh_candidates.insert(c);
    for (int f = 0; f < 6; ++f)
        m_mesh_candidates.insert(c + face_normal(Face(f)));
    if (m_observer)
        m_observer->on_chunk_loaded(c);
}

bool ChunkStreamer::neighbours_present(ChunkCoord c) const {
    for (int f = 0; f < 6; ++f) {
        auto it = m_chunks.find(c + face_normal(Face(f)));
        if (it == m_chunks.end() || it->second.data != Data::Present)
            return false;
    }
    return true;
}

void ChunkStreamer::schedule_meshes(Clock::time_point deadline) {
    for (auto it = m_mesh_candidates.begin(); it != m_mesh_candidates.end();) {
        if (Clock::now() >= deadline)
            return; // The rest wait for the next frame.
        const ChunkCoord c = *it;
        it = m_mesh_candidates.erase(it);
        auto st = m_chunks.find(c);
        if (st == m_chunks.end())
            continue;
        ChunkState& s = st->second;
        if (s.data != Data::Present || s.has_mesh || s.mesh_pending || !wants_mesh(c) || !neighbours_present(c))
            continue; // A later put_chunk() or refresh_region() brings it back.
        request_mesh(c, s);
    }
}

void ChunkStreamer::request_mesh(ChunkCoord c, ChunkState& s) {
    const Chunk& chunk = *m_world.find_chunk(c);
    if (chunk.is_empty()) { // Air has no faces: no job, no mesh to draw.
        s.mesh.reset();
        s.has_mesh = true;
        m_sink.on_mesh(c, empty_mesh(), {});
        return;
    }
    auto apron = std::make_unique<Apron>(make_apron(m_world, c));
    s.mesh_pending = true;
    s.mesh_stale = false;
    m_jobs->submit(std::make_unique<MeshJob>(events(), c, chunk, std::move(apron), m_world.registry()));
}

void ChunkStreamer::on_meshed(ChunkCoord c, ChunkMesh mesh) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || !it->second.mesh_pending)
        return;
    ChunkState& s = it->second;
    s.mesh_pending = false;
    if (s.mesh_stale || s.data != Data::Present) {
        // Edited while the job ran: its snapshot is out of date; mesh again.
        m_mesh_candidates.insert(c);
        return;
    }
    s.mesh = mesh.empty() ? nullptr : std::make_unique<ChunkMesh>(std::move(mesh));
    s.has_mesh = true;
    m_sink.on_mesh(c, s.mesh ? *s.mesh : empty_mesh(), {});
}

void ChunkStreamer::on_saved(ChunkCoord c, const std::string& error) {
    if (!error.empty())
        VX_LOG_ERROR("saving chunk %d,%d,%d failed: %s", c.x, c.y, c.z, error.c_str());
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
    if (m_store && !m_store->read_only() && !s.dirty) {
        s.dirty = true;
        s.dirty_since = Clock::now();
    }
    for (const SliceUpdate& u : r.updates)
        m_sink.on_mesh(u.chunk, *m_chunks.at(u.chunk).mesh, std::span<const int>(u.slices.data(), size_t(u.count)));
    return {};
}

void ChunkStreamer::unload_far(Clock::time_point now, Clock::time_point deadline) {
    // A slice of the chunks is checked each frame (all of them every ~16 frames), so the cost
    // stays flat however many chunks are loaded; the unload delay dwarfs the scan latency.
    // Drops stay within the frame's budget, but at least kMinDrops happen a frame so memory
    // cannot grow without bound while the budget is spent elsewhere.
    constexpr int kMinDrops = 32;
    const auto delay = std::chrono::duration<double>(m_settings.unload_delay_s);
    if (m_scan_pos >= m_scan.size()) {
        m_scan.clear();
        for (const auto& [c, st] : m_chunks)
            m_scan.push_back(c);
        m_scan_pos = 0;
    }
    const size_t end = std::min(m_scan.size(), m_scan_pos + std::max<size_t>(256, m_scan.size() / 16));
    int dropped = 0;
    for (; m_scan_pos < end; ++m_scan_pos) {
        const ChunkCoord c = m_scan[m_scan_pos];
        auto it = m_chunks.find(c);
        if (it == m_chunks.end())
            continue;
        ChunkState& s = it->second;
        if (!beyond_unload(c)) {
            s.outside = false;
            continue;
        }
        if (!s.outside) {
            s.outside = true;
            s.outside_since = now;
        }
        if (now - s.outside_since < delay)
            continue;
        if (dropped >= kMinDrops && Clock::now() >= deadline)
            return; // Checked again on the next pass.
        drop(c, s);
        ++m_unloaded;
        ++dropped;
    }
}

void ChunkStreamer::drop(ChunkCoord c, ChunkState& s) {
    m_jobs->cancel({c, JobKind::Load});
    m_jobs->cancel({c, JobKind::Generate});
    m_jobs->cancel({c, JobKind::Mesh});
    if (s.data == Data::Present) {
        Chunk* chunk = m_world.find_chunk(c);
        if (s.dirty && m_store) { // Saved before it is dropped: the job owns the data now.
            m_jobs->submit(std::make_unique<SaveJob>(events(), c, std::move(*chunk), *m_store));
            ++m_saves;
        }
        m_block_bytes -= s.bytes;
        m_world.remove_chunk(c);
    }
    const bool had_data = s.data == Data::Present;
    if (s.has_mesh)
        m_sink.on_unload(c);
    m_mesh_candidates.erase(c);
    m_chunks.erase(c);
    if (had_data && m_observer)
        m_observer->on_chunk_unloaded(c);
}

void ChunkStreamer::save_dirty(Clock::time_point now, bool all) {
    if (!m_store)
        return;
    const auto delay = std::chrono::duration<double>(m_settings.save_delay_s);
    for (auto& [c, s] : m_chunks) {
        if (!s.dirty || (!all && now - s.dirty_since < delay))
            continue;
        m_jobs->submit(std::make_unique<SaveJob>(events(), c, *m_world.find_chunk(c), *m_store));
        s.dirty = false;
        ++m_saves;
    }
}

void ChunkStreamer::enforce_memory_cap() {
    if (m_settings.memory_cap_bytes == 0 || m_block_bytes <= m_settings.memory_cap_bytes)
        return;
    // Farthest first; only chunks beyond the loaded ring (those the view needs stay).
    std::vector<std::pair<int64_t, ChunkCoord>> far;
    for (const auto& [c, s] : m_chunks) {
        if (s.data != Data::Present || in_loaded_ring(c))
            continue;
        const glm::i64vec3 d = glm::i64vec3(c - m_center);
        far.push_back({d.x * d.x + d.y * d.y + d.z * d.z, c});
    }
    std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [dist, c] : far) {
        if (m_block_bytes <= m_settings.memory_cap_bytes)
            break;
        drop(c, m_chunks.at(c));
        ++m_evicted;
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
    save_dirty(Clock::now(), true);
    // Reported on the I/O thread (or by the job's destructor if it never runs).
    auto report = [tracker = m_saves_done, sequence](const Status& s) { tracker->finished(sequence, s); };
    m_jobs->submit(std::make_unique<StoreSyncJob>(events(), *m_store, sequence, std::move(report)));
    return sequence;
}

bool ChunkStreamer::settled() const {
    if (!m_have_center)
        return false;
    const auto delay = std::chrono::duration<double>(m_settings.unload_delay_s);
    for (const auto& [c, s] : m_chunks) {
        if (s.data != Data::Present || (wants_mesh(c) && (!s.has_mesh || s.mesh_pending)))
            return false;
        // A chunk beyond the unload radius that is due to go (or not yet noticed) is pending work.
        if (beyond_unload(c) && (!s.outside || m_last_now - s.outside_since >= delay))
            return false;
    }
    return true;
}

StreamingMetrics ChunkStreamer::metrics() const {
    StreamingMetrics m;
    for (const auto& [c, s] : m_chunks) {
        m.loaded += s.data == Data::Present;
        m.pending_data += s.data == Data::Requested;
        const bool view = in_view(c);
        m.wanted_meshes += view;
        m.meshed += view && s.has_mesh && !s.mesh_pending;
        m.pending_meshes += s.mesh_pending;
        m.dirty += s.dirty;
    }
    m.block_bytes = m_block_bytes;
    m.unloaded = m_unloaded;
    m.evicted = m_evicted;
    m.saves = m_saves;
    m.regenerated_corrupt = m_regenerated;
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
