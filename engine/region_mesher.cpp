#include "engine/region_mesher.h"

#include <chrono>
#include <memory>
#include <utility>
#include <unordered_set>

#include "engine/job_batch.h"
#include "world/base/assert.h"

namespace vx::engine {
namespace {

// Pool: builds the apron of one chunk and meshes it into its output slot. Reads the World, and
// writes the slot, only while the batch that submitted it blocks the main thread
// (RegionMesher::mesh), so neither the chunk nor the result is copied: a 13 KB apron copied back
// and forth per chunk cost more main-thread time than the job system itself.
class RegionMeshJob final : public Job {
public:
    RegionMeshJob(const world::World& world, world::ChunkCoord c, const RegionMeshInfo& info, world::MeshedChunk& slot)
        : Job({c, JobKind::Mesh}), m_world(world), m_info(info), m_slot(slot) {}

    void run(JobContext& ctx) override {
        if (ctx.is_cancelled())
            return;
        // One greedy mesher (and its scratch) per worker thread, reused by every job it runs.
        thread_local world::GreedyMesher scratch;
        mesh_chunk(m_world, key().chunk, m_info, scratch, m_slot);
    }
    void complete() override {}

private:
    const world::World& m_world;
    const RegionMeshInfo& m_info;
    world::MeshedChunk& m_slot;
};

} // namespace

RegionMeshStats RegionMesher::mesh(const world::World& world, const std::vector<world::ChunkCoord>& coords,
                                   world::MeshMap& meshes) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    // Every output slot exists before any job runs: the map is not rehashed or erased while
    // workers write their own slots (unordered_map keeps element addresses stable).
    std::vector<std::pair<world::ChunkCoord, world::MeshedChunk*>> slots;
    slots.reserve(coords.size());
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> seen;
    for (world::ChunkCoord c : coords)
        if (world.find_chunk(c) && seen.insert(c).second)
            slots.emplace_back(c, &meshes[c]);
    std::vector<std::unique_ptr<Job>> batch;
    batch.reserve(slots.size());
    for (auto& [c, slot] : slots)
        batch.push_back(std::make_unique<RegionMeshJob>(world, c, m_info, *slot));
    const BatchStats b = run_batch(m_jobs, std::move(batch));
    VX_ASSERT(b.completed == slots.size()); // Distinct keys, nothing cancels a blocking batch.
    RegionMeshStats stats;
    stats.chunks = slots.size();
    for (const auto& [c, slot] : slots)
        stats.quads += slot->mesh.quad_count();
    stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return stats;
}

void RegionMesher::mesh_one(const world::World& world, world::ChunkCoord c, world::MeshMap& meshes) {
    if (world.find_chunk(c))
        mesh_chunk(world, c, m_info, m_main_scratch, meshes[c]);
}

void mesh_chunk(const world::World& world, world::ChunkCoord c, const RegionMeshInfo& info,
                world::GreedyMesher& scratch, world::MeshedChunk& out) {
    const world::Chunk* chunk = world.find_chunk(c);
    VX_ASSERT(chunk != nullptr);
    out.apron = info.apron == ApronMode::Air ? world::Apron::air() : world::make_apron(world, c);
    const world::MesherInput in{*chunk, out.apron, world.registry()};
    if (info.mesh_fn)
        info.mesh_fn(scratch, in, out.mesh);
    else
        scratch.mesh(in, out.mesh);
}

std::vector<world::ChunkCoord> chunk_coords(const world::World& world) {
    std::vector<world::ChunkCoord> coords;
    coords.reserve(world.chunk_count());
    world.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) { coords.push_back(c); });
    return coords;
}

} // namespace vx::engine
