#pragma once
// Procedural terrain: a pure function (seed, chunk coordinate) -> Chunk.
//
// Hills and mountains from a 2D fBm heightmap, a sea at sea_level, grass / dirt / sand / snow
// surfaces, tunnels where two 3D noises are both near zero (the intersection of two noise
// iso-surfaces makes long worm-like tubes), rare crystal clusters (glass and mirror) lining cave
// floors and ceilings, and a few lamps on cave floors. Blocks are ids of
// BlockRegistry::default_registry(), looked up by name.
//
// Determinism: the output depends only on (seed, params, chunk coordinate); there is no global
// or shared mutable state, all randomness is integer hashing of world positions (noise.h), and
// every feature is decided per block from world-position functions, so neighbouring chunks agree
// at their borders however they are generated.
//
// Cost: the noise fields are evaluated sparsely (heights every 4 blocks in x and z, cave
// densities every 4 blocks in x, y, z) and interpolated; multilinear interpolation never leaves
// the range of its samples, so a chunk entirely above the terrain and the sea, entirely under
// water, or entirely below the surface soil with no cave sample under the threshold is returned
// as a uniform chunk without touching its 32768 blocks.
//
// Levels of detail: generate_coarse() makes a level-k chunk (world/lod/) from the same height
// samples without generating its blocks. The surface height is already the bilinear
// interpolation of samples every 4 blocks, so the exact height of every column under a coarse
// cell is cheap (no noise per column), and the coarse solid cells are exactly those of
// downsampling the generated blocks, except that caves are not carved: a cell holding only
// cave air (or a cave's lamps and crystals, which never rise above the surface) is solid. So
// coarse ground never lies below fine ground, and lies less than one cell above the highest
// block under each cell column, as with downsample(), except over cave mouths, which coarse
// chunks plug (there it is higher by the mouth's depth); cave interiors are solid.

#include <cstdint>

#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/coords.h"
#include "world/gen/chunk_generator.h"

namespace vx::world {

struct TerrainParams {
    int sea_level = 0;        // Highest water block, world y.
    int base_height = 2;      // Mean height of the lowlands, world y.
    float hill_amplitude = 48.f; // About a third of the surface ends up under the sea.
    float mountain_amplitude = 110.f; // Added where the mountain mask is 1.
    int snow_line = 78;       // Surfaces at or above this (jittered by up to 4) are snow.
    int soil_depth = 3;       // Dirt (or sand) blocks under the surface block.
    int cave_bottom = -160;   // No caves below this world y (uniform stone down there)...
    int cave_top = 40;        // ... nor above this one (mountains stay whole).
    float cave_radius = 0.15f; // Tunnel thickness in noise units (larger: wider tunnels).
    int crystal_cell_bits = 4;  // One crystal-cluster candidate per (2^bits)^3 cell...
    int crystal_rarity = 10;    // ... with probability 1 / crystal_rarity.
    int lamp_rarity = 160;      // One cave-floor block in this many gets a lamp.
};

// Not thread-safe to construct; generate(), generate_coarse() and surface_height() are const
// and thread-safe.
class TerrainGenerator final : public ChunkGenerator {
public:
    explicit TerrainGenerator(uint64_t seed, TerrainParams params = {});

    // The chunk at `c`. Pure: equal inputs give equal chunks (operator==) on any thread.
    int coarse_levels() const override { return kMaxDirectLevel; }
    Chunk generate(ChunkCoord c) const override;

    // Levels 1..kMaxDirectLevel: the level-c.level chunk at c.chunk, as described above; ids by
    // downsample()'s vote (each block column under a cell votes for its topmost non-air block in
    // the cell; the class by majority, water against opaque ids, ties to opaque; then most votes
    // within it, ties to the smaller id), counted over block columns. Cost: the height
    // noise every 4 blocks over the chunk's footprint ((8 * 2^k + 1)² samples) and one bilinear
    // height per block column under cells near the surface ((32 * 2^k)² at most). Coarser
    // levels return false (generate_lod() then builds them from 8 level-6 chunks each).
    bool generate_coarse(LodCoord c, Chunk& out) const override;
    static constexpr int kMaxDirectLevel = 6;

    // Surface height (world y of the topmost terrain block, before caves) of column (x, z).
    int surface_height(int64_t x, int64_t z) const;
    // Bounds of surface_height() over every column, world y (from the params alone, with a
    // little margin): every surface block of any seed lies in [height_min(), height_max()].
    int64_t height_min() const;
    int64_t height_max() const;

    uint64_t seed() const { return m_seed; }
    const TerrainParams& params() const { return m_params; }

    // Block ids used (from the default registry).
    struct Ids {
        BlockId stone, dirt, grass, sand, water, snow, glass, mirror, lamp;
    };
    const Ids& ids() const { return m_ids; }

private:
    struct Columns;
    struct Caves;
    struct SurfaceIds {
        BlockId top, under; // The surface block and the soil_depth blocks below it.
    };
    struct CoarseGrid;
    float coarse_height(int64_t x, int64_t z) const;
    SurfaceIds surface_ids(int h, int64_t x, int64_t z) const;
    void coarse_column(CoarseGrid& g, int cx, int cz, BlockId* dense) const;
    void fill_grid(ChunkCoord c, Columns& cols) const;
    void fill_columns(ChunkCoord c, Columns& cols) const;
    bool fill_caves(ChunkCoord c, int top_y, Caves& caves) const;
    float cave_threshold(int64_t y) const;
    bool is_terrain_solid(BlockId id) const;
    bool solid_at(const Columns& cols, const Caves& caves, int64_t y0, int x, int y, int z) const;
    void fill_blocks(ChunkCoord c, const Columns& cols, const Caves* caves, BlockId* ids) const;
    void place_crystals(ChunkCoord c, const Columns& cols, const Caves& caves, BlockId* ids) const;

    uint64_t m_seed;
    TerrainParams m_params;
    Ids m_ids{};
    uint32_t m_terrain_mask = 0; // Bit per terrain block id (all default ids are < 32).
};

// Convenience: TerrainGenerator(seed).generate(c). Thread-safe.
Chunk generate_terrain_chunk(uint64_t seed, ChunkCoord c);

} // namespace vx::world
