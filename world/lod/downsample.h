#pragma once
// Downsampling (issue 16): a level-k chunk from its 8 level-(k-1) children (lod_coords.h).
//
// The rule, per coarse cell over the 2×2×2 sub-cells under it:
//   - Solid if any sub-cell is non-air; air only if all 8 are. Air never wins, so coarse ground
//     lies on or outside the fine ground, within one cell of it (a ray may stop early at a point
//     less than a cell from fine ground, never pass through; along a grazing ray the early stop
//     can be far longer: lod_raycast_test measures both), and nothing is invented (a coarse cell
//     is non-air only if something under it is). Applied level after level, a level-k cell is
//     non-air exactly when one of the (2^k)³ blocks under it is. Water and every other drawn
//     block count as solid.
//   - The id: each of the 4 sub-columns votes for its topmost non-air sub-cell, in two stages
//     (CellVote, cell_vote.h; the terrain's direct coarse levels elect the same way). First the
//     class, by majority: opaque tops against see-through ones (water, glass: not
//     BlockRegistry::is_opaque), ties to opaque. Then the id with the most votes within that
//     class, ties going to the smaller id. A surface is what is seen from above, so a hillside
//     keeps its grass (the dirt under a grass block never outvotes it, however many dirt blocks
//     the cell holds), and a beach cell half water, half sand stays one of the two. The class
//     stage is for coasts: a plain plurality let water (one id) win a cell whose columns are
//     mostly land split over grass, sand and dirt, and the ground seen through the water sank.
//     (Land columns of a cell where water holds the majority still sink: one id per cell.) The
//     most frequent id would turn a thin surface layer into what lies beneath it; Cubyz's most
//     exposed sub-cell keeps surfaces too but reads neighbours across chunk borders, while the
//     vote needs only the 8 sub-cells. The class never decides whether a cell is air: the rule
//     above is untouched.
//
// Cost: the work is on palette indices (one unpack per child, a table says which entries are
// air, opaque or see-through: one is_opaque() per palette entry), ids are looked up once per
// output cell, or once per vote where the 4 tops differ; a uniform child fills its octant without reading anything, and 8 equal uniform
// children give a uniform chunk at once.
// Thread-safe: pure functions of their arguments.

#include <span>

#include "world/base/result.h"
#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/gen/chunk_generator.h"
#include "world/lod/lod_coords.h"

namespace vx::world {

// `registry` in every function below says which ids are see-through (the class stage of the vote);
// it must outlive the call. The engine's LOD streamer and scene loader pass their world's; the
// default registry is the one the terrain generator's ids come from. Every path that builds or
// refreshes the same chunk must pass the same registry, or their ids may differ (which cells are
// air never depends on it).

// The level-k chunk whose children (level k-1, order of lod_child()) are `children`, none null.
Chunk downsample(std::span<const Chunk* const, kLodChildren> children,
                 const BlockRegistry& registry = BlockRegistry::default_registry());

// Writes the 16³ cells that `child` (child number `octant` of its parent, 0..7) contributes to its
// parent: out[local_index(cell)] for the cells of that octant; other entries are untouched.
// `out` holds kChunkVolume ids.
void downsample_octant(const Chunk& child, int octant, std::span<BlockId> out,
                       const BlockRegistry& registry = BlockRegistry::default_registry());

// After `child` (child number `octant` of `parent`) changed: rewrites that octant of `parent`
// and returns whether any of its cells changed. An edit climbs the levels while this returns
// true: a level that did not change leaves every coarser one as it was (Voxy's rule). Costs
// about one downsample_octant() and one Chunk::from_dense().
bool refresh_octant(Chunk& parent, const Chunk& child, int octant,
                    const BlockRegistry& registry = BlockRegistry::default_registry());

// The level-c.level chunk at c.chunk built from generated blocks: 8^level generate() calls
// (try_generate(), so a game's generator that throws reaches the caller as the first error),
// downsampled level by level, depth first (memory: 8 chunks per level). This is what an engine
// does for a generator that does not offer generate_coarse(): 512 level-0 chunks per level-3
// chunk, 4,096 per level 4. Also the reference the direct coarse terrain is tested against.
Result<Chunk> downsample_generated(const ChunkGenerator& gen, LodCoord c,
                                   const BlockRegistry& registry = BlockRegistry::default_registry());

// A level-c.level chunk for the engine: gen.generate_coarse() when the generator offers it,
// otherwise downsample_generated() (level 0: try_generate()).
Result<Chunk> generate_lod(const ChunkGenerator& gen, LodCoord c,
                           const BlockRegistry& registry = BlockRegistry::default_registry());

} // namespace vx::world
