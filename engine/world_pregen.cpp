#include "engine/world_pregen.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/job_batch.h"
#include "world/lod/downsample.h"
#include "world/store/lod_load.h"
#include "world/mesh/mesher.h"

namespace vx::engine {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

// The state shared by one pregeneration's jobs; main thread only (complete()).
struct Progress {
    JobSystem& jobs;
    ChunkStore& store;
    const TerrainGenerator& gen;
    PregenStats stats;
    std::string failure; // The store's or the generator's first error.
    size_t lod_done = 0; // Coarse chunks saved or kept, all levels.
    // The store's stale coarse chunks, read by the first coarse save (I/O lane only).
    std::optional<LodDirtySet> lod_dirty;
};

// I/O lane: saves one chunk unless the store has it (a player's edits, say: kept), and lets the
// store commit when its batch is old enough.
class SaveChunkJob final : public Job {
public:
    SaveChunkJob(ChunkCoord c, Chunk chunk, Progress& p) : Job({c, JobKind::Save}), m_chunk(std::move(chunk)), m_p(p) {}
    void run(JobContext&) override {
        Result<bool> stored = m_p.store.contains(key().chunk);
        if (!stored) {
            m_status = Error{stored.error()};
            return;
        }
        m_kept = *stored;
        if (!m_kept) {
            // If absent: a shared store keeps a chunk another process saves before the commit.
            ChunkWrite w{key().chunk, &m_chunk};
            w.if_absent = true;
            m_status = m_p.store.save(std::span<const ChunkWrite>(&w, 1));
        }
        (void)m_p.store.tick(Clock::now()); // A failed commit shows again at flush().
    }
    void complete() override {
        if (!m_status && m_p.failure.empty())
            m_p.failure = m_status.error();
        ++(m_kept ? m_p.stats.kept : m_p.stats.chunks);
    }

private:
    Chunk m_chunk;
    Progress& m_p;
    Status m_status;
    bool m_kept = false;
};

// A coarse chunk the store has, or marks stale (edits under it: derived on load), is kept: a
// terrain chunk over it would hide those edits. Unmarked and absent, nothing under it was edited
// (the engine marks the coarse ancestors of every edit, with levels of detail on or off), so the
// terrain's chunk is right. A damaged record (moved aside by the load) is derived from the levels
// below and saved, as the engine does (LodLoadJob): kept as missing, it would read as terrain.
Result<bool> keep_coarse(Progress& p, LodCoord c) {
    if (!p.lod_dirty) {
        Result<std::vector<LodCoord>> dirty = p.store.list_lod_dirty();
        if (!dirty)
            return Error{dirty.error()};
        p.lod_dirty.emplace(dirty->begin(), dirty->end());
    }
    if (p.lod_dirty->contains(c))
        return true;
    Result<ChunkLoad> stored = p.store.load_lod(c);
    if (!stored)
        return Error{stored.error()};
    if (stored->state == LoadState::Corrupt) {
        LodDerived derived;
        Result<Chunk> d = load_or_derive_lod(p.store, p.gen, c, LodDirtySet{c}, &derived);
        if (!d)
            return Error{d.error()};
        if (Status s = save_derived(p.store, derived); !s)
            return Error{s.error()};
    }
    return stored->state != LoadState::Absent;
}

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

// I/O lane: saves one coarse chunk (see SaveChunkJob).
class SaveLodJob final : public Job {
public:
    SaveLodJob(LodCoord c, Chunk chunk, Progress& p)
        : Job({c.chunk, JobKind::Save}), m_level(c.level), m_chunk(std::move(chunk)), m_p(p) {}
    void run(JobContext&) override {
        Result<bool> keep = keep_coarse(m_p, {m_level, key().chunk});
        if (!keep) {
            m_status = Error{keep.error()};
            return;
        }
        m_kept = *keep;
        if (!m_kept)
            m_status = m_p.store.save_lod({m_level, key().chunk}, m_chunk);
        (void)m_p.store.tick(Clock::now());
    }
    void complete() override {
        if (!m_status && m_p.failure.empty())
            m_p.failure = m_status.error();
        ++(m_kept ? m_p.stats.lod_kept : m_p.stats.lod_chunks[size_t(m_level - 1)]);
        ++m_p.lod_done;
    }

private:
    int m_level;
    Chunk m_chunk;
    Progress& m_p;
    Status m_status;
    bool m_kept = false;
};

// Pool: makes one coarse chunk (generate_lod: the terrain's direct coarse chunk); complete()
// queues its save. Keyed by chunk coordinates alone, so one batch holds one level.
class GenerateLodJob final : public Job {
public:
    GenerateLodJob(LodCoord c, const TerrainGenerator& gen, Progress& p)
        : Job({c.chunk, JobKind::Generate}), m_level(c.level), m_gen(gen), m_p(p) {}
    void run(JobContext&) override { m_chunk = generate_lod(m_gen, {m_level, key().chunk}); }
    void complete() override {
        if (!m_chunk) {
            if (m_p.failure.empty())
                m_p.failure = m_chunk.error();
            return;
        }
        m_p.jobs.submit(std::make_unique<SaveLodJob>(LodCoord{m_level, key().chunk}, std::move(*m_chunk), m_p));
    }

private:
    int m_level;
    const TerrainGenerator& m_gen;
    Progress& m_p;
    Result<Chunk> m_chunk = Error{"not generated"};
};

size_t box_volume(ChunkCoord lo, ChunkCoord hi) {
    return size_t(hi.x - lo.x + 1) * size_t(hi.y - lo.y + 1) * size_t(hi.z - lo.z + 1);
}

// PregenInfo's rules for its box (world_pregen.h), in 64-bit arithmetic: the int32 sides of a
// box across the whole world overflow.
Status check_box(ChunkCoord lo, ChunkCoord hi) {
    int64_t volume = 1;
    for (int a = 0; a < 3; ++a) {
        if (lo[a] > hi[a])
            return Error{"pregeneration box: lo is above hi"};
        if (lo[a] == INT32_MIN || hi[a] == INT32_MAX)
            return Error{"pregeneration box: the world's outermost chunk layer has no neighbours to mesh against"};
        volume *= std::min<int64_t>(int64_t(hi[a]) - lo[a] + 1, kMaxPregenChunks + 1);
        volume = std::min(volume, kMaxPregenChunks + 1);
    }
    if (volume > kMaxPregenChunks)
        return Error{"pregeneration box: more than " + std::to_string(kMaxPregenChunks) + " chunks"};
    return {};
}

} // namespace

Result<PregenStats> pregenerate(JobSystem& jobs, const TerrainGenerator& gen, ChunkStore& store,
                                const PregenInfo& info) {
    VX_ASSERT_RETURN(info.lod_levels >= 0 && info.lod_levels <= kMaxLodLevel, Error{"lod levels out of range"});
    if (info.lod_levels > 0 && !store.supports_lod())
        return Error{"this store keeps no coarse levels"};
    if (Status s = check_box(info.lo, info.hi); !s)
        return Error{s.error()};
    const auto t0 = Clock::now();
    Progress p{jobs, store, gen, {}, {}, 0, std::nullopt};
    p.stats.lod_chunks.assign(size_t(info.lod_levels), 0);
    std::vector<std::unique_ptr<Job>> batch;
    batch.reserve(size_t(box_volume(info.lo, info.hi)));
    for (int y = info.lo.y; y <= info.hi.y; ++y) // check_box: hi < INT32_MAX, so ++ cannot overflow.
        for (int z = info.lo.z; z <= info.hi.z; ++z)
            for (int x = info.lo.x; x <= info.hi.x; ++x)
                batch.push_back(std::make_unique<GenerateChunkJob>(ChunkCoord(x, y, z), gen, p));
    size_t total = batch.size();
    for (int k = 1; k <= info.lod_levels; ++k)
        total += box_volume(info.lo >> k, info.hi >> k);
    std::function<void()> tick;
    if (info.progress)
        tick = [&] { info.progress(p.stats.chunks + p.lod_done, total); };
    run_batch(jobs, std::move(batch), tick);
    // Coarse levels after the blocks, one batch per level: jobs are keyed by chunk coordinates,
    // which repeat from level to level.
    for (int k = 1; k <= info.lod_levels && p.failure.empty(); ++k) {
        const ChunkCoord lo = info.lo >> k, hi = info.hi >> k;
        std::vector<std::unique_ptr<Job>> level;
        for (int y = lo.y; y <= hi.y; ++y)
            for (int z = lo.z; z <= hi.z; ++z)
                for (int x = lo.x; x <= hi.x; ++x)
                    level.push_back(std::make_unique<GenerateLodJob>(LodCoord{k, ChunkCoord(x, y, z)}, gen, p));
        run_batch(jobs, std::move(level), tick);
    }
    if (info.progress)
        info.progress(p.stats.chunks + p.lod_done, total);
    if (!p.failure.empty())
        return Error{"pregeneration failed: " + p.failure};
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
