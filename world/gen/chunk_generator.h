#pragma once
// Where chunks come from when no store holds them: a pure function chunk coordinate -> Chunk.
// The streaming engine calls it from its pool workers, several chunks at once, so an
// implementation must be thread-safe through const (no mutable state, or its own locking).
// TerrainGenerator is the built-in one; a game brings its own (through the facade's
// vx::Generator, adapted in engine/) or implements this directly.

#include "world/base/result.h"
#include "world/chunk.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

namespace vx::world {

class ChunkGenerator {
public:
    virtual ~ChunkGenerator() = default;

    // Thread-safe (called concurrently from worker threads). The chunk at `c`; block ids are the
    // engine registry's. Should be deterministic: a chunk dropped unedited is generated again
    // when the viewer returns, and its neighbours were meshed against the first result.
    virtual Chunk generate(ChunkCoord c) const = 0;
    // Thread-safe. generate(c), or an error (one line) when this generator could not make chunk
    // `c`: a game's generator that threw (engine/world_setup.h). The streamer calls this one; the
    // built-in generators never fail.
    virtual Result<Chunk> try_generate(ChunkCoord c) const { return generate(c); }
    // Thread-safe. Levels of detail (world/lod/): writes the level-c.level chunk at c.chunk
    // (1 <= c.level <= kMaxLodLevel) to `out` without generating the blocks under it and returns
    // true, or returns false (the default) when this generator does not offer coarse chunks (or
    // not this one). Then generate_lod() (world/lod/downsample.h) builds it from its children,
    // down to 8^k generate() calls for a level-k chunk (512 at level 3, 4,096 at level 4). An
    // implementation keeps downsample()'s guarantee: a cell is non-air if any block under it
    // would be (it may add cells, never drop one), so coarse ground never lets a ray through.
    virtual bool generate_coarse(LodCoord c, Chunk& out) const {
        (void)c;
        (void)out;
        return false;
    }
    // Thread-safe. The highest level generate_coarse() makes (0: none): the engine keeps coarser
    // levels it would have to build from 8^k generated chunks out of its views.
    virtual int coarse_levels() const { return 0; }
};

} // namespace vx::world
