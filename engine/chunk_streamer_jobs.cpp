// ChunkStreamer's jobs' side (main thread): chunk data requested, what load, generate, reload,
// mesh, save and store-sync jobs report (StreamJobEvents), failed loads and generations retried,
// the store's change feed, and mesh jobs scheduled.
#include "engine/chunk_streamer.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/mesh_sink.h"
#include "engine/stream_jobs.h"
#include "world/base/log.h"
#include "world/coords.h"

namespace vx::engine {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

std::unique_ptr<Job> ChunkStreamer::request_data(ChunkCoord c) {
    ChunkState& s = m_chunks[c];
    s.data = Data::Requested;
    ++m_requested;
    auto generate = std::make_unique<GenerateJob>(events(), c, m_generator);
    if (m_store)
        return std::make_unique<LoadJob>(events(), c, *m_store, std::move(generate));
    return generate;
}

void ChunkStreamer::on_loaded(ChunkCoord c, std::optional<Chunk> chunk, uint64_t version, const std::string& problem,
                              bool store_failed) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Requested)
        return; // Unloaded meanwhile.
    if (store_failed) {
        // The store could not say what is there (a server away): ask again in a second rather
        // than generate a chunk that would hide the stored one. Logged once per outage.
        ++m_load_failures;
        if (!m_store_failing)
            VX_LOG_WARN("chunk %d,%d,%d: %s; retrying (further failures are counted, not logged)", c.x, c.y, c.z,
                        problem.c_str());
        m_store_failing = true;
        m_retry.emplace_back(c, m_last_now + std::chrono::seconds(1));
        return;
    }
    m_store_failing = false;
    if (chunk) {
        it->second.store_version = version;
        put_chunk(c, std::move(*chunk));
        return;
    }
    // A miss: the load job already handed the chunk to its generate job (no hop through here).
    if (!problem.empty()) {
        VX_LOG_WARN("chunk %d,%d,%d: %s; regenerating", c.x, c.y, c.z, problem.c_str());
        ++m_regenerated;
    }
}

void ChunkStreamer::on_generated(ChunkCoord c, Chunk chunk) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Requested)
        return;
    put_chunk(c, std::move(chunk));
}

void ChunkStreamer::on_generate_failed(ChunkCoord c, const std::string& error) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Requested)
        return;
    ChunkState& s = it->second;
    s.data = Data::Failed;
    --m_requested;
    ++m_failed;
    ++m_generate_failures;
    // A generator that fails for a chunk will likely fail again: back off, 1 s doubling to 60 s.
    constexpr int kMaxDoublings = 6;
    const int doublings = std::min<int>(s.failures, kMaxDoublings);
    s.failures = uint8_t(std::min<int>(s.failures + 1, 255));
    const double wait_s = std::min(60.0, double(1 << doublings));
    s.retry_at = m_last_now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait_s));
    m_failed_retry.emplace_back(c, s.retry_at);
    VX_LOG_ERROR("chunk %d,%d,%d not loaded (nothing drawn there): %s; retrying in %.0f s", c.x, c.y, c.z,
                 error.c_str(), wait_s);
    // Its neighbours need not wait: they mesh as if it were air.
    for (int f = 0; f < 6; ++f)
        queue_mesh(c + face_normal(Face(f)));
}

void ChunkStreamer::retry_failed(Clock::time_point now) {
    if (m_failed_retry.empty())
        return;
    std::vector<std::unique_ptr<Job>> jobs;
    std::erase_if(m_failed_retry, [&](const std::pair<ChunkCoord, Clock::time_point>& e) {
        auto it = m_chunks.find(e.first);
        if (it == m_chunks.end() || it->second.data != Data::Failed || it->second.retry_at != e.second)
            return true; // Dropped, or failed again since (a newer entry).
        if (now < e.second)
            return false;
        --m_failed;
        jobs.push_back(request_data(e.first));
        return true;
    });
    if (!jobs.empty())
        m_jobs->submit_batch(std::move(jobs));
}

void ChunkStreamer::put_chunk(ChunkCoord c, Chunk chunk) {
    ChunkState& s = m_chunks[c];
    s.data = Data::Present;
    --m_requested;
    ++m_present;
    const bool was_failed = s.failures > 0;
    s.failures = 0;
    s.bytes = chunk.memory_bytes();
    m_block_bytes += s.bytes;
    m_world.put_chunk(c, std::move(chunk));
    if (m_settings.memory_cap_bytes != 0 && !in_loaded_ring(c))
        note_evictable(c, s); // Arrived after the ring moved on.
    // This chunk and its face neighbours may now have everything they need to mesh. After a
    // failed generation the neighbours were meshed against air: they mesh again.
    if (was_failed)
        remesh_around(c);
    queue_mesh(c);
    for (int f = 0; f < 6; ++f)
        queue_mesh(c + face_normal(Face(f)));
    if (s.changed_while_requested && m_store) { // The feed's news may be newer than what arrived.
        s.changed_while_requested = false;
        m_jobs->submit(std::make_unique<ReloadJob>(events(), c, *m_store));
    }
    if (m_observer)
        m_observer->on_chunk_loaded(c);
}

bool ChunkStreamer::neighbours_settled(ChunkCoord c) const {
    for (int f = 0; f < 6; ++f) {
        auto it = m_chunks.find(c + face_normal(Face(f)));
        if (it == m_chunks.end() || it->second.data == Data::Requested)
            return false;
    }
    return true;
}

void ChunkStreamer::queue_mesh(ChunkCoord c) {
    // A chunk that wants no mesh now is not queued: refresh_region() queues it when it enters
    // either box, and put_chunk() when its data arrives. But one still drawn (outside both boxes,
    // not unloaded yet) is kept current: left out, its old mesh stayed drawn, and edits of it
    // never reached the screen (their lookup finds no current mesh).
    if (in_view(c)) {
        m_mesh_candidates.insert(c);
    } else if (wants_mesh(c)) {
        m_ahead_candidates.insert(c);
    } else if (auto it = m_chunks.find(c); it != m_chunks.end() && it->second.in_sink) {
        m_ahead_candidates.insert(c);
    }
}

void ChunkStreamer::schedule_meshes(Clock::time_point deadline) {
    // One batch: one lock of the job system for the frame's mesh jobs, not one per job. Chunks in
    // the view go first (one missing now is a hole), then those around the lookahead point. The
    // clock is read after each chunk handed on (a chunk copy) and every kCheckEvery candidates
    // skipped: reading it costs about as much as skipping one. The first check comes after the
    // first chunk handed on (or kCheckEvery skipped), so every frame meshes one at least.
    constexpr int kCheckEvery = 16;
    std::vector<std::unique_ptr<Job>> jobs;
    int unchecked = 0;
    auto out_of_time = [&] {
        if (unchecked < kCheckEvery)
            return false;
        unchecked = 0;
        return Clock::now() >= deadline;
    };
    bool late = false;
    for (int pass = 0; pass < 2 && !late; ++pass) {
        auto& candidates = pass == 0 ? m_mesh_candidates : m_ahead_candidates;
        for (auto it = candidates.begin(); it != candidates.end();) {
            if ((late = out_of_time()))
                break; // The rest wait for the next frame.
            ++unchecked;
            const ChunkCoord c = *it;
            it = candidates.erase(it);
            auto st = m_chunks.find(c);
            if (st == m_chunks.end())
                continue;
            ChunkState& s = st->second;
            // Drawn only (queue_mesh): meshed whatever its neighbours, which may lie beyond the
            // loaded ring; one that arrives later remeshes it (put_chunk, remesh_around).
            const bool drawn_only = !wants_mesh(c);
            if (s.data != Data::Present || s.has_mesh || s.mesh_pending || (drawn_only && !s.in_sink) ||
                (!drawn_only && !neighbours_settled(c)))
                continue; // A later put_chunk() or refresh_region() brings it back.
            unchecked = kCheckEvery;
            if (std::unique_ptr<Job> job = request_mesh(c, s))
                jobs.push_back(std::move(job));
        }
    }
    if (!jobs.empty())
        m_jobs->submit_batch(std::move(jobs));
}

std::unique_ptr<Job> ChunkStreamer::request_mesh(ChunkCoord c, ChunkState& s) {
    const Chunk& chunk = *m_world.find_chunk(c);
    if (chunk.is_empty()) { // Air has no faces: no job, no mesh to draw.
        s.mesh.reset();
        set_mesh_flags(c, s, true, false);
        s.in_sink = true;
        m_sink.on_mesh(c, empty_mesh(), {});
        return nullptr;
    }
    set_mesh_flags(c, s, false, true);
    s.mesh_stale = false;
    return std::make_unique<MeshJob>(events(), c, m_world);
}

void ChunkStreamer::on_meshed(ChunkCoord c, ChunkMesh mesh) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || !it->second.mesh_pending)
        return;
    ChunkState& s = it->second;
    set_mesh_flags(c, s, s.has_mesh, false);
    if (s.mesh_stale || s.data != Data::Present) {
        // Edited while the job ran: its snapshot is out of date; mesh again.
        queue_mesh(c);
        return;
    }
    s.mesh = mesh.empty() ? nullptr : std::make_unique<ChunkMesh>(std::move(mesh));
    set_mesh_flags(c, s, true, false);
    s.in_sink = true;
    m_sink.on_mesh(c, s.mesh ? *s.mesh : empty_mesh(), {});
}

void ChunkStreamer::set_mesh_flags(ChunkCoord c, ChunkState& s, bool has_mesh, bool pending) {
    const bool was = s.has_mesh && !s.mesh_pending, is = has_mesh && !pending;
    m_mesh_pending = m_mesh_pending - size_t(s.mesh_pending) + size_t(pending);
    s.has_mesh = has_mesh;
    s.mesh_pending = pending;
    if (was != is && in_view(c))
        m_view_meshed = is ? m_view_meshed + 1 : m_view_meshed - 1;
}

void ChunkStreamer::on_saved(ChunkCoord c, const std::string& error, size_t edits_saved) {
    if (!error.empty())
        VX_LOG_ERROR("saving chunk %d,%d,%d failed: %s", c.x, c.y, c.z, error.c_str());
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || edits_saved == 0)
        return;
    std::vector<BlockEdit>& edits = it->second.edits; // The store has these now.
    edits.erase(edits.begin(), edits.begin() + std::ptrdiff_t(std::min(edits_saved, edits.size())));
}

void ChunkStreamer::on_store_commit(const Status& status) {
    // One line when commits start failing and one when they work again, not one per tick: a
    // store away for minutes would otherwise flood the log.
    if (!status && !m_commits_failing)
        VX_LOG_ERROR("store commit failed: %s; edits stay queued and are retried (further failures are not logged)",
                     status.error().c_str());
    else if (status && m_commits_failing)
        VX_LOG_WARN("store commits work again");
    m_commits_failing = !status;
}

void ChunkStreamer::poll_store_changes() {
    if (!m_store)
        return;
    // Loads the store failed to answer, once their second (of update time) has passed.
    const Clock::time_point t = m_last_now;
    std::vector<std::unique_ptr<Job>> jobs;
    while (!m_retry.empty() && m_retry.front().second <= t) {
        const ChunkCoord c = m_retry.front().first;
        m_retry.pop_front();
        auto it = m_chunks.find(c);
        if (it != m_chunks.end() && it->second.data == Data::Requested) {
            --m_requested; // request_data counts it again.
            jobs.push_back(request_data(c));
        }
    }
    // Chunks other processes changed (a shared store's feed; thread-safe and cheap to ask).
    m_changed.clear();
    if (m_store->poll_changes(m_changed)) { // Changes may have been missed: re-check every chunk held.
        VX_LOG_WARN("the store may have missed other processes' changes: re-checking %zu chunks", m_chunks.size());
        m_changed.clear();
        for (const auto& [c, state] : m_chunks)
            m_changed.push_back(c);
    }
    for (ChunkCoord c : m_changed) {
        auto it = m_chunks.find(c);
        if (it != m_chunks.end() && it->second.data == Data::Present)
            jobs.push_back(std::make_unique<ReloadJob>(events(), c, *m_store));
        else if (it != m_chunks.end() && it->second.data == Data::Requested)
            it->second.changed_while_requested = true; // Reloaded once present (put_chunk).
    }
    if (!jobs.empty())
        m_jobs->submit_batch(std::move(jobs));
}

void ChunkStreamer::on_reloaded(ChunkCoord c, std::optional<Chunk> chunk, uint64_t version) {
    auto it = m_chunks.find(c);
    if (it == m_chunks.end() || it->second.data != Data::Present || !chunk)
        return;
    ChunkState& s = it->second;
    // The copy is this version now, with the edits on top: its saves replace this version. (A
    // save queued before, of the older copy, still names the older one: it merges, not overwrites.)
    s.store_version = version;
    for (const BlockEdit& e : s.edits) // This process's edits the store has not seen stay on top.
        chunk->set(e.pos, e.id);
    const Chunk* now = m_world.find_chunk(c);
    if (now && *now == *chunk)
        return; // Nothing new (our own write, or already merged).
    m_block_bytes -= s.bytes;
    s.bytes = chunk->memory_bytes();
    m_block_bytes += s.bytes;
    m_world.put_chunk(c, std::move(*chunk));
    ++m_reloaded;
    remesh_around(c);
}

void ChunkStreamer::remesh_around(ChunkCoord c) {
    // The chunk and its face neighbours (whose aprons hold its border) mesh again; their current
    // meshes stay with the sink until the new ones replace them, so nothing blinks.
    for (int f = -1; f < 6; ++f) {
        const ChunkCoord q = f < 0 ? c : c + face_normal(Face(f));
        auto it = m_chunks.find(q);
        if (it == m_chunks.end() || it->second.data != Data::Present)
            continue;
        ChunkState& s = it->second;
        if (s.mesh_pending)
            s.mesh_stale = true;
        else if (s.has_mesh)
            set_mesh_flags(q, s, false, false);
        queue_mesh(q);
    }
}

} // namespace vx::engine
