#pragma once
// A coarse chunk for the engine's load job (levels of detail, issue 16): the stored chunk while it
// is current, re-derived from the levels below when edits made it stale, generated when nothing
// is stored.
//
// The rule for the level-k chunk c (k >= 1):
//   - stored and not in `dirty`: returned as stored;
//   - in `dirty` (a level-0 edit under it was saved, ChunkStore::mark_lod_dirty), or its record is
//     corrupt (the store moved it aside): rebuilt by downsample() from its 8 children, each made
//     by this same rule; a level-0 child is the store's chunk, or the generator's (try_generate)
//     where none is stored or its record was corrupt (as the streamer does), unless the caller's
//     `overlay` holds a newer one (edited in memory, not saved yet). A corrupt coarse
//     record is re-derived, not regenerated: coarse chunks are stored over edited blocks, which
//     generation would hide;
//   - neither stored nor dirty: generate_lod() (nothing edited under it, as long as every level-0
//     edit's save marks all its coarse ancestors dirty with it).
// Only the dirty and corrupt chunks are descended into: a dirty level-k chunk over one edit costs
// k levels of 8 loads (stored siblings) or generate_lod() calls (absent ones).
//
// Failures: a store error (the server away, the disk failing) or a generator error returns that
// error, naming the chunk; never terrain made up in place of a chunk that could not be read.
// Thread affinity: calls the store, so the store's thread only (the I/O lane); the generator runs
// on the same thread (ChunkGenerator is thread-safe, so any thread would do).

#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "world/base/result.h"
#include "world/chunk.h"
#include "world/gen/chunk_generator.h"
#include "world/lod/lod_coords.h"
#include "world/store/chunk_store.h"

namespace vx::world {

// Coarse chunks marked dirty (ChunkStore::list_lod_dirty(), kept up to date by the caller).
using LodDirtySet = std::unordered_set<LodCoord, LodCoordHash>;

// Every coarse chunk a load_or_derive_lod() call rebuilt (dirty or corrupt ones, the requested
// chunk included when it was), children before parents: the caller saves them with save_lod(),
// which clears their dirty marks, and drops them from its dirty set.
using LodDerived = std::vector<std::pair<LodCoord, Chunk>>;

// Saves every chunk of `derived` in one batch (clearing their dirty marks). Store's thread only.
Status save_derived(ChunkStore& store, const LodDerived& derived);

// Level-0 chunks newer than the store's (edited in memory, maybe not saved yet): a derivation
// that reaches one of them reads it here instead of the store.
using LodOverlay = std::unordered_map<ChunkCoord, Chunk, ChunkCoordHash>;

// The chunk at `c` by the rule above (level 0: `overlay`'s chunk, else the store's, else the
// generator's). `derived` and `overlay` may be null. `registry`: the opacity downsample() votes
// by (the world's registry).
Result<Chunk> load_or_derive_lod(ChunkStore& store, const ChunkGenerator& gen, LodCoord c,
                                 const LodDirtySet& dirty, LodDerived* derived = nullptr,
                                 const LodOverlay* overlay = nullptr,
                                 const BlockRegistry& registry = BlockRegistry::default_registry());

} // namespace vx::world
