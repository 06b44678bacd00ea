#include "engine/lod_jobs.h"

#include "world/base/log.h"
#include "world/lod/downsample.h"
#include "world/mesh/apron.h"
#include "world/mesh/mesher.h"
#include "world/store/lod_load.h"

namespace vx::engine {

glm::dvec3 lod_priority_position(world::LodCoord c, const glm::dvec3& viewer) {
    const world::BlockPos o = world::lod_origin(c);
    const double half = double(world::lod_chunk_blocks(c.level)) * 0.5;
    const glm::dvec3 centre(double(o.x) + half, double(o.y) + half, double(o.z) + half);
    const double cell = double(world::lod_cell_size(c.level));
    return viewer + (centre - viewer) / (cell * cell);
}

void LodGenerateJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    Result<world::Chunk> r = world::generate_lod(m_gen, lod_of(key()), m_registry);
    if (r)
        m_chunk = std::move(*r);
    else
        m_error = r.error();
}

void LodGenerateJob::complete() {
    m_owner.on_lod_data(lod_of(key()), std::move(m_chunk),
                        m_chunk || !m_error.empty() ? m_error : std::string("no chunk generated"));
}

void LodLoadJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    Result<world::ChunkLoad> r = m_store.load_lod(lod_of(key()));
    if (!r) {
        m_error = "store failed: " + r.error();
        m_done = true;
        return;
    }
    if (r->state == world::LoadState::Present) {
        m_chunk = std::move(r->chunk);
        m_done = true;
    } else if (r->state == world::LoadState::Corrupt) {
        derive_corrupt();
    }
}

void LodLoadJob::derive_corrupt() {
    m_done = true;
    const world::LodCoord c = lod_of(key());
    world::LodDerived derived;
    Result<world::Chunk> d =
        world::load_or_derive_lod(m_store, m_gen, c, world::LodDirtySet{c}, &derived, m_overlay.get(), m_registry);
    if (!d) {
        m_error = d.error();
        return;
    }
    m_chunk = std::move(*d);
    // Saved even over edits not saved yet (as LodSaveJob saves refreshed levels): unsaved, the
    // moved record would read as a miss, terrain, from then on.
    if (!m_store.read_only()) // A failure only means deriving again next time.
        (void)world::save_derived(m_store, derived);
}

std::unique_ptr<Job> LodLoadJob::take_continuation() { return m_done ? nullptr : std::move(m_fallback); }

void LodLoadJob::complete() {
    if (m_done) // A miss reports through its generate job.
        m_owner.on_lod_data(lod_of(key()), std::move(m_chunk), m_error);
}

void LodDeriveJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    world::LodDerived derived;
    Result<world::Chunk> r =
        world::load_or_derive_lod(m_store, m_gen, lod_of(key()), *m_dirty, &derived, m_overlay.get(), m_registry);
    if (!r) {
        m_error = r.error();
        return;
    }
    m_chunk = std::move(*r);
    if (m_save) // Clears their marks; a failure only means deriving again.
        (void)world::save_derived(m_store, derived);
}

void LodDeriveJob::complete() { m_owner.on_lod_data(lod_of(key()), std::move(m_chunk), m_error); }

void LodMarkDirtyJob::run(JobContext&) {
    if (Status s = m_store.mark_lod_dirty(m_coords); !s)
        VX_LOG_WARN("marking coarse chunks stale failed (%s): they may show an edit late", s.error().c_str());
}

void LodMeshJob::run(JobContext& ctx) {
    if (ctx.is_cancelled())
        return;
    thread_local world::GreedyMesher mesher;
    static const world::Apron kAir = world::Apron::air(); // As the LOD scene loader's.
    mesher.mesh({m_chunk, kAir, m_registry}, m_mesh);
}

void LodMeshJob::complete() { m_owner.on_lod_meshed(lod_of(key()), std::move(m_mesh)); }

void LodSaveJob::run(JobContext&) {
    Status s = m_store.save_lod(lod_of(key()), m_chunk);
    if (!s)
        m_error = s.error();
}

void LodSaveJob::complete() { m_owner.on_lod_saved(lod_of(key()), m_error); }

} // namespace vx::engine
