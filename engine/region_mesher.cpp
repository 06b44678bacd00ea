#include "engine/region_mesher.h"

#include <memory>
#include <unordered_set>

#include "engine/job_batch.h"
#include "world/base/assert.h"

namespace vx::engine {
namespace {

// Pool: builds the apron of one chunk and meshes it. Reads the World only while the batch that
// submitted it blocks the main thread (RegionMesher::mesh), so the chunk is not copied.
class RegionMeshJob final : public Job {
public:
    RegionMeshJob(const world::World& world, world::ChunkCoord c, const RegionMeshInfo& info,
                  world::MeshMap& meshes, uint64_t& quads)
        : Job({c, JobKind::Mesh}), m_world(world), m_info(info), m_meshes(meshes), m_quads(quads) {}

    void run(JobContext& ctx) override {
        if (ctx.is_cancelled())
            return;
        // One greedy mesher (and its scratch) per worker thread, reused by every job it runs.
        thread_local world::GreedyMesher scratch;
        mesh_chunk(m_world, key().chunk, m_info, scratch, m_out);
    }

    void complete() override {
        m_quads += m_out.mesh.quad_count();
        m_meshes[key().chunk] = std::move(m_out);
    }

private:
    const world::World& m_world;
    const RegionMeshInfo& m_info;
    world::MeshMap& m_meshes;
    uint64_t& m_quads;
    world::MeshedChunk m_out;
};

} // namespace

RegionMeshStats RegionMesher::mesh(const world::World& world, const std::vector<world::ChunkCoord>& coords,
                                   world::MeshMap& meshes) {
    RegionMeshStats stats;
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> seen;
    std::vector<std::unique_ptr<Job>> batch;
    batch.reserve(coords.size());
    for (world::ChunkCoord c : coords)
        if (world.find_chunk(c) && seen.insert(c).second)
            batch.push_back(std::make_unique<RegionMeshJob>(world, c, m_info, meshes, stats.quads));
    const BatchStats b = run_batch(m_jobs, std::move(batch));
    stats.chunks = b.completed;
    stats.seconds = b.seconds;
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
