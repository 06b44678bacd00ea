#pragma once
// Pregeneration of a terrain world into a store (`vx world gen`): every chunk of a box generated
// and meshed on the job system's pool, then saved on its I/O lane, then (levels of detail, when
// asked) every coarse chunk of levels 1..N over the box made by world::generate_lod (the terrain
// makes them directly, without their blocks) and saved with save_lod, then flushed. Meshing here
// checks that each chunk meshes and measures the world (quads in isolation); the streamer meshes
// again with real neighbours when it streams the world in. Chunks the store already has (edited by
// players, made by an earlier run) are kept, and so are coarse chunks it has or marks stale: a run
// over an existing world only fills in what is missing. The check and the commit are not one
// step, so the save is conditional (ChunkWrite::if_absent): on a shared PostgreSQL world, a chunk
// another process saves in between is kept too (counted in PregenStats::chunks, not kept).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/job_system.h"
#include "world/base/result.h"
#include "world/coords.h"
#include "world/gen/terrain.h"
#include "world/store/chunk_store.h"

namespace vx::engine {

// What to generate. Plain value (not thread-safe).
// The most chunks one pregenerate() call makes (about 10^8: 512 x 512 columns of 256 layers).
inline constexpr int64_t kMaxPregenChunks = int64_t(1) << 26;

struct PregenInfo {
    // Inclusive box of chunk coordinates; lo <= hi per axis, at most kMaxPregenChunks, and a
    // chunk inside the world's outermost layer (each chunk's mesh reads its six neighbours).
    world::ChunkCoord lo{0}, hi{0};
    // Called on the main thread about every 50 ms: chunks saved so far, and the total.
    // Coarse chunks count as chunks here.
    std::function<void(size_t done, size_t total)> progress;
    // Coarse levels to store, 1..lod_levels (0: none; at most kMaxLodLevel): at level k, every
    // level-k chunk overlapping the box (lo >> k .. hi >> k). The store must keep them (supports_lod()).
    // Boxes side by side (`vx world gen --part`) both store the coarse chunks over their border:
    // the same chunk twice, the last writer wins.
    int lod_levels = 0;
};

// What was made. Plain value (not thread-safe).
struct PregenStats {
    size_t chunks = 0;        // Chunks generated and saved (level 0).
    size_t kept = 0;          // Chunks the store had already: left as they were.
    std::vector<size_t> lod_chunks; // Coarse chunks saved per level: [k - 1] for level k.
    size_t lod_kept = 0;      // Coarse chunks stored or marked stale already: left as they were.
    uint64_t non_uniform = 0; // Of the chunks generated (saved or kept), not all one block.
    uint64_t quads = 0;       // Their greedy quads, each chunk meshed in isolation (air around).
    double seconds = 0;       // Wall time, the final flush included.
};

// Main thread of `jobs`; blocks until every chunk is saved and the store flushed. `store` is used
// only from the job system's I/O lane during the call (see chunk_store.h); `gen` and `store` must
// outlive it. Fails with the store's first error (the world may then be partly saved).
Result<PregenStats> pregenerate(JobSystem& jobs, const world::TerrainGenerator& gen, world::ChunkStore& store,
                                const PregenInfo& info);

} // namespace vx::engine
