#pragma once
// The jobs of chunk streaming. Each owns its snapshot (coordinates, a chunk copy, an apron) and
// reports back to the ChunkStreamer in complete(), on the main thread; the streamer re-checks
// that the chunk is still wanted (it may have been unloaded since).

#include <climits>
#include <future>
#include <memory>
#include <optional>
#include <string>

#include "engine/job.h"
#include "world/mesh/apron.h"
#include "world/mesh/chunk_mesh.h"
#include "world/store/chunk_store.h"
#include "world/gen/terrain.h"

namespace vx::engine {

class ChunkStreamer;

// I/O lane: reads a chunk record. When the store has none (absent, corrupt or a failed read) the
// job hands `fallback` (the chunk's GenerateJob) to the job system from the I/O thread: a miss
// goes to the pool without waiting for the main thread; complete() then only reports problems.
class LoadJob final : public Job {
public:
    LoadJob(ChunkStreamer& owner, world::ChunkCoord c, world::ChunkStore& store, std::unique_ptr<Job> fallback)
        : Job({c, JobKind::Load}), m_owner(owner), m_store(store), m_fallback(std::move(fallback)) {}
    void run(JobContext& ctx) override;
    void complete() override;
    std::unique_ptr<Job> take_continuation() override;

private:
    ChunkStreamer& m_owner;
    world::ChunkStore& m_store;
    std::unique_ptr<Job> m_fallback; // Submitted on a miss, destroyed unrun on a hit.
    std::optional<world::Chunk> m_chunk;
    std::string m_problem; // Corrupt record or store failure, for the log.
};

// Pool: generates terrain; a pure function of (seed, coordinate).
class GenerateJob final : public Job {
public:
    GenerateJob(ChunkStreamer& owner, world::ChunkCoord c, const world::TerrainGenerator& gen)
        : Job({c, JobKind::Generate}), m_owner(owner), m_gen(gen) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    ChunkStreamer& m_owner;
    const world::TerrainGenerator& m_gen; // Immutable; outlives the job system.
    world::Chunk m_chunk;
};

// Pool: meshes a snapshot (chunk copy + apron).
class MeshJob final : public Job {
public:
    MeshJob(ChunkStreamer& owner, world::ChunkCoord c, world::Chunk chunk, std::unique_ptr<world::Apron> apron,
            const world::BlockRegistry& registry)
        : Job({c, JobKind::Mesh}), m_owner(owner), m_chunk(std::move(chunk)), m_apron(std::move(apron)),
          m_registry(registry) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    ChunkStreamer& m_owner;
    world::Chunk m_chunk;
    std::unique_ptr<world::Apron> m_apron;
    const world::BlockRegistry& m_registry; // The streamer's; outlives the job system.
    world::ChunkMesh m_mesh;
};

// I/O lane: queues a chunk's record in the store (which commits within its time bound).
class SaveJob final : public Job {
public:
    SaveJob(ChunkStreamer& owner, world::ChunkCoord c, world::Chunk chunk, world::ChunkStore& store)
        : Job({c, JobKind::Save}), m_owner(owner), m_chunk(std::move(chunk)), m_store(store) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    ChunkStreamer& m_owner;
    world::Chunk m_chunk;
    world::ChunkStore& m_store;
    std::string m_error;
};

// I/O lane: store.tick(now), or flush() when a promise waits for it. Ticks and flushes use keys of
// their own (no chunk has them), so a tick never replaces a waiting flush.
inline const world::ChunkCoord kTickKey{INT32_MIN, INT32_MIN, INT32_MIN};
inline const world::ChunkCoord kFlushKey{INT32_MIN, INT32_MIN, INT32_MIN + 1};
class StoreSyncJob final : public Job {
public:
    StoreSyncJob(ChunkStreamer& owner, world::ChunkStore& store, std::promise<Status>* flushed)
        : Job({flushed ? kFlushKey : kTickKey, JobKind::IoTask}), m_owner(owner), m_store(store), m_flushed(flushed) {}
    ~StoreSyncJob() override;
    void run(JobContext& ctx) override;
    void complete() override;

private:
    ChunkStreamer& m_owner;
    world::ChunkStore& m_store;
    std::promise<Status>* m_flushed; // Null: a periodic tick.
    Status m_status;
};

} // namespace vx::engine
