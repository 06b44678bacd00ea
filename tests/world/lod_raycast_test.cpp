// Rays cast at a LOD scene and at full detail on the CPU (issue 16: "0 that pass through LOD but
// hit full detail"). The scene is the target cut of lod_cut.h around a viewer on the built-in
// terrain; its level-0 chunks are generated, its coarse ones either made directly by the terrain
// (generate_lod) or downsampled from generated blocks (downsample(): the engine's path for edits).
// Full detail is the generated blocks over the same region (the blocks the cut covers; beyond it
// neither draws anything, so a hit there would be no hole).
//
// The casters work on cells, so this checks the data: coarse cells conservative over their
// blocks and the cut covering the view without gaps. It does not see meshes: coarse chunks are
// meshed with an air apron (every border face drawn) and level-0 chunks with their real
// neighbours, so where a level-0 chunk meets a coarser one the coarse side draws its border
// faces; a mesh is closed wherever its cells are, and the cells are what is tested here.
//
// What is bounded: a LOD hit is never farther than the full-detail hit (same block walk, cells
// conservative), and its point lies within one cell diagonal of full-detail ground (its cell holds
// a block). How early a ray stops *along the ray* has no bound: a grazing ray that clips a coarse
// cell over a slope or a hilltop passes above the fine ground and may land hundreds of blocks
// farther (the printout shows it: up to 670 blocks from level borders); that is the price of
// "air never wins", and the reason the distance is measured, not asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/lod/lod_cut.h"
#include "world/lod/lod_raycast.h"

namespace vx::world {
namespace {

constexpr uint64_t kSeed = 1;

// Level-0 chunks, generated on first use.
class Blocks {
public:
    explicit Blocks(const TerrainGenerator& gen) : m_gen(gen) {}
    const Chunk& chunk(ChunkCoord c) {
        auto it = m_chunks.find(c);
        if (it == m_chunks.end())
            it = m_chunks.emplace(c, m_gen.generate(c)).first;
        return it->second;
    }
    size_t size() const { return m_chunks.size(); }

private:
    const TerrainGenerator& m_gen;
    std::unordered_map<ChunkCoord, Chunk, ChunkCoordHash> m_chunks;
};

// Coarse chunks downsampled level by level from generated blocks (each chunk built once).
class Downsampled {
public:
    explicit Downsampled(Blocks& blocks) : m_blocks(blocks) {}
    const Chunk& chunk(LodCoord c) {
        if (c.level == 0)
            return m_blocks.chunk(c.chunk);
        if (auto it = m_chunks.find(c); it != m_chunks.end())
            return it->second;
        std::array<const Chunk*, kLodChildren> kids;
        for (int i = 0; i < kLodChildren; ++i)
            kids[size_t(i)] = &chunk(lod_child(c, i));
        return m_chunks.emplace(c, downsample(kids)).first->second;
    }

private:
    Blocks& m_blocks;
    std::unordered_map<LodCoord, Chunk, LodCoordHash> m_chunks;
};

// Full detail over the blocks the scene covers, air elsewhere. Caches the last region and chunk.
class FullDetail {
public:
    FullDetail(const LodScene& scene, Blocks& blocks) : m_scene(scene), m_blocks(blocks) {}
    BlockId operator()(BlockPos p) {
        if (glm::any(glm::lessThan(p, m_box.min)) || glm::any(glm::greaterThan(p, m_box.max))) {
            const LodScene::Covering cov = m_scene.covering(p);
            m_box = lod_block_box(cov.coord);
            m_covered = cov.chunk != nullptr;
        }
        if (!m_covered)
            return kAir;
        const ChunkCoord c = chunk_of(p);
        if (!m_chunk || c != m_coord) {
            m_chunk = &m_blocks.chunk(c);
            m_coord = c;
        }
        return m_chunk->get(local_of(p));
    }

private:
    const LodScene& m_scene;
    Blocks& m_blocks;
    LodBlockBox m_box{BlockPos(1), BlockPos(0)};
    bool m_covered = false;
    const Chunk* m_chunk = nullptr;
    ChunkCoord m_coord{0};
};

// The highest ground (terrain or sea) under column (x, z).
int64_t ground(const TerrainGenerator& gen, int64_t x, int64_t z) {
    return std::max<int64_t>(gen.surface_height(x, z), gen.params().sea_level);
}

std::string str(glm::dvec3 v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.4f, %.4f, %.4f)", v.x, v.y, v.z);
    return buf;
}

struct TestRay {
    Ray ray;
    int kind; // 0: all directions from the viewer, 1: grazing from the viewer, 2: from a level border.
};
constexpr const char* kKindNames[] = {"all directions", "grazing", "level borders"};

glm::dvec3 direction(double azimuth, double elevation) {
    return {std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
}

std::vector<TestRay> make_rays(const TerrainGenerator& gen, const LodScene& scene, glm::dvec3 viewer) {
    std::vector<TestRay> rays;
    const double kPi = 3.14159265358979323846;
    // Directions spread evenly over the sphere (Fibonacci lattice).
    constexpr int kSphere = 2000;
    for (int i = 0; i < kSphere; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / kSphere;
        rays.push_back({Ray::from_world(viewer, direction(i * kPi * (3.0 - std::sqrt(5.0)), std::asin(y))), 0});
    }
    // Grazing: nearly level, from the viewer and from a block plane (a ray in a plane belongs to
    // the blocks above it: the tie rule of raycast.h), at every 1.5 degrees of azimuth.
    const glm::dvec3 on_plane(viewer.x, std::floor(viewer.y), viewer.z);
    for (int a = 0; a < 240; ++a)
        for (double deg : {-2.0, -0.7, -0.2, 0.0, 0.3}) {
            const glm::dvec3 d = direction(a * 2.0 * kPi / 240.0, deg * kPi / 180.0);
            rays.push_back({Ray::from_world(viewer, d), 1});
            rays.push_back({Ray::from_world(on_plane, d), 1});
        }
    // Level borders: walking out from the viewer along 8 compass directions, every block where
    // the covering level changes; rays start on the border plane, just before and after it, and
    // on top of the coarse ground there, in random and grazing directions.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BlockPos v0(glm::floor(viewer));
    for (int dir = 0; dir < 8; ++dir) {
        const BlockPos step(int64_t(std::lround(std::cos(dir * kPi / 4))), 0,
                            int64_t(std::lround(std::sin(dir * kPi / 4))));
        int last_level = -2;
        for (int i = 0; i < 1200; ++i) {
            BlockPos b = v0 + step * int64_t(i);
            b.y = ground(gen, b.x, b.z) + 1;
            int level = -1;
            scene.cell_at(b, &level);
            if (level == -1)
                break; // Out of the view.
            if (level != last_level && last_level != -2) {
                // The top of the LOD ground in this column: the lowest air cell above ground.
                BlockPos top = b;
                while (scene.cell_at(top) != kAir)
                    ++top.y;
                const glm::dvec3 border(double(b.x) + (step.x < 0 ? 1.0 : 0.0) + 0.5 * (step.x == 0),
                                        double(b.y) + 0.5,
                                        double(b.z) + (step.z < 0 ? 1.0 : 0.0) + 0.5 * (step.z == 0));
                const glm::dvec3 back = -glm::dvec3(step);
                for (const glm::dvec3 o : {border, border + 0.01 * back, border - 0.01 * back,
                                           glm::dvec3(border.x, double(top.y), border.z)})
                    for (int r = 0; r < 24; ++r) {
                        const double az = unit(rng) * 2.0 * kPi;
                        const double el = r < 16 ? std::asin(2.0 * unit(rng) - 1.0) : -unit(rng) * 3.0 * kPi / 180.0;
                        rays.push_back({Ray::from_world(o, direction(az, el)), 2});
                    }
            }
            last_level = level;
        }
    }
    return rays;
}

struct Stats {
    int rays = 0, lod_hits = 0, full_hits = 0;
    int passes = 0;        // Full detail hits, LOD misses: a hole. Must be 0.
    int late = 0;          // Both hit, LOD farther than full detail. Must be 0.
    int lod_only = 0;      // LOD hits, full detail misses (a coarse cell stops a ray early).
    int no_block = 0;      // LOD hit cells holding no full-detail block.
    std::vector<std::pair<BlockPos, int>> empty_cells; // Those cells: minimum block and level.
    int hits_per_level[kMaxLodLevel + 1] = {};
    std::vector<double> early;  // Along the ray, blocks: full-detail hit distance - LOD hit distance.
    std::vector<double> early_over_diag; // The same in cell diagonals of the level hit.
    std::vector<double> gap;    // From the LOD hit point to the nearest full-detail block in its cell.
};

double percentile(std::vector<double> v, double q) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    return v[size_t(q * double(v.size() - 1))];
}

// Distance from point p to the unit cube of block b.
double to_block(glm::dvec3 p, BlockPos b) {
    const glm::dvec3 lo(b), d = glm::max(glm::max(lo - p, glm::dvec3(0.0)), p - (lo + 1.0));
    return glm::length(d);
}

Stats cast_all(const LodScene& scene, FullDetail& full, const std::vector<TestRay>& rays, int kind,
               double max_distance) {
    Stats s;
    for (const TestRay& tr : rays) {
        if (tr.kind != kind)
            continue;
        ++s.rays;
        const LodRaycastHit lod = raycast_lod(scene, tr.ray, max_distance);
        const RaycastHit fine = raycast(tr.ray, max_distance, full);
        s.lod_hits += lod.hit.hit;
        s.full_hits += fine.hit;
        if (fine.hit && !lod.hit.hit) {
            ++s.passes;
            ADD_FAILURE() << "ray through LOD: origin " << str(glm::dvec3(tr.ray.anchor) + tr.ray.offset)
                          << " direction " << str(tr.ray.direction) << ", full detail hits "
                          << str(glm::dvec3(fine.block)) << " at " << fine.distance;
            continue;
        }
        if (!lod.hit.hit)
            continue;
        const int64_t size = lod_cell_size(lod.level);
        const double diag = std::sqrt(3.0) * double(size);
        if (fine.hit) {
            s.late += lod.hit.distance > fine.distance;
            s.early.push_back(fine.distance - lod.hit.distance);
            s.early_over_diag.push_back((fine.distance - lod.hit.distance) / diag);
        } else {
            ++s.lod_only;
        }
        // The hit point, and the nearest full-detail block of the hit cell.
        const glm::dvec3 p = glm::dvec3(tr.ray.anchor) + tr.ray.offset +
                             glm::normalize(tr.ray.direction) * lod.hit.distance;
        double nearest = INFINITY;
        for (int64_t z = 0; z < size; ++z)
            for (int64_t y = 0; y < size; ++y)
                for (int64_t x = 0; x < size; ++x) {
                    const BlockPos b = lod.cell + BlockPos(x, y, z);
                    if (full(b) != kAir)
                        nearest = std::min(nearest, to_block(p, b));
                }
        ++s.hits_per_level[lod.level];
        if (std::isinf(nearest)) {
            ++s.no_block;
            s.empty_cells.emplace_back(lod.cell, lod.level);
        } else
            s.gap.push_back(nearest);
    }
    return s;
}

struct Case {
    LodViewSettings settings;
    bool downsampled = false; // Coarse chunks by downsample() of generated blocks, else generate_lod().
};

void run_case(const Case& c) {
    const auto t0 = std::chrono::steady_clock::now();
    const TerrainGenerator gen(kSeed);
    // The viewer a few blocks above the ground (terrain or sea) at the origin.
    const glm::dvec3 viewer(0.5, double(ground(gen, 0, 0)) + 3.25, 0.5);
    const LodView view(viewer, c.settings);
    ASSERT_GE(view.top_level(), 2) << "the test wants several coarse levels";
    std::vector<LodCoord> cut;
    view.cut(cut);
    Blocks blocks(gen);
    Downsampled down(blocks);
    TerrainParams params;
    params.cave_radius = 0.0f; // Nothing carved (TerrainCoarse.ExactWithoutCaves).
    const TerrainGenerator gen_no_caves(kSeed, params);
    Blocks no_caves(gen_no_caves);
    LodScene scene;
    int per_level[kMaxLodLevel + 1] = {};
    for (const LodCoord& lc : cut) {
        Chunk cells;
        if (lc.level == 0)
            cells = blocks.chunk(lc.chunk);
        else if (c.downsampled)
            cells = down.chunk(lc);
        else {
            Result<Chunk> r = generate_lod(gen, lc);
            ASSERT_TRUE(r.ok()) << r.error();
            cells = std::move(*r);
        }
        ASSERT_TRUE(scene.add(lc, std::move(cells))) << "the cut overlaps itself";
        ++per_level[lc.level];
    }
    std::printf("viewer (%.2f, %.2f, %.2f), view distance %lld, levels 0..%d; cut chunks per level:", viewer.x,
                viewer.y, viewer.z, (long long)c.settings.view_distance, view.top_level());
    for (int k = 0; k <= view.top_level(); ++k)
        std::printf(" %d", per_level[k]);
    std::printf("; coarse chunks %s\n", c.downsampled ? "downsampled from blocks" : "from generate_lod");

    const std::vector<TestRay> rays = make_rays(gen, scene, viewer);
    FullDetail full(scene, blocks);
    // Far enough to leave the cut in every direction (roots reach the view distance plus one root).
    const double max_distance = double(c.settings.view_distance + 2 * lod_chunk_blocks(view.top_level()));
    int total = 0, hits = 0;
    for (int kind = 0; kind < 3; ++kind) {
        const Stats s = cast_all(scene, full, rays, kind, max_distance);
        total += s.rays;
        hits += s.lod_hits;
        std::printf("  %-14s %5d rays: LOD hits %d, full detail hits %d, through LOD %d, LOD later %d, LOD-only %d;"
                    " early stop along the ray (blocks) median %.2f p99 %.2f max %.2f, > 1 cell diagonal %d;"
                    " hit point to nearest block of its cell median %.2f max %.2f, cells without a block %d\n",
                    kKindNames[kind], s.rays, s.lod_hits, s.full_hits, s.passes, s.late, s.lod_only,
                    percentile(s.early, 0.5), percentile(s.early, 0.99), percentile(s.early, 1.0),
                    int(std::count_if(s.early_over_diag.begin(), s.early_over_diag.end(),
                                      [](double e) { return e > 1.0; })),
                    percentile(s.gap, 0.5), percentile(s.gap, 1.0), s.no_block);
        std::printf("    LOD hits per level:");
        for (int k = 0; k <= view.top_level(); ++k)
            std::printf(" %d", s.hits_per_level[k]);
        std::printf("\n");
        EXPECT_EQ(s.passes, 0) << kKindNames[kind];
        EXPECT_EQ(s.late, 0) << kKindNames[kind];
        EXPECT_GT(s.lod_hits, 0) << kKindNames[kind];
        // Every LOD hit lies within one cell diagonal of full-detail ground: its cell holds a
        // block. Downsampled cells are exactly "some block under it", so always; direct coarse
        // terrain does not carve caves (terrain.h), so a cell it adds must hold a block of the
        // same terrain without caves.
        if (c.downsampled) {
            EXPECT_EQ(s.no_block, 0) << kKindNames[kind];
        } else {
            int unexplained = 0;
            for (const auto& [cell, level] : s.empty_cells) {
                bool any = false;
                const int64_t size = lod_cell_size(level);
                for (int64_t i = 0; i < size * size * size && !any; ++i) {
                    const BlockPos b = cell + BlockPos(i % size, (i / size) % size, i / (size * size));
                    any = no_caves.chunk(chunk_of(b)).get(local_of(b)) != kAir;
                }
                unexplained += !any;
            }
            EXPECT_EQ(unexplained, 0) << kKindNames[kind];
        }
    }
    EXPECT_GT(total, 5000);
    EXPECT_GT(hits, total / 3);
    std::printf("  %zu level-0 chunks generated, %.2f s\n", blocks.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

TEST(LodRaycast, SceneRefusesOverlapsAndCoversByLevel) {
    LodScene scene;
    const LodCoord parent{2, ChunkCoord(1, 0, -1)};
    EXPECT_TRUE(scene.add(lod_child(parent, 3), Chunk(5)));
    EXPECT_FALSE(scene.add(lod_child(parent, 3), Chunk(5))) << "the same chunk twice";
    EXPECT_FALSE(scene.add(parent, Chunk(6))) << "an ancestor of a scene chunk";
    EXPECT_FALSE(scene.add(lod_child(lod_child(parent, 3), 0), Chunk(6))) << "a descendant of a scene chunk";
    EXPECT_TRUE(scene.add(lod_child(parent, 4), Chunk(kAir)));
    EXPECT_TRUE(scene.add({0, ChunkCoord(-1, 0, 0)}, Chunk(7)));
    EXPECT_EQ(scene.max_level(), 1);
    EXPECT_EQ(scene.size(), 3u);
    int level = -2;
    // Child 3 of the level-2 chunk (1, 0, -1) is level-1 chunk (3, 1, -2): blocks x 192.., y 64.., z -128...
    EXPECT_EQ(scene.cell_at(BlockPos(200, 70, -100), &level), 5);
    EXPECT_EQ(level, 1);
    EXPECT_EQ(scene.cell_at(BlockPos(-1, 0, 0), &level), 7);
    EXPECT_EQ(level, 0);
    EXPECT_EQ(scene.cell_at(BlockPos(0, 0, 0), &level), kAir);
    EXPECT_EQ(level, -1);
    // A ray along +x at y 70, z -100 from x 100: enters the level-1 chunk at x 192.
    const glm::dvec3 o(100.5, 70.5, -99.5);
    const LodRaycastHit h = raycast_lod(scene, Ray::from_world(o, glm::dvec3(1, 0, 0)), 500.0);
    ASSERT_TRUE(h.hit.hit);
    EXPECT_EQ(h.level, 1);
    EXPECT_EQ(h.hit.id, 5);
    EXPECT_DOUBLE_EQ(h.hit.distance, 91.5);
    EXPECT_EQ(h.hit.block, BlockPos(192, 70, -100));
    EXPECT_EQ(h.cell, BlockPos(192, 70, -100));
    EXPECT_FALSE(raycast_lod(scene, Ray::from_world(o, glm::dvec3(-1, 0, 0)), 500.0).hit.hit);
}

// Past the world's edge is air for LOD rays too: a scene of level 0 only (no coarse lookup to stop
// it) once wrapped a ray leaving at +x round to the chunk at the far edge (32-bit chunk
// coordinates), reporting a block outside the world.
TEST(LodRaycast, BeyondTheWorldsEdgeIsAir) {
    LodScene scene;
    ASSERT_TRUE(scene.add({0, ChunkCoord(INT32_MIN, 0, 0)}, Chunk(3)));
    Ray ray;
    ray.anchor = BlockPos(kWorldMaxBlock - 3, 5, 5);
    ray.offset = {0.5, 0.5, 0.5};
    ray.direction = {1, 0, 0};
    EXPECT_FALSE(raycast_lod(scene, ray, 64.0).hit.hit);
    ray.anchor = BlockPos(kWorldMaxBlock + 40, 5, 5); // From beyond the edge, back in: still nothing there.
    ray.direction = {-1, 0, 0};
    EXPECT_FALSE(raycast_lod(scene, ray, 64.0).hit.hit);
    ray.anchor = BlockPos(kWorldMinBlock + 40, 5, 5); // The chunk itself is found from inside the world.
    const LodRaycastHit h = raycast_lod(scene, ray, 64.0);
    ASSERT_TRUE(h.hit.hit);
    EXPECT_EQ(h.hit.block, BlockPos(kWorldMinBlock + 31, 5, 5));
    EXPECT_EQ(h.hit.distance, 8.5);
    // The walk ends at the edge: a limit of 1e12 blocks walked hours of air past it.
    ray.anchor = BlockPos(kWorldMaxBlock - 3, 5, 5);
    ray.direction = {1, 0, 0};
    EXPECT_FALSE(raycast_lod(scene, ray, 1e12).hit.hit);
}

TEST(LodRaycast, DirectCoarseTerrainLetsNoRayThrough) {
    Case c;
    c.settings.radius0 = 2;
    c.settings.vradius0 = 2;
    c.settings.ring = 3;
    c.settings.vertical_reach = 64;
    c.settings.view_distance = 400;
    run_case(c);
}

TEST(LodRaycast, DownsampledCoarseChunksLetNoRayThrough) {
    Case c;
    c.settings.radius0 = 1;
    c.settings.vradius0 = 1;
    c.settings.ring = 2;
    c.settings.vertical_reach = 32;
    c.settings.view_distance = 200;
    c.downsampled = true;
    run_case(c);
}

} // namespace
} // namespace vx::world
