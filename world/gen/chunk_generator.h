#pragma once
// Where chunks come from when no store holds them: a pure function chunk coordinate -> Chunk.
// The streaming engine calls it from its pool workers, several chunks at once, so an
// implementation must be thread-safe through const (no mutable state, or its own locking).
// TerrainGenerator is the built-in one; a game brings its own (through the facade's
// vx::Generator, adapted in engine/) or implements this directly.

#include "world/base/result.h"
#include "world/chunk.h"
#include "world/coords.h"

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
};

} // namespace vx::world
