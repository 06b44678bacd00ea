#include "engine/world_pregen.h"

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "engine/job_batch.h"
#include "world/mesh/mesher.h"

namespace vx::engine {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

// The state shared by one pregeneration's jobs; main thread only (complete()).
struct Progress {
    JobSystem& jobs;
    ChunkStore& store;
    PregenStats stats;
    std::string failure; // The store's first error.
};

// I/O lane: saves one chunk and lets the store commit when its batch is old enough.
class SaveChunkJob final : public Job {
public:
    SaveChunkJob(ChunkCoord c, Chunk chunk, Progress& p) : Job({c, JobKind::Save}), m_chunk(std::move(chunk)), m_p(p) {}
    void run(JobContext&) override {
        m_status = m_p.store.save(key().chunk, m_chunk);
        (void)m_p.store.tick(Clock::now()); // A failed commit shows again at flush().
    }
    void complete() override {
        if (!m_status && m_p.failure.empty())
            m_p.failure = m_status.error();
        ++m_p.stats.chunks;
    }

private:
    Chunk m_chunk;
    Progress& m_p;
    Status m_status;
};

// Pool: generates one chunk and meshes it in isolation; complete() queues its save.
class GenerateChunkJob final : public Job {
public:
    GenerateChunkJob(ChunkCoord c, const TerrainGenerator& gen, Progress& p)
        : Job({c, JobKind::Generate}), m_gen(gen), m_p(p) {}
    void run(JobContext&) override {
        // Every chunk must be saved: no early return on cancellation (the batch owns the system).
        thread_local GreedyMesher mesher;
        thread_local ChunkMesh mesh;
        m_chunk = m_gen.generate(key().chunk);
        mesher.mesh({m_chunk, Apron::air(), BlockRegistry::default_registry()}, mesh);
        m_quads = mesh.quad_count();
    }
    void complete() override {
        m_p.stats.quads += m_quads;
        m_p.stats.non_uniform += !m_chunk.is_uniform();
        m_p.jobs.submit(std::make_unique<SaveChunkJob>(key().chunk, std::move(m_chunk), m_p));
    }

private:
    const TerrainGenerator& m_gen;
    Progress& m_p;
    Chunk m_chunk;
    uint32_t m_quads = 0;
};

} // namespace

Result<PregenStats> pregenerate(JobSystem& jobs, const TerrainGenerator& gen, ChunkStore& store,
                                const PregenInfo& info) {
    const auto t0 = Clock::now();
    Progress p{jobs, store, {}, {}};
    std::vector<std::unique_ptr<Job>> batch;
    for (int y = info.lo.y; y <= info.hi.y; ++y)
        for (int z = info.lo.z; z <= info.hi.z; ++z)
            for (int x = info.lo.x; x <= info.hi.x; ++x)
                batch.push_back(std::make_unique<GenerateChunkJob>(ChunkCoord(x, y, z), gen, p));
    const size_t total = batch.size();
    std::function<void()> tick;
    if (info.progress)
        tick = [&] { info.progress(p.stats.chunks, total); };
    run_batch(jobs, std::move(batch), tick);
    if (info.progress)
        info.progress(p.stats.chunks, total);
    if (!p.failure.empty())
        return Error{"saving failed: " + p.failure};
    // The flush, too, on the I/O lane: the store is never touched from this thread.
    Status flushed;
    std::vector<std::unique_ptr<Job>> flush;
    flush.push_back(std::make_unique<FunctionJob>(JobKey{ChunkCoord(0), JobKind::IoTask},
                                                  [&](JobContext&) { flushed = store.flush(); }, nullptr));
    run_batch(jobs, std::move(flush));
    if (!flushed)
        return Error{flushed.error()};
    p.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return p.stats;
}

} // namespace vx::engine
