#include "engine/stream_jobs.h"

#include "world/mesh/mesher.h"

namespace vx::engine {

void LoadJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    Result<world::ChunkLoad> r = m_store.load(key().chunk);
    if (!r) {
        m_problem = "store failed: " + r.error();
        m_failed = true;
        return;
    }
    m_version = r->version;
    if (r->state == world::LoadState::Present)
        m_chunk = std::move(r->chunk);
    else if (r->state == world::LoadState::Corrupt)
        m_problem = "corrupt record (quarantined): " + r->problem;
}

std::unique_ptr<Job> LoadJob::take_continuation() { return m_chunk || m_failed ? nullptr : std::move(m_fallback); }

void LoadJob::complete() { m_owner.on_loaded(key().chunk, std::move(m_chunk), m_version, m_problem, m_failed); }

void ReloadJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    Result<world::ChunkLoad> r = m_store.load(key().chunk);
    if (r && r->state == world::LoadState::Present) {
        m_chunk = std::move(r->chunk);
        m_version = r->version;
    }
}

void ReloadJob::complete() { m_owner.on_reloaded(key().chunk, std::move(m_chunk), m_version); }

void GenerateJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    Result<world::Chunk> r = m_gen.try_generate(key().chunk);
    if (r)
        m_chunk = std::move(*r);
    else
        m_error = r.error();
}

void GenerateJob::complete() {
    // A job that completes has run (a cancelled one is discarded unapplied), so it has one or the other.
    if (m_chunk)
        m_owner.on_generated(key().chunk, std::move(*m_chunk));
    else
        m_owner.on_generate_failed(key().chunk, m_error.empty() ? std::string("no chunk generated") : m_error);
}

MeshJob::MeshJob(StreamJobEvents& owner, world::ChunkCoord c, const world::World& world)
    : Job({c, JobKind::Mesh}), m_owner(owner), m_chunk(*world.find_chunk(c)), m_registry(world.registry()) {
    for (int f = 0; f < 6; ++f)
        m_layers[size_t(f)].take(world::Face(f), world.find_neighbour(c, world::Face(f)));
}

void MeshJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    // One mesher and apron (and their scratch) per worker thread, reused by every mesh job it runs.
    thread_local world::GreedyMesher mesher;
    thread_local world::Apron apron;
    for (int f = 0; f < 6; ++f)
        apron.set_face(world::Face(f), m_layers[size_t(f)], m_registry);
    mesher.mesh({m_chunk, apron, m_registry}, m_mesh);
}

void MeshJob::complete() { m_owner.on_meshed(key().chunk, std::move(m_mesh)); }

void SaveJob::run(JobContext&) {
    // Saves are never skipped, even when cancelled: the chunk was dropped trusting this job.
    world::ChunkWrite w{key().chunk, &m_chunk, m_edits};
    w.base_version = m_base_version;
    Status s = m_store.save(std::span<const world::ChunkWrite>(&w, 1));
    if (!s)
        m_error = s.error();
}

void SaveJob::complete() { m_owner.on_saved(key().chunk, m_error, m_error.empty() ? m_edits.size() : 0); }

world::ChunkCoord flush_key(uint64_t sequence) {
    return {INT32_MIN, INT32_MIN + 1, int32_t(sequence & 0x7fffffffu)};
}

void StoreSyncJob::run(JobContext&) {
    if (m_flushed) {
        FlushDone done = std::move(m_flushed);
        m_flushed = nullptr;
        m_status = m_store.flush();
        done(m_status);
        return;
    }
    m_status = m_store.tick(world::ChunkStore::Clock::now());
}

void StoreSyncJob::complete() { m_owner.on_store_commit(m_status); }

StoreSyncJob::~StoreSyncJob() {
    if (m_flushed) // Never ran (shutdown): whoever waits must not wait forever.
        m_flushed(Error{"flush cancelled: the job system is shutting down"});
}

} // namespace vx::engine
