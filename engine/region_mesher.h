#pragma once
// Batch meshing of a region of a World on the engine's job system: every chunk of a list, each
// with its apron (its neighbours' border layers, or air), one job per chunk on the pool. The
// CLI's `vx mesh`, `vx render` scenes and the benchmarks mesh through this; the streamer meshes
// frame by frame through its own jobs (engine/stream_jobs.h) with the same mesher.

#include <functional>
#include <vector>

#include "engine/job_system.h"
#include "world/mesh/edit_mesher.h"
#include "world/mesh/mesher.h"
#include "world/world.h"

namespace vx::engine {

// Meshes one chunk snapshot into `out` (its storage reused). Called on pool workers, concurrently
// for different chunks: it must be thread-safe for distinct inputs. `scratch` is the calling
// worker's own greedy mesher (scratch memory reused across its jobs), for functions that want it.
using ChunkMeshFn =
    std::function<void(world::GreedyMesher& scratch, const world::MesherInput& in, world::ChunkMesh& out)>;

enum class ApronMode {
    Neighbours, // The apron holds the neighbour chunks' border layers (absent neighbours: air).
    Air,        // Every chunk meshed in isolation, padded with air (the thesis's seed scene).
};

// Creation parameters. Plain value (not thread-safe).
struct RegionMeshInfo {
    ApronMode apron = ApronMode::Neighbours;
    ChunkMeshFn mesh_fn; // Empty: the engine's greedy mesher. Tests and `vx mesh --mesher` pass oracles.
};

// What one batch did. Plain value (not thread-safe).
struct RegionMeshStats {
    size_t chunks = 0;  // Chunks meshed (those of the list present in the world).
    uint64_t quads = 0; // Sum over the meshed chunks.
    double seconds = 0; // Wall time of the batch: output slots, aprons and meshing.
};

// Meshes chunks of a World on a JobSystem. Main thread of `jobs` only (the one that made it).
class RegionMesher {
public:
    // `jobs` must outlive the mesher.
    explicit RegionMesher(JobSystem& jobs, RegionMeshInfo info = {}) : m_jobs(jobs), m_info(std::move(info)) {}

    // Blocks until done. Meshes every chunk of `coords` that `world` holds into meshes[c] (mesh and
    // apron replaced; coords absent from the world are skipped, duplicates meshed once). Workers
    // read `world` while this call blocks: nothing may write it until it returns (the main thread
    // is the only writer, and it is waiting here). The entries of `meshes` are made on this thread
    // first; each job then fills only its own entry (apron, mesh) and no job touches the map's
    // structure. Jobs are keyed
    // {chunk, JobKind::Mesh}: a streamer sharing `jobs` must not be meshing the same chunks.
    RegionMeshStats mesh(const world::World& world, const std::vector<world::ChunkCoord>& coords,
                         world::MeshMap& meshes);

    // Main thread. Meshes one chunk on the calling thread (after an edit, say); no jobs. Does
    // nothing when `world` does not hold `c`.
    void mesh_one(const world::World& world, world::ChunkCoord c, world::MeshMap& meshes);

    const RegionMeshInfo& info() const { return m_info; }

private:
    JobSystem& m_jobs;
    RegionMeshInfo m_info;
    world::GreedyMesher m_main_scratch; // mesh_one's scratch.
};

// Any thread, while nothing writes `world`. Meshes chunk `c`, which `world` must hold, into `out`
// (apron and mesh replaced) on the calling thread, using `scratch` for the greedy mesher.
void mesh_chunk(const world::World& world, world::ChunkCoord c, const RegionMeshInfo& info,
                world::GreedyMesher& scratch, world::MeshedChunk& out);

// Not thread-safe (reads `world`). The chunks of `world`, in no particular order.
std::vector<world::ChunkCoord> chunk_coords(const world::World& world);

} // namespace vx::engine
