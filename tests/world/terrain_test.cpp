#include "world/gen/terrain.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "world/gen/noise.h"
#include "world/world.h"

namespace vx::world {
namespace {

constexpr uint64_t kSeed = 42;

// FNV-1a over the dense ids of a chunk.
uint64_t chunk_hash(const Chunk& c) {
    std::vector<BlockId> ids(kChunkVolume);
    c.to_dense(ids);
    uint64_t h = 0xCBF29CE484222325ull;
    for (BlockId id : ids) {
        h = (h ^ (id & 0xFF)) * 0x100000001B3ull;
        h = (h ^ (id >> 8)) * 0x100000001B3ull;
    }
    return h;
}

// 6 x 4 x 6 chunks around the origin, y from -3 to 0 (world y -96..31: sea floor, beaches,
// hills and the upper cave band). Small enough for sanitizer builds to stay fast.
std::vector<ChunkCoord> test_region() {
    std::vector<ChunkCoord> r;
    for (int z = -3; z < 3; ++z)
        for (int y = -3; y <= 0; ++y)
            for (int x = -3; x < 3; ++x)
                r.emplace_back(x, y, z);
    return r;
}

uint64_t region_hash(const std::map<std::tuple<int, int, int>, uint64_t>& per_chunk) {
    uint64_t h = 0;
    for (const auto& [c, v] : per_chunk)
        h = noise::mix64(h ^ v);
    return h;
}

// ---- Noise ----

TEST(Noise, GridMatchesPointwiseBitForBit) {
    const int64_t far = int64_t(1) << 33;
    for (const BlockPos o : {BlockPos(0, 0, 0), BlockPos(-100, -36, 68), BlockPos(far, -far, far + 12)}) {
        constexpr int n = 9;
        noise::Noise3Pair grid[n][n + 1][n];
        noise::gradient_3d_pair_grid(7, o.x, o.y, o.z, 4, n, n + 1, n, 6, 5, &grid[0][0][0]);
        for (int k = 0; k < n; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i < n; ++i) {
                    const auto p = noise::gradient_3d_pair_at(7, o.x + 4 * i, o.y + 4 * j, o.z + 4 * k, 6, 5);
                    ASSERT_EQ(std::memcmp(&p, &grid[k][j][i], sizeof(p)), 0) << i << " " << j << " " << k;
                }
    }
}

TEST(Noise, BoundedSmoothZeroOnLatticeAndSeeded) {
    double sum2 = 0.0, sum3 = 0.0;
    float max2 = 0.0f, max3 = 0.0f, max_step = 0.0f;
    int differ = 0;
    const int count = 20000;
    for (int i = 0; i < count; ++i) {
        const int64_t x = int64_t(noise::hash_coords(1, i) % 100000) - 50000;
        const int64_t z = int64_t(noise::hash_coords(2, i) % 100000) - 50000;
        const float n2 = noise::gradient_2d_at(3, x, z, 6);
        const auto n3 = noise::gradient_3d_pair_at(3, x, z, x + z, 6, 5);
        max2 = std::max(max2, std::abs(n2));
        max3 = std::max({max3, std::abs(n3.a), std::abs(n3.b)});
        sum2 += double(n2) * n2;
        sum3 += double(n3.a) * n3.a;
        // One block is 1/64 of a wavelength: neighbours differ by little (the fade is smooth).
        max_step = std::max(max_step, std::abs(noise::gradient_2d_at(3, x + 1, z, 6) - n2));
        differ += noise::gradient_2d_at(4, x, z, 6) != n2;
        // Zero on lattice points (multiples of the wavelength).
        ASSERT_EQ(noise::gradient_2d_at(3, x * 64, z * 64, 6), 0.0f);
    }
    EXPECT_LE(max2, 1.01f);
    EXPECT_LE(max3, 1.1f);
    EXPECT_GT(max2, 0.5f);
    const double rms2 = std::sqrt(sum2 / count), rms3 = std::sqrt(sum3 / count);
    EXPECT_GT(rms2, 0.15);
    EXPECT_LT(rms2, 0.6);
    EXPECT_GT(rms3, 0.15);
    EXPECT_LT(rms3, 0.6);
    EXPECT_LT(max_step, 0.1f);
    EXPECT_GT(differ, count * 9 / 10);
    // fBm stays normalized.
    for (int i = 0; i < 1000; ++i)
        EXPECT_LE(std::abs(noise::fbm_2d_at(5, i * 37 - 9000, i * 11, 8, 5, 0.5f)), 1.01f);
}

TEST(Terrain, DeterministicAcrossOrderInstancesAndThreads) {
    std::vector<ChunkCoord> region = test_region();
    std::map<std::tuple<int, int, int>, uint64_t> forward, backward, threaded;
    {
        const TerrainGenerator gen(kSeed);
        for (const ChunkCoord& c : region)
            forward[{c.x, c.y, c.z}] = chunk_hash(gen.generate(c));
    }
    {
        const TerrainGenerator gen(kSeed); // A fresh instance, the reverse order.
        for (auto it = region.rbegin(); it != region.rend(); ++it)
            backward[{it->x, it->y, it->z}] = chunk_hash(gen.generate(*it));
    }
    {
        // Two threads sharing one generator, interleaved halves.
        const TerrainGenerator gen(kSeed);
        std::vector<uint64_t> out(region.size());
        auto work = [&](size_t first) {
            for (size_t i = first; i < region.size(); i += 2)
                out[i] = chunk_hash(gen.generate(region[i]));
        };
        std::thread t(work, 1);
        work(0);
        t.join();
        for (size_t i = 0; i < region.size(); ++i)
            threaded[{region[i].x, region[i].y, region[i].z}] = out[i];
    }
    EXPECT_EQ(forward, backward);
    EXPECT_EQ(forward, threaded);
    EXPECT_EQ(region_hash(forward), region_hash(backward));
    // The free function is the same generator.
    const uint64_t one = chunk_hash(generate_terrain_chunk(kSeed, ChunkCoord(1, -1, 2)));
    EXPECT_EQ(one, (forward[{1, -1, 2}]));
}

TEST(Terrain, DifferentSeedsDiffer) {
    const TerrainGenerator a(kSeed), b(kSeed + 1);
    int differ = 0, mixed = 0;
    for (const ChunkCoord& c : test_region()) {
        const Chunk ca = a.generate(c);
        mixed += !ca.is_uniform();
        differ += !(ca == b.generate(c));
    }
    // Near the surface almost every chunk differs; only uniform ones may coincide.
    EXPECT_GT(mixed, 36);
    EXPECT_GE(differ, mixed * 9 / 10);
}

TEST(Terrain, UniformFarAboveAndDeepBelow) {
    const TerrainGenerator gen(kSeed);
    const auto& ids = gen.ids();
    for (int x = -3; x <= 3; ++x)
        for (int z = -3; z <= 3; ++z) {
            const Chunk sky = gen.generate({x, 20, z});
            EXPECT_TRUE(sky.is_empty());
            const Chunk deep = gen.generate({x, -40, z});
            ASSERT_TRUE(deep.is_uniform());
            EXPECT_EQ(deep.uniform_id(), ids.stone);
        }
    // The chunk right above a column group's highest surface (and the sea) is uniform air too.
    const ChunkCoord c(2, 0, -1);
    int top = gen.params().sea_level;
    const BlockPos o = chunk_origin(c);
    for (int z = 0; z < kChunkSize; ++z)
        for (int x = 0; x < kChunkSize; ++x)
            top = std::max(top, gen.surface_height(o.x + x, o.z + z));
    const Chunk above = gen.generate({c.x, int(top >> kChunkBits) + 1, c.z});
    EXPECT_TRUE(above.is_empty());
}

TEST(Terrain, SurfaceHeightMatchesGeneratedColumns) {
    const TerrainGenerator gen(kSeed);
    const auto& ids = gen.ids();
    World world;
    for (int y = -2; y <= 2; ++y)
        world.put_chunk({0, y, 0}, gen.generate({0, y, 0}));
    int checked = 0;
    for (int z = 0; z < kChunkSize; ++z)
        for (int x = 0; x < kChunkSize; ++x) {
            const int h = gen.surface_height(x, z);
            ASSERT_GT(h, -64);
            ASSERT_LT(h, 95);
            const BlockId above = world.get_block({x, h + 1, z});
            EXPECT_TRUE(above == kAir || above == ids.water);
            const BlockId surf = world.get_block({x, h, z});
            // The surface block, unless a cave entrance carved it.
            EXPECT_TRUE(surf == ids.grass || surf == ids.sand || surf == ids.snow || surf == kAir) << surf;
            checked += surf != kAir;
        }
    EXPECT_GT(checked, 900);
}

TEST(Terrain, RegionHasWaterCavesAndEveryBlockType) {
    const TerrainGenerator gen(kSeed);
    const auto& ids = gen.ids();
    World world;
    std::vector<int64_t> counts(size_t(1) << 16, 0);
    int64_t cave_air = 0, uniform = 0, total = 0;
    std::vector<BlockPos> features; // Lamps and crystals.
    // No surface lies below this (noise is within [-1, 1]): air under it is cave air.
    const int64_t lowest_surface = int64_t(float(gen.params().base_height) - gen.params().hill_amplitude) - 2;
    // 8 x 5 x 8 chunks, world y -128..31: sea, beaches, hills and most of the cave band.
    for (int z = -4; z < 4; ++z)
        for (int x = -4; x < 4; ++x)
            for (int y = -4; y <= 0; ++y) {
                const Chunk c = gen.generate({x, y, z});
                ++total;
                uniform += c.is_uniform();
                std::vector<BlockId> dense(kChunkVolume);
                c.to_dense(dense);
                for (int i = 0; i < kChunkVolume; ++i) {
                    ++counts[dense[i]];
                    const int lx = i & 31, ly = (i >> 5) & 31, lz = i >> 10;
                    cave_air += dense[i] == kAir && y * kChunkSize + ly < lowest_surface;
                    if (dense[i] == ids.lamp || dense[i] == ids.glass || dense[i] == ids.mirror)
                        features.push_back(chunk_origin({x, y, z}) + BlockPos(lx, ly, lz));
                }
                world.put_chunk({x, y, z}, c);
            }
    for (BlockId id : {ids.stone, ids.dirt, ids.grass, ids.sand, ids.water, ids.glass, ids.mirror, ids.lamp})
        EXPECT_GT(counts[id], 0) << BlockRegistry::default_registry().info(id).name;
    EXPECT_GT(counts[ids.water], 1000); // Some sea (a third of all surface; less in this region).
    EXPECT_GT(cave_air, 20000); // Caves: air below any surface.
    EXPECT_LT(uniform, total);
    // Lamps stand on terrain and crystals touch terrain above or below, across chunk borders too.
    auto terrain = [&](BlockId b) {
        return b == ids.stone || b == ids.dirt || b == ids.grass || b == ids.sand || b == ids.snow;
    };
    int lamps = 0, crystals = 0;
    for (const BlockPos& p : features) {
        const BlockId b = world.get_block(p);
        const BlockId below = world.get_block(p - BlockPos(0, 1, 0)), above = world.get_block(p + BlockPos(0, 1, 0));
        if (p.y == -128 || p.y == 31)
            continue; // The neighbour lies outside the generated region.
        if (b == ids.lamp) {
            ++lamps;
            EXPECT_TRUE(terrain(below));
        } else {
            ++crystals;
            EXPECT_TRUE(terrain(below) || terrain(above));
        }
    }
    EXPECT_GT(lamps, 0);
    EXPECT_GT(crystals, 0);
}

TEST(Terrain, MountainsCarrySnow) {
    const TerrainGenerator gen(kSeed);
    // Find the highest column on a coarse scan of a 8192-block square, then look at its chunk.
    int64_t best_x = 0, best_z = 0;
    int best_h = INT32_MIN;
    for (int64_t z = -4096; z < 4096; z += 64)
        for (int64_t x = -4096; x < 4096; x += 64) {
            const int h = gen.surface_height(x, z);
            if (h > best_h) {
                best_h = h;
                best_x = x;
                best_z = z;
            }
        }
    ASSERT_GT(best_h, gen.params().snow_line + 4); // Some mountain rises above the snow line.
    const ChunkCoord c = chunk_of(BlockPos(best_x, best_h, best_z));
    const Chunk chunk = gen.generate(c);
    const LocalPos l = local_of(BlockPos(best_x, best_h, best_z));
    EXPECT_EQ(chunk.get(l), gen.ids().snow);
}

} // namespace
} // namespace vx::world
