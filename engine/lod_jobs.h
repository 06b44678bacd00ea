#pragma once
// The jobs of coarse levels of detail (engine/lod_streamer.h): load a coarse chunk from the store
// (I/O lane), make it with the generator (pool), mesh it (pool), save an edited one (I/O lane).
// Each owns its snapshot and reports in complete() on the main thread through LodJobEvents; the
// receiver re-checks that the chunk is still wanted. Keys carry the level (JobKey::level), so a
// coarse job never replaces a level-0 job of the same chunk coordinate.

#include <memory>
#include <optional>
#include <string>

#include "engine/job.h"
#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/gen/chunk_generator.h"
#include "world/lod/lod_coords.h"
#include "world/mesh/chunk_mesh.h"
#include "world/store/chunk_store.h"
#include "world/store/lod_load.h"

namespace vx::engine {

// What the coarse jobs report. Main thread only: every call comes from a job's complete().
class LodJobEvents {
public:
    // Coarse chunk `c`'s data: from the store or the generator; `error` (one line) when neither
    // could make it (a store away, a game's generator that threw): then no chunk.
    virtual void on_lod_data(world::LodCoord c, std::optional<world::Chunk> chunk, const std::string& error) = 0;
    virtual void on_lod_meshed(world::LodCoord c, world::ChunkMesh mesh) = 0;
    // A coarse save failed with `error` (empty: it succeeded).
    virtual void on_lod_saved(world::LodCoord c, const std::string& error) = 0;

protected:
    ~LodJobEvents() = default;
};

// Job keys of coarse chunks: the level rides in JobKey::level.
inline JobKey lod_job_key(world::LodCoord c, JobKind kind) { return {c.chunk, kind, uint8_t(c.level)}; }
inline world::LodCoord lod_of(const JobKey& k) { return {int(k.level), k.chunk}; }

// Coarse jobs are ordered as if a level-k chunk were 4^k times nearer than it is: a level's ring
// lies 2^k times farther out than level 0's, so this puts coarse chunks ahead of full detail at
// the same angular size. The far view is cheap (a few hundred chunks per level) and a missing
// root is a hole, while a missing fine chunk only leaves its coarse parent drawn a while longer.
glm::dvec3 lod_priority_position(world::LodCoord c, const glm::dvec3& viewer);

// Pool: the generator's coarse chunk (world::generate_lod: the terrain makes it directly).
class LodGenerateJob final : public Job {
public:
    LodGenerateJob(LodJobEvents& owner, world::LodCoord c, const world::ChunkGenerator& gen,
                   const world::BlockRegistry& registry, const glm::dvec3& viewer)
        : Job(lod_job_key(c, JobKind::Generate)), m_owner(owner), m_gen(gen), m_registry(registry), m_viewer(viewer) {}
    void run(JobContext& ctx) override;
    void complete() override;
    glm::dvec3 priority_position() const override { return lod_priority_position(lod_of(key()), m_viewer); }

private:
    LodJobEvents& m_owner;
    const world::ChunkGenerator& m_gen;
    const world::BlockRegistry& m_registry; // Opacity for the vote of levels built by downsampling.
    glm::dvec3 m_viewer;
    std::optional<world::Chunk> m_chunk;
    std::string m_error;
};

// I/O lane: the stored coarse chunk; a miss hands over to `fallback` (the chunk's LodGenerateJob)
// from the I/O thread. A corrupt record (the store moved it aside) is derived from the levels
// below and saved, never generated: coarse records lie over edited blocks (world/store/lod_load.h),
// and the moved record would have read as a miss from then on; `overlay` (may be null): level-0
// chunks edited in memory, maybe unsaved (see LodDeriveJob), read before the store's. A store
// failure reports an error: nothing is generated in place of what may be stored.
class LodLoadJob final : public Job {
public:
    LodLoadJob(LodJobEvents& owner, world::LodCoord c, world::ChunkStore& store, const world::ChunkGenerator& gen,
               const world::BlockRegistry& registry, std::unique_ptr<Job> fallback,
               std::unique_ptr<const world::LodOverlay> overlay = nullptr)
        : Job(lod_job_key(c, JobKind::Load)), m_owner(owner), m_store(store), m_gen(gen), m_registry(registry),
          m_fallback(std::move(fallback)), m_overlay(std::move(overlay)) {}
    void run(JobContext& ctx) override;
    void complete() override;
    std::unique_ptr<Job> take_continuation() override;

private:
    void derive_corrupt();

    LodJobEvents& m_owner;
    world::ChunkStore& m_store;
    const world::ChunkGenerator& m_gen;
    const world::BlockRegistry& m_registry;
    std::unique_ptr<Job> m_fallback;
    std::unique_ptr<const world::LodOverlay> m_overlay;
    std::optional<world::Chunk> m_chunk;
    std::string m_error;
    bool m_done = false; // Found, or the store failed: no fallback.
};

// I/O lane: a coarse chunk the store marks stale (a level-0 edit under it was saved after it):
// re-derived from the levels below (world::load_or_derive_lod); with `save`, what was rebuilt
// is saved, which clears its marks. Without (chunks marked stale in this session, whose level-0
// edits may not all be saved yet): the marks stay for the next session to derive from. `overlay`
// (may be null): copies of level-0 chunks edited in memory, read before the store's. A store
// failure reports an error.
class LodDeriveJob final : public Job {
public:
    LodDeriveJob(LodJobEvents& owner, world::LodCoord c, world::ChunkStore& store, const world::ChunkGenerator& gen,
                 const world::BlockRegistry& registry, std::shared_ptr<const world::LodDirtySet> dirty, bool save,
                 std::unique_ptr<const world::LodOverlay> overlay = nullptr)
        : Job(lod_job_key(c, JobKind::Load)), m_owner(owner), m_store(store), m_gen(gen), m_registry(registry),
          m_dirty(std::move(dirty)), m_save(save), m_overlay(std::move(overlay)) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    LodJobEvents& m_owner;
    world::ChunkStore& m_store;
    const world::ChunkGenerator& m_gen;
    const world::BlockRegistry& m_registry;
    std::shared_ptr<const world::LodDirtySet> m_dirty;
    bool m_save;
    std::unique_ptr<const world::LodOverlay> m_overlay;
    std::optional<world::Chunk> m_chunk;
    std::string m_error;
};

// I/O lane: marks the coarse ancestors of an edited chunk above the levels kept in memory as
// stale (ChunkStore::mark_lod_dirty), so a later view that loads them re-derives them.
class LodMarkDirtyJob final : public Job {
public:
    LodMarkDirtyJob(world::ChunkCoord edited, world::ChunkStore& store, std::vector<world::LodCoord> coords)
        : Job({edited, JobKind::IoTask, kMarkLevel}), m_store(store), m_coords(std::move(coords)) {}
    void run(JobContext& ctx) override;
    void complete() override {}

private:
    static constexpr uint8_t kMarkLevel = 0xFF; // Keys apart from every chunk's.
    world::ChunkStore& m_store;
    std::vector<world::LodCoord> m_coords;
};

// Pool: meshes a coarse chunk with air on all six sides. Every border face is drawn, so where a
// coarse chunk meets a finer level the seam is closed: its cells are solid wherever a block under
// them is, so a ray that reaches the border through the finer level's air meets a face.
class LodMeshJob final : public Job {
public:
    LodMeshJob(LodJobEvents& owner, world::LodCoord c, world::Chunk chunk, const world::BlockRegistry& registry,
               const glm::dvec3& viewer)
        : Job(lod_job_key(c, JobKind::Mesh)), m_owner(owner), m_chunk(std::move(chunk)), m_registry(registry),
          m_viewer(viewer) {}
    void run(JobContext& ctx) override;
    void complete() override;
    glm::dvec3 priority_position() const override { return lod_priority_position(lod_of(key()), m_viewer); }

private:
    LodJobEvents& m_owner;
    world::Chunk m_chunk;
    const world::BlockRegistry& m_registry;
    glm::dvec3 m_viewer;
    world::ChunkMesh m_mesh;
};

// I/O lane: queues an edited coarse chunk in the store (save_lod; the store commits it with the
// level-0 edits' transactions). Never skipped once submitted.
class LodSaveJob final : public Job {
public:
    LodSaveJob(LodJobEvents& owner, world::LodCoord c, world::Chunk chunk, world::ChunkStore& store)
        : Job(lod_job_key(c, JobKind::Save)), m_owner(owner), m_chunk(std::move(chunk)), m_store(store) {}
    void run(JobContext& ctx) override;
    void complete() override;

private:
    LodJobEvents& m_owner;
    world::Chunk m_chunk;
    world::ChunkStore& m_store;
    std::string m_error;
};

} // namespace vx::engine
