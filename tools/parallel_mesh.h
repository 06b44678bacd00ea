#pragma once
// Meshes many chunks on all cores (the CLI's batch path; the engine uses its job system).
// Not thread-safe: call from one thread; it fans out internally and joins before returning.

#include <functional>
#include <vector>

#include "world/mesh/edit_mesher.h"

namespace vx::tools {

// Calls fn(i) for every i in [0, count) on `threads` threads (0 = all cores), the calling thread
// included, claiming indices in batches of `batch`; returns when all are done.
void parallel_for(size_t count, unsigned threads, const std::function<void(size_t)>& fn, size_t batch = 1);

struct MeshJob {
    world::ChunkCoord coord;
    const world::Chunk* chunk;
    world::MeshedChunk* out; // Its apron must be filled in; the mesh is written.
};

enum class MeshMode { Greedy, Culled, Naive };

// Meshes every job using `threads` threads (0 = all cores). Returns seconds spent meshing.
double mesh_parallel(std::vector<MeshJob>& jobs, const world::BlockRegistry& registry, MeshMode mode,
                     unsigned threads);

} // namespace vx::tools
