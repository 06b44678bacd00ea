#pragma once
// The jobs of chunk streaming. Each owns its snapshot (coordinates, chunk copies) and
// reports back through StreamJobEvents in complete(), on the main thread; the receiver (the
// ChunkStreamer) re-checks that the chunk is still wanted (it may have been unloaded since).

#include <array>
#include <climits>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "engine/job.h"
#include "world/mesh/apron.h"
#include "world/mesh/chunk_mesh.h"
#include "world/store/chunk_store.h"
#include "world/gen/chunk_generator.h"
#include "world/world.h"

namespace vx::engine {

// What the jobs report, and nothing more: the streamer implements it (no friendship, so a job
// cannot reach the streamer's state). Main thread only: every call comes from a job's complete().
class StreamJobEvents {
public:
    // A load finished: `chunk` when stored and intact; else `problem` says why (empty: absent).
    // `store_failed`: the store could not answer (a shared store's server away): nothing was
    // generated in its place, so the caller asks again later.
    // `version`: the store's version of `chunk` (world::ChunkLoad::version), for its saves.
    virtual void on_loaded(world::ChunkCoord c, std::optional<world::Chunk> chunk, uint64_t version,
                           const std::string& problem, bool store_failed) = 0;
    // Another process changed chunk `c` in a shared store: its stored version (nullopt: erased,
    // unreadable or the store failed), and that version's number.
    virtual void on_reloaded(world::ChunkCoord c, std::optional<world::Chunk> chunk, uint64_t version) = 0;
    virtual void on_generated(world::ChunkCoord c, world::Chunk chunk) = 0;
    // The generator failed for `c` (a game's generator threw): `error` says why; no chunk.
    virtual void on_generate_failed(world::ChunkCoord c, const std::string& error) = 0;
    virtual void on_meshed(world::ChunkCoord c, world::ChunkMesh mesh) = 0;
    // A save failed with `error` (empty: it succeeded). `edits_saved`: how many of the chunk's
    // oldest recorded block edits the save carried to the store.
    virtual void on_saved(world::ChunkCoord c, const std::string& error, size_t edits_saved) = 0;
    // A store commit (a periodic tick, or a flush, which also reports to its waiter) ended:
    // `status` is its error, or success. Failed commits keep their edits queued in the store,
    // and the next tick retries them.
    virtual void on_store_commit(const Status& status) = 0;

protected:
    ~StreamJobEvents() = default;
};

// I/O lane: reads a chunk record. When the store has none (absent or corrupt) the job hands
// `fallback` (the chunk's GenerateJob) to the job system from the I/O thread: a miss goes to the
// pool without waiting for the main thread; complete() then only reports problems. When the store
// itself fails (a server away), nothing is generated: a generated chunk would hide what is stored.
class LoadJob final : public Job {
public:
    LoadJob(StreamJobEvents& owner, world::ChunkCoord c, world::ChunkStore& store, std::unique_ptr<Job> fallback)
        : Job({c, JobKind::Load}), m_owner(owner), m_store(store), m_fallback(std::move(fallback)) {}
    void run(JobContext& ctx) override;
    void complete() override;
    std::unique_ptr<Job> take_continuation() override;

private:
    StreamJobEvents& m_owner;
    world::ChunkStore& m_store;
    std::unique_ptr<Job> m_fallback; // Submitted on a miss, destroyed unrun on a hit.
    std::optional<world::Chunk> m_chunk;
    uint64_t m_version = 0;
    std::string m_problem; // Corrupt record or store failure, for the log.
    bool m_failed = false; // The store failed: no fallback.
};

// I/O lane: reads a chunk another process changed (a shared store's change feed).
class ReloadJob final : public Job {
public:
    ReloadJob(StreamJobEvents& owner, world::ChunkCoord c, world::ChunkStore& store)
        : Job({c, JobKind::Load}), m_owner(owner), m_store(store) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    StreamJobEvents& m_owner;
    world::ChunkStore& m_store;
    std::optional<world::Chunk> m_chunk;
    uint64_t m_version = 0;
};

// Pool: generates a chunk (a pure function of the coordinate). A generator that fails (a game's
// that threw) is reported as such: no chunk, never a partial one.
class GenerateJob final : public Job {
public:
    GenerateJob(StreamJobEvents& owner, world::ChunkCoord c, const world::ChunkGenerator& gen)
        : Job({c, JobKind::Generate}), m_owner(owner), m_gen(gen) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    StreamJobEvents& m_owner;
    const world::ChunkGenerator& m_gen; // Thread-safe const; outlives the job system.
    std::optional<world::Chunk> m_chunk;
    std::string m_error; // The generator's failure.
};

// Pool: meshes a snapshot: a copy of the chunk and the layers of its six face neighbours that
// touch it (as palette entries, world::ApronLayer), taken on the main thread; the apron is
// expanded from them on the worker. Expanding an apron (~6,000 blocks classified and written)
// was the largest main-thread cost of a mesh job; taking the layers is a few row unpacks.
class MeshJob final : public Job {
public:
    // Main thread (reads `world`): chunk `c` must be loaded; absent neighbours are air.
    MeshJob(StreamJobEvents& owner, world::ChunkCoord c, const world::World& world);
    void run(JobContext& ctx) override;
    void complete() override;

private:
    StreamJobEvents& m_owner;
    world::Chunk m_chunk;
    std::array<world::ApronLayer, 6> m_layers; // Indexed by world::Face.
    const world::BlockRegistry& m_registry;    // The world's; outlives the job system.
    world::ChunkMesh m_mesh;
};

// I/O lane: queues a chunk's record in the store (which commits within its time bound).
class SaveJob final : public Job {
public:
    // `edits`: the block edits since the chunk was last handed to the store (a shared store
    // re-applies them if another process wrote the chunk meanwhile). A newer SaveJob of the
    // chunk replaces a queued one, so each carries every edit not yet saved, not only new ones.
    // `base_version`: the stored version the chunk was loaded as (world::ChunkWrite).
    SaveJob(StreamJobEvents& owner, world::ChunkCoord c, world::Chunk chunk, world::ChunkStore& store,
            std::vector<world::BlockEdit> edits = {}, uint64_t base_version = 0)
        : Job({c, JobKind::Save}), m_owner(owner), m_chunk(std::move(chunk)), m_store(store),
          m_edits(std::move(edits)), m_base_version(base_version) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    StreamJobEvents& m_owner;
    world::Chunk m_chunk;
    world::ChunkStore& m_store;
    std::vector<world::BlockEdit> m_edits;
    uint64_t m_base_version;
    std::string m_error;
};

// I/O lane: store.tick(now), or store.flush() reporting to `flushed` (on the I/O thread, or with
// an error from the destructor if the job never ran). Ticks share one key (a newer tick replaces
// a queued one); each flush has a key of its own, so a later flush never takes an earlier one's
// place in line ahead of the saves submitted between them. No chunk uses JobKind::IoTask.
inline const world::ChunkCoord kTickKey{INT32_MIN, INT32_MIN, INT32_MIN};
world::ChunkCoord flush_key(uint64_t sequence);
class StoreSyncJob final : public Job {
public:
    using FlushDone = std::function<void(const Status&)>;
    // Tick.
    StoreSyncJob(StreamJobEvents& owner, world::ChunkStore& store)
        : Job({kTickKey, JobKind::IoTask}), m_owner(owner), m_store(store) {}
    // Flush number `sequence`; `flushed` is called exactly once.
    StoreSyncJob(StreamJobEvents& owner, world::ChunkStore& store, uint64_t sequence, FlushDone flushed)
        : Job({flush_key(sequence), JobKind::IoTask}), m_owner(owner), m_store(store), m_flushed(std::move(flushed)) {}
    ~StoreSyncJob() override;
    void run(JobContext& ctx) override;
    void complete() override;

private:
    StreamJobEvents& m_owner;
    world::ChunkStore& m_store;
    FlushDone m_flushed; // Empty: a periodic tick (or already reported).
    Status m_status;
};

} // namespace vx::engine
