// Levels of detail, world side (issue 16): coordinates and downsampling. Coarse chunks from
// generators (direct coarse terrain): lod_coarse_terrain_test.cpp.

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <random>
#include <unordered_set>
#include <vector>

#include <gtest/gtest.h>

#include "lod_test_util.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/lod/lod_coords.h"

namespace vx::world {
namespace {

constexpr uint64_t kSeed = 42;

using test::dense_of;
using test::pointers;

// The id rule of downsample() written out plainly, straight from dense ids: each of the 4
// sub-columns votes for its topmost non-air sub-cell; the class (opaque or see-through in the
// default registry) with more votes wins, ties to opaque; then most votes within it, ties to the
// smaller id.
BlockId oracle_cell(const std::vector<BlockId>& child, int cx, int cy, int cz) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    std::vector<BlockId> votes;
    for (int dz = 0; dz < 2; ++dz)
        for (int dx = 0; dx < 2; ++dx)
            for (int dy = 1; dy >= 0; --dy) {
                const BlockId b = child[size_t(local_index(2 * cx + dx, 2 * cy + dy, 2 * cz + dz))];
                if (b != kAir) {
                    votes.push_back(b);
                    break;
                }
            }
    const long clear = std::count_if(votes.begin(), votes.end(), [&](BlockId v) { return !reg.is_opaque(v); });
    const bool want_opaque = 2 * clear <= long(votes.size());
    BlockId best = kAir;
    long best_n = 0;
    for (BlockId v : votes) {
        if (reg.is_opaque(v) != want_opaque)
            continue;
        const long n = std::count(votes.begin(), votes.end(), v);
        if (n > best_n || (n == best_n && v < best)) {
            best = v;
            best_n = n;
        }
    }
    return best;
}

// ---- Coordinates ----

TEST(LodCoords, ParentChildOctantRoundTrip) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> coord(-100000, 100000);
    for (int t = 0; t < 2000; ++t) {
        const int level = t % kMaxLodLevel; // 0..kMaxLodLevel-1: each has a parent.
        const LodCoord c{level, ChunkCoord(coord(rng), coord(rng), coord(rng))};
        const LodCoord parent = lod_parent(c);
        EXPECT_EQ(parent.level, level + 1);
        EXPECT_EQ(lod_child(parent, lod_octant(c)), c);
        EXPECT_EQ(lod_ancestor(c, level + 1), parent);
        EXPECT_EQ(lod_ancestor(c, level), c);
        // The parent's box holds the child's, at the octant's offset.
        const LodBlockBox pb = lod_block_box(parent), cb = lod_block_box(c);
        const int o = lod_octant(c);
        const BlockPos half(lod_chunk_blocks(level));
        EXPECT_EQ(cb.min, pb.min + BlockPos(o & 1, (o >> 1) & 1, o >> 2) * half);
        EXPECT_EQ(cb.max - cb.min, half - int64_t(1));
        // Every child of c is a chunk whose parent is c.
        if (level >= 1)
            for (int i = 0; i < kLodChildren; ++i) {
                EXPECT_EQ(lod_parent(lod_child(c, i)), c);
                EXPECT_EQ(lod_octant(lod_child(c, i)), i);
            }
    }
}

TEST(LodCoords, BlocksMapToTheirChunkAndCell) {
    std::mt19937 rng(8);
    std::uniform_int_distribution<int64_t> coord(-(int64_t(1) << 34), int64_t(1) << 34);
    for (int t = 0; t < 2000; ++t) {
        const int level = t % (kMaxLodLevel + 1);
        const BlockPos p(coord(rng), coord(rng), coord(rng));
        const LodCoord c = lod_chunk_of(p, level);
        const LodBlockBox box = lod_block_box(c);
        ASSERT_TRUE(glm::all(glm::greaterThanEqual(p, box.min)) && glm::all(glm::lessThanEqual(p, box.max)));
        // The cell's corner: origin + cell size * local cell, and the block lies inside that cell.
        const LocalPos l = lod_local_of(p, level);
        const BlockPos cell_min = lod_origin(c) + BlockPos(l) * lod_cell_size(level);
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, cell_min)) &&
                    glm::all(glm::lessThan(p, cell_min + lod_cell_size(level))));
        // Level 0 is the ordinary chunk grid.
        if (level == 0) {
            EXPECT_EQ(c.chunk, chunk_of(p));
            EXPECT_EQ(l, local_of(p));
        }
    }
    // Negative coordinates floor: block -1 is in chunk -1 at every level, in its last cell.
    for (int level = 0; level <= kMaxLodLevel; ++level) {
        EXPECT_EQ(lod_chunk_of(BlockPos(-1), level).chunk, ChunkCoord(-1));
        EXPECT_EQ(lod_local_of(BlockPos(-1), level), LocalPos(kChunkSize - 1));
    }
    EXPECT_EQ(lod_cell_size(3), 8);
    EXPECT_EQ(lod_chunk_blocks(4), 512);
    EXPECT_EQ(lod_origin({2, ChunkCoord(-1, 0, 3)}), BlockPos(-128, 0, 384));
}

TEST(LodCoords, HashSeparatesLevelsAndNeighbours) {
    std::unordered_set<LodCoord, LodCoordHash> seen;
    for (int level = 0; level <= 4; ++level)
        for (int z = -4; z < 4; ++z)
            for (int y = -2; y < 2; ++y)
                for (int x = -4; x < 4; ++x)
                    seen.insert({level, ChunkCoord(x, y, z)});
    EXPECT_EQ(seen.size(), size_t(5 * 8 * 4 * 8));
    // Same chunk coordinate on two levels: different keys, and (for this hash) different hashes.
    EXPECT_NE(LodCoordHash{}({0, ChunkCoord(1, 2, 3)}), LodCoordHash{}({1, ChunkCoord(1, 2, 3)}));
}

// ---- Downsampling ----

TEST(Downsample, UniformChildrenShortcut) {
    std::array<Chunk, kLodChildren> kids;
    for (Chunk& k : kids)
        k = Chunk(BlockId(3));
    const Chunk all = downsample(pointers(kids));
    ASSERT_TRUE(all.is_uniform());
    EXPECT_EQ(all.uniform_id(), 3);
    // Uniform children with different ids (air among them) fill their octants.
    for (int i = 0; i < kLodChildren; ++i)
        kids[size_t(i)] = Chunk(BlockId(i));
    const Chunk mixed = downsample(pointers(kids));
    EXPECT_FALSE(mixed.is_uniform());
    for (int i = 0; i < kLodChildren; ++i) {
        const LocalPos base = LocalPos(i & 1, (i >> 1) & 1, i >> 2) * (kChunkSize / 2);
        EXPECT_EQ(mixed.get(base), BlockId(i));
        EXPECT_EQ(mixed.get(base + LocalPos(kChunkSize / 2 - 1)), BlockId(i));
    }
}

// A hillside: surface height rising 1 block per 2 along x, a grass block on top, 3 dirt under
// it, stone below. Every topmost coarse cell of a cell column must be grass at levels 1..3,
// though dirt outnumbers grass in the surface cells (3 dirt blocks under each grass block).
TEST(Downsample, HillsideStaysGrass) {
    constexpr BlockId kStone = 1, kDirt = 2, kGrass = 3;
    std::vector<BlockId> ids(kChunkVolume, kAir);
    for (int z = 0; z < kChunkSize; ++z)
        for (int x = 0; x < kChunkSize; ++x) {
            const int h = 4 + x / 2 + z / 4;
            for (int y = 0; y <= h && y < kChunkSize; ++y)
                ids[size_t(local_index(x, y, z))] = y == h ? kGrass : y >= h - 3 ? kDirt : kStone;
        }
    // Level k from 8 copies of the level-(k-1) chunk (a periodic hillside is fine for the rule).
    Chunk level = Chunk::from_dense(ids);
    for (int k = 1; k <= 3; ++k) {
        std::array<Chunk, kLodChildren> kids;
        for (Chunk& c : kids)
            c = level;
        level = downsample(pointers(kids));
        int tops = 0;
        for (int z = 0; z < kChunkSize; ++z)
            for (int x = 0; x < kChunkSize; ++x) {
                int y = kChunkSize - 1;
                while (y >= 0 && level.get(x, y, z) == kAir)
                    --y;
                // The upper octants hold the copies' tops (y 16..31); the lower ones are capped by
                // the upper copies, so only the top of each column is checked.
                ASSERT_GE(y, 0);
                EXPECT_EQ(level.get(x, y, z), kGrass) << "level " << k << " column " << x << "," << z;
                ++tops;
            }
        EXPECT_EQ(tops, kChunkSize * kChunkSize);
    }
}

TEST(Downsample, VoteAndTieRules) {
    constexpr BlockId kSand = 4, kWater = 5, kDirt = 2, kGrass = 3;
    std::vector<BlockId> ids(kChunkVolume, kAir);
    auto set = [&](int x, int y, int z, BlockId b) { ids[size_t(local_index(x, y, z))] = b; };
    // Cell (0,0,0): two sub-columns water over sand, two sand alone: 2 water, 2 sand -> tie ->
    // the smaller id (sand, 4).
    set(0, 0, 0, kSand), set(0, 1, 0, kWater);
    set(1, 0, 0, kSand), set(1, 1, 0, kWater);
    set(0, 0, 1, kSand), set(1, 0, 1, kSand);
    // Cell (1,0,0): one grass on top of a dirt column, three dirt-only lower blocks: grass 1,
    // dirt 3 -> dirt (most votes; the rule counts columns, not blocks).
    set(2, 0, 0, kDirt), set(2, 1, 0, kGrass);
    set(3, 0, 0, kDirt), set(2, 0, 1, kDirt), set(3, 0, 1, kDirt);
    // Cell (2,0,0): one block of grass at the bottom and nothing else: solid, grass.
    set(4, 0, 0, kGrass);
    // Cell (3,0,0): 4 columns, each with dirt on top of grass: dirt (the topmost wins).
    for (int dz = 0; dz < 2; ++dz)
        for (int dx = 0; dx < 2; ++dx)
            set(6 + dx, 0, dz, kGrass), set(6 + dx, 1, dz, kDirt);
    std::vector<BlockId> out(kChunkVolume, BlockId(999));
    downsample_octant(Chunk::from_dense(ids), 0, out);
    EXPECT_EQ(out[size_t(local_index(0, 0, 0))], kSand);
    EXPECT_EQ(out[size_t(local_index(1, 0, 0))], kDirt);
    EXPECT_EQ(out[size_t(local_index(2, 0, 0))], kGrass);
    EXPECT_EQ(out[size_t(local_index(3, 0, 0))], kDirt);
    EXPECT_EQ(out[size_t(local_index(4, 0, 0))], kAir);
    // Only octant 0 (cells 0..15 on each axis) was written.
    EXPECT_EQ(out[size_t(local_index(16, 0, 0))], BlockId(999));
    EXPECT_EQ(out[size_t(local_index(15, 15, 15))], kAir);
}

// A coast: water is one id, land is split over several, so water can have the most votes of
// any id while most columns are land. The class is chosen first (opaque against see-through, by
// majority, ties to opaque), so the cell stays land and the ground seen through the water does
// not sink. The old plain plurality gave water in cells (0,0,0) and (1,0,0).
TEST(Downsample, CoastLandMajorityBeatsWaterPlurality) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    const BlockId grass = *reg.find("grass"), sand = *reg.find("sand"), dirt = *reg.find("dirt");
    const BlockId water = *reg.find("water"), glass = *reg.find("glass");
    ASSERT_FALSE(reg.is_opaque(water));
    ASSERT_FALSE(reg.is_opaque(glass));
    std::vector<BlockId> ids(kChunkVolume, kAir);
    auto set = [&](int x, int y, int z, BlockId b) { ids[size_t(local_index(x, y, z))] = b; };
    // Cell (0,0,0): water, water, grass, sand: 2 see-through, 2 opaque -> tie -> opaque; grass
    // and sand tie -> the smaller id (grass, 3).
    set(0, 1, 0, water), set(1, 1, 0, water), set(0, 0, 1, grass), set(1, 1, 1, sand);
    // Cell (1,0,0): water over sand, water, sand, dirt (lower sub-cell): 2 against 2 -> opaque;
    // dirt and sand tie -> dirt (2).
    set(2, 0, 0, sand), set(2, 1, 0, water), set(3, 0, 0, water), set(2, 1, 1, sand), set(3, 0, 1, dirt);
    // Cell (2,0,0): 3 water, 1 grass: see-through by majority -> water.
    set(4, 1, 0, water), set(5, 1, 0, water), set(4, 1, 1, water), set(5, 0, 1, grass);
    // Cell (3,0,0): glass, glass, water, grass: 3 see-through -> the plurality within: glass.
    set(6, 1, 0, glass), set(7, 0, 0, glass), set(6, 1, 1, water), set(7, 1, 1, grass);
    std::vector<BlockId> out(kChunkVolume, BlockId(999));
    downsample_octant(Chunk::from_dense(ids), 0, out);
    EXPECT_EQ(out[size_t(local_index(0, 0, 0))], grass);
    EXPECT_EQ(out[size_t(local_index(1, 0, 0))], dirt);
    EXPECT_EQ(out[size_t(local_index(2, 0, 0))], water);
    EXPECT_EQ(out[size_t(local_index(3, 0, 0))], glass);
    // downsample() agrees (octant 0 of the parent from child 0, the others uniform air).
    std::array<Chunk, kLodChildren> kids;
    kids[0] = Chunk::from_dense(ids);
    const Chunk parent = downsample(pointers(kids));
    EXPECT_EQ(parent.get(0, 0, 0), grass);
    EXPECT_EQ(parent.get(2, 0, 0), water);
    // The registry passed decides: in an empty one every id is opaque, so one class, and cell
    // (0,0,0) goes to water by plurality (2 of 4 votes).
    const BlockRegistry all_opaque;
    std::vector<BlockId> plain(kChunkVolume, kAir);
    downsample_octant(Chunk::from_dense(ids), 0, plain, all_opaque);
    EXPECT_EQ(plain[size_t(local_index(0, 0, 0))], water);
    EXPECT_EQ(plain[size_t(local_index(1, 0, 0))], water); // 2 water, 1 sand, 1 dirt.
}

// Random children of several densities and palette widths (up to 300 ids: 9-bit indices take
// the 16-bit unpack path): each parent cell equals the oracle's, so it is solid exactly when a
// sub-cell is, and its id is one present under it.
TEST(Downsample, MatchesOracleOnRandomChunks) {
    std::mt19937 rng(11);
    struct Case {
        double fill;
        int types;
    };
    for (const Case cs : {Case{0.01, 3}, Case{0.3, 2}, Case{0.5, 12}, Case{0.9, 300}, Case{0.999, 5}}) {
        std::array<Chunk, kLodChildren> kids;
        std::array<std::vector<BlockId>, kLodChildren> dense;
        std::bernoulli_distribution solid(cs.fill);
        std::uniform_int_distribution<int> type(1, cs.types);
        for (int i = 0; i < kLodChildren; ++i) {
            dense[size_t(i)].resize(kChunkVolume);
            for (BlockId& b : dense[size_t(i)])
                b = solid(rng) ? BlockId(type(rng)) : kAir;
            kids[size_t(i)] = Chunk::from_dense(dense[size_t(i)]);
        }
        if (cs.types == 300) {
            ASSERT_GT(kids[0].palette()->indices.bits(), 8u);
        }
        const Chunk parent = downsample(pointers(kids));
        int mismatches = 0;
        for (int i = 0; i < kLodChildren; ++i) {
            const LocalPos base = LocalPos(i & 1, (i >> 1) & 1, i >> 2) * (kChunkSize / 2);
            for (int z = 0; z < kChunkSize / 2; ++z)
                for (int y = 0; y < kChunkSize / 2; ++y)
                    for (int x = 0; x < kChunkSize / 2; ++x)
                        mismatches += parent.get(base + LocalPos(x, y, z)) != oracle_cell(dense[size_t(i)], x, y, z);
        }
        EXPECT_EQ(mismatches, 0) << "fill " << cs.fill << " types " << cs.types;
    }
}

// Solid-cell pyramid of a generated region: occupancy at level j is the OR of the 8 cells under
// each cell at level j - 1. The downsampled chain must match it at every level: conservative
// (every solid block's cell is solid at every coarser level) and inventing nothing.
TEST(Downsample, TerrainChainIsConservativeAndInventsNothing) {
    const TerrainGenerator gen(kSeed);
    constexpr int kTop = 3;                        // One level-3 chunk: 8³ level-0 chunks.
    const LodCoord top{kTop, ChunkCoord(1, 0, -1)}; // Blocks y 0..255: hills and the cave band.
    constexpr int kEdge = kChunkSize << kTop;      // 256 blocks.
    const BlockPos origin = lod_origin(top);
    // occ[j]: (kEdge >> j)³ cells, x fastest.
    std::vector<std::vector<uint8_t>> occ(kTop + 1);
    occ[0].assign(size_t(kEdge) * kEdge * kEdge, 0);
    std::vector<Chunk> level; // Chunks of the current level, [z][y][x] over the region.
    const int n0 = 1 << kTop;
    for (int z = 0; z < n0; ++z)
        for (int y = 0; y < n0; ++y)
            for (int x = 0; x < n0; ++x) {
                const ChunkCoord c = chunk_of(origin) + ChunkCoord(x, y, z);
                level.push_back(gen.generate(c));
                const auto d = dense_of(level.back());
                for (int i = 0; i < kChunkVolume; ++i) {
                    const int bx = x * kChunkSize + (i & 31), by = y * kChunkSize + ((i >> 5) & 31),
                              bz = z * kChunkSize + (i >> 10);
                    occ[0][(size_t(bz) * kEdge + size_t(by)) * kEdge + size_t(bx)] = d[size_t(i)] != kAir;
                }
            }
    size_t solid_cells[kTop + 1] = {};
    for (int j = 1; j <= kTop; ++j) {
        const int e = kEdge >> j, pe = e * 2;
        occ[size_t(j)].assign(size_t(e) * e * e, 0);
        for (int z = 0; z < e; ++z)
            for (int y = 0; y < e; ++y)
                for (int x = 0; x < e; ++x) {
                    uint8_t any = 0;
                    for (int o = 0; o < 8; ++o)
                        any |= occ[size_t(j - 1)][(size_t(2 * z + (o >> 2)) * pe + size_t(2 * y + ((o >> 1) & 1))) * pe +
                                                  size_t(2 * x + (o & 1))];
                    occ[size_t(j)][(size_t(z) * e + size_t(y)) * e + size_t(x)] = any;
                }
        // Downsample the chunks of level j - 1 into those of level j.
        const int n = n0 >> j, pn = n * 2;
        std::vector<Chunk> next;
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    std::array<const Chunk*, kLodChildren> kids;
                    for (int i = 0; i < kLodChildren; ++i)
                        kids[size_t(i)] = &level[(size_t(2 * z + (i >> 2)) * pn + size_t(2 * y + ((i >> 1) & 1))) * pn +
                                                 size_t(2 * x + (i & 1))];
                    next.push_back(downsample(kids));
                }
        level = std::move(next);
        int wrong = 0;
        for (int z = 0; z < e; ++z)
            for (int y = 0; y < e; ++y)
                for (int x = 0; x < e; ++x) {
                    const Chunk& c = level[(size_t(z / kChunkSize) * n + size_t(y / kChunkSize)) * n + size_t(x / kChunkSize)];
                    const bool solid = c.get(x % kChunkSize, y % kChunkSize, z % kChunkSize) != kAir;
                    const bool expect = occ[size_t(j)][(size_t(z) * e + size_t(y)) * e + size_t(x)] != 0;
                    wrong += solid != expect;
                    solid_cells[j] += solid;
                }
        EXPECT_EQ(wrong, 0) << "level " << j;
        EXPECT_GT(solid_cells[j], 0u);
    }
    // downsample_generated() builds the same chunk.
    const Result<Chunk> direct = downsample_generated(gen, top);
    ASSERT_TRUE(direct.ok());
    ASSERT_EQ(level.size(), 1u);
    EXPECT_TRUE(*direct == level[0]);
}

// On generated terrain the topmost solid cell of each coarse column shows the surface (grass,
// sand, snow, water, or rock under snow), not the dirt under grass. Caves opening at the
// surface expose dirt in a few columns at level 0 already; coarse levels show about as much.
TEST(Downsample, TerrainSurfaceKeepsItsBlocks) {
    const TerrainGenerator gen(kSeed);
    const auto& ids = gen.ids();
    for (int level = 0; level <= 3; ++level) {
        int dirt = 0, grass = 0, columns = 0;
        std::vector<int> hist(16, 0);
        const int stacks = level == 3 ? 2 : 4; // A level-3 stack is 1,024 generated chunks.
        for (int t = 0; t < stacks; ++t) {
            // A stack of chunks from above the highest peak (y 200) down to y -64.
            const ChunkCoord cc(t - 2, 0, 1 - t);
            std::vector<Chunk> stack;
            const int span = kChunkSize << level;
            for (int y = 200 / span; y >= -64 / span - 1; --y) {
                Result<Chunk> r = downsample_generated(gen, {level, ChunkCoord(cc.x, y, cc.z)});
                ASSERT_TRUE(r.ok());
                stack.push_back(std::move(*r));
            }
            for (int z = 0; z < kChunkSize; ++z)
                for (int x = 0; x < kChunkSize; ++x)
                    for (size_t s = 0; s < stack.size(); ++s) {
                        int y = kChunkSize - 1;
                        while (y >= 0 && stack[s].get(x, y, z) == kAir)
                            --y;
                        if (y < 0)
                            continue;
                        const BlockId b = stack[s].get(x, y, z);
                        dirt += b == ids.dirt;
                        grass += b == ids.grass;
                        ++hist[std::min<size_t>(b, hist.size() - 1)];
                        ++columns;
                        break;
                    }
        }
        std::printf("level %d, topmost ids of %d columns:", level, columns);
        for (size_t b = 0; b < hist.size(); ++b)
            if (hist[b])
                std::printf(" %s %d", BlockRegistry::default_registry().info(BlockId(b)).name.c_str(), hist[b]);
        std::printf("\n");
        EXPECT_EQ(columns, stacks * kChunkSize * kChunkSize);
        EXPECT_GT(grass, columns / 10);
        // Caves opening at the surface leave dirt on top of 1.5% of the columns at level 0.
        EXPECT_LE(dirt, columns / 40) << "level " << level;
    }
}

// Edits climb the levels through refresh_octant(), stopping at the first level that did not
// change; after every edit the chain equals one rebuilt from scratch.
TEST(Downsample, EditsClimbAndStopWhereNothingChanged) {
    const TerrainGenerator gen(kSeed);
    const LodCoord top{2, ChunkCoord(0, 0, 1)};
    std::vector<Chunk> l0(64), l1(8);
    auto child0 = [](int i1, int o) { return size_t(i1 * 8 + o); }; // Level-0 chunk o of level-1 chunk i1.
    for (int i1 = 0; i1 < 8; ++i1)
        for (int o = 0; o < 8; ++o)
            l0[child0(i1, o)] = gen.generate(lod_child(lod_child(top, i1), o).chunk);
    auto rebuild1 = [&](int i1) {
        std::array<const Chunk*, kLodChildren> p;
        for (int o = 0; o < 8; ++o)
            p[size_t(o)] = &l0[child0(i1, o)];
        return downsample(p);
    };
    auto rebuild2 = [&]() {
        std::array<const Chunk*, kLodChildren> p;
        for (int i = 0; i < 8; ++i)
            p[size_t(i)] = &l1[size_t(i)];
        return downsample(p);
    };
    for (int i1 = 0; i1 < 8; ++i1)
        l1[size_t(i1)] = rebuild1(i1);
    Chunk l2 = rebuild2();
    std::mt19937 rng(21);
    std::uniform_int_distribution<int> pick(0, 63), local(0, kChunkSize - 1), block(0, 9);
    int climbed[3] = {};
    for (int t = 0; t < 120; ++t) {
        const int i = pick(rng), i1 = i / 8, o = i % 8;
        const BlockId b = BlockId(block(rng)); // Air, a terrain block or a feature (ids 0..9).
        l0[size_t(i)].set(local(rng), local(rng), local(rng), b);
        int reached = 0;
        if (refresh_octant(l1[size_t(i1)], l0[size_t(i)], o)) {
            reached = 1;
            if (refresh_octant(l2, l1[size_t(i1)], i1))
                reached = 2;
        }
        ++climbed[reached];
        ASSERT_TRUE(l1[size_t(i1)] == rebuild1(i1)) << "edit " << t;
        ASSERT_TRUE(l2 == rebuild2()) << "edit " << t;
    }
    std::printf("120 random edits: stopped at level 0: %d, level 1: %d, reached level 2: %d\n", climbed[0],
                climbed[1], climbed[2]);
    EXPECT_GT(climbed[0], 0); // Some edits change nothing coarser (a hidden block, a vote kept).
    EXPECT_GT(climbed[2], 0); // Some reach the top (a block in the sky, a hole in a surface).
}

} // namespace
} // namespace vx::world
