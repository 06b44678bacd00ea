// Import of VDB volumes: files the tests write with OpenVDB (vdb_test_files.h), which always run,
// and real files written by other tools (shared/data/vdb, see its PROVENANCE.md), read too when
// that folder is present (the test then says in one line that only generated inputs ran).

#include <climits>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "tests/vdb/vdb_test_files.h"
#include "tests/vdb/vdb_test_util.h"
#include "world/vdb/vdb_accuracy.h"
#include "world/vdb/vdb_volume.h"

namespace vx::vdb {
namespace {

using test::data_path;
using test::test_file;
using test::TestFile;
using world::BlockPos;

::testing::AssertionResult fails_with(const Result<VolumeImport>& r, const std::string& words) {
    if (r.ok())
        return ::testing::AssertionFailure() << "import succeeded; expected an error with '" << words << "'";
    if (r.error().find('\n') != std::string::npos)
        return ::testing::AssertionFailure() << "error is not one line: " << r.error();
    if (r.error().find(words) == std::string::npos)
        return ::testing::AssertionFailure() << "error lacks '" << words << "': " << r.error();
    return ::testing::AssertionSuccess();
}

// Each test below first reads files OpenVDB writes here (a clone alone runs them), then, when
// shared/data/vdb is present, the real files of other writers (half floats, old versions, points).
TEST(VdbVolume, ListGridsComputesBoundsFromTheTree) {
    Result<std::vector<GridInfo>> g = list_grids(test_file(TestFile::ThreeDensities));
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_EQ(g->size(), 3u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ((*g)[size_t(i)].name, "density");
        EXPECT_EQ((*g)[size_t(i)].index, i);
        EXPECT_EQ((*g)[size_t(i)].value_type, "float");
        EXPECT_EQ((*g)[size_t(i)].grid_class, "fog volume");
    }
    EXPECT_EQ((*g)[1].bbox_min, glm::ivec3(-9, -13, -8)); // Ball of radius 9 at (0, -4, 1).
    EXPECT_EQ((*g)[1].bbox_max, glm::ivec3(9, 5, 10));
    g = list_grids(test_file(TestFile::LevelSetSphere));
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_EQ(g->size(), 1u);
    EXPECT_EQ((*g)[0].grid_class, "level set");
    EXPECT_NEAR((*g)[0].voxel_size.x, 0.05, 1e-9);
    EXPECT_EQ((*g)[0].bbox_max.x, 62); // The band reaches 60 + 2 voxels (|d| < 3).
    g = list_grids(test_file(TestFile::EmptyFog));
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_TRUE((*g)[0].empty);
    EXPECT_EQ((*g)[0].active_voxels, 0u);
    g = list_grids(test_file(TestFile::ColourField));
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_EQ((*g)[0].value_type, "vec3s");
    EXPECT_EQ((*g)[0].active_voxels, 64u);

    VX_REAL_VDB_DATA_OR_RETURN();
    g = list_grids(data_path("arnoldusd_smoke.vdb"));
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_EQ(g->size(), 1u);
    EXPECT_EQ((*g)[0].name, "density");
    EXPECT_EQ((*g)[0].value_type, "float");
    EXPECT_EQ((*g)[0].grid_class, "fog volume");
    EXPECT_EQ((*g)[0].active_voxels, 1049275u); // vdb_print's count.
    EXPECT_EQ((*g)[0].bbox_min, glm::ivec3(1, 2, 1));
    EXPECT_EQ((*g)[0].bbox_max, glm::ivec3(111, 223, 112));
    EXPECT_TRUE((*g)[0].saved_as_half);
    EXPECT_NEAR((*g)[0].voxel_size.x, 0.476, 1e-3);

    g = list_grids(data_path("arnoldusd_grids.vdb"));
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_EQ(g->size(), 3u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ((*g)[size_t(i)].name, "density");
        EXPECT_EQ((*g)[size_t(i)].index, i);
    }
    EXPECT_EQ((*g)[1].bbox_min, glm::ivec3(-9, -13, -9));
    EXPECT_EQ((*g)[1].bbox_max, glm::ivec3(9, 5, 12));

    // The damaged files claim huge bboxes in their metadata; the tree is empty.
    for (const char* f : {"damaged/oiio_bad-bbox-huge.vdb", "damaged/oiio_bad-bbox-bomb.vdb"}) {
        g = list_grids(data_path(f));
        ASSERT_TRUE(g.ok()) << g.error();
        ASSERT_EQ(g->size(), 1u);
        EXPECT_TRUE((*g)[0].empty);
        EXPECT_EQ((*g)[0].active_voxels, 0u);
    }
    g = list_grids(data_path("gaffer_points.vdb"));
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_EQ((*g)[0].value_type, "ptdataidx32");
}

TEST(VdbVolume, LevelSetSphereFromOldFormatHalfFloats) {
    {
        // The level set written here: radius 60 voxels, interior inactive tiles at -background.
        Result<VolumeImport> r = import_volume(test_file(TestFile::LevelSetSphere));
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(r->summary.mode, VolumeMode::LevelSet);
        const double r3 = 4.0 / 3.0 * M_PI * std::pow(60.0, 3); // 904,779 blocks; +-3%.
        EXPECT_NEAR(double(r->summary.solid_blocks), r3, 0.03 * r3);
        EXPECT_NE(r->world.get_block(BlockPos(0)), world::kAir);         // Deep interior (tile).
        EXPECT_NE(r->world.get_block(BlockPos(0, 0, -56)), world::kAir); // Inside, near the band.
        EXPECT_EQ(r->world.get_block(BlockPos(0, 62, 0)), world::kAir);  // Outside, in the band.
    }
    VX_REAL_VDB_DATA_OR_RETURN();
    // OpenVDB 1.1 file, half floats, narrow band of 3 voxels: the interior is inactive tiles at
    // -background, which must read as inside.
    Result<VolumeImport> r = import_volume(data_path("gaffer_vdbtest_sphere.vdb"));
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->summary.mode, VolumeMode::LevelSet);
    EXPECT_EQ(r->summary.grid_name, "ls_sphere");
    // The band's bbox is [-62, 62] with 3 voxels of band: radius ~59.5 voxels. A sphere of
    // radius R has 4/3 pi R^3 blocks: 882,347 at R = 59.5; allow +-3% for the exact radius.
    const double r3 = 4.0 / 3.0 * M_PI * std::pow(59.5, 3);
    EXPECT_NEAR(double(r->summary.solid_blocks), r3, 0.03 * r3);
    EXPECT_EQ(test::count_solid(r->world), r->summary.solid_blocks);
    EXPECT_NE(r->world.get_block(BlockPos(0)), world::kAir);          // Deep interior (inactive tile).
    EXPECT_NE(r->world.get_block(BlockPos(0, 0, -55)), world::kAir);  // Inside, near the band.
    EXPECT_EQ(r->world.get_block(BlockPos(0, 62, 0)), world::kAir);   // Outside, in the band.
    EXPECT_EQ(r->world.get_block(BlockPos(61, 61, 0)), world::kAir);  // Outside, bbox corner.
    EXPECT_GT(r->summary.supersampled_blocks, 0u);
}

TEST(VdbVolume, EveryRealFileImportsOrIsRefused) {
    // The files written here: fog, level set and multi-grid import; a vector grid and an empty
    // grid are refused with one line. (A truncated file is untrusted input: it is read in the
    // isolated child, VdbIsolated.*, since OpenVDB may read garbage sizes from it in-process.)
    for (const TestFile f : {TestFile::FogSphere, TestFile::LevelSetSphere, TestFile::ThreeDensities}) {
        Result<VolumeImport> r = import_volume(test_file(f));
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(r->summary.mode, f == TestFile::LevelSetSphere ? VolumeMode::LevelSet : VolumeMode::Fog);
        EXPECT_GT(r->summary.solid_blocks, 0u);
        EXPECT_EQ(test::count_solid(r->world), r->summary.solid_blocks);
    }
    EXPECT_TRUE(fails_with(import_volume(test_file(TestFile::ColourField)), "vec3s"));
    EXPECT_TRUE(fails_with(import_volume(test_file(TestFile::EmptyFog)), "empty"));

    VX_REAL_VDB_DATA_OR_RETURN();
    struct Case {
        const char* file;
        const char* error; // Null: imports.
        VolumeMode mode;
    };
    const Case cases[] = {
        {"gaffer_vdbtest_sphere.vdb", nullptr, VolumeMode::LevelSet},
        {"arnoldusd_smoke.vdb", nullptr, VolumeMode::Fog},
        {"arnoldusd_torus01.vdb", nullptr, VolumeMode::Fog},
        {"oiio_sphere.vdb", nullptr, VolumeMode::Fog},
        {"gaffer_arnoldtest_sphere.vdb", nullptr, VolumeMode::Fog},
        {"arnoldusd_grids.vdb", nullptr, VolumeMode::Fog}, // First scalar grid.
        {"oiio_sphereCd.vdb", "vec3s", VolumeMode::Auto},
        {"gaffer_points.vdb", "point-data", VolumeMode::Auto},
        {"damaged/oiio_bad-bbox-huge.vdb", "empty", VolumeMode::Auto},
        {"damaged/oiio_bad-bbox-bomb.vdb", "empty", VolumeMode::Auto},
        {"damaged/oiio_truncated.vdb", "cannot read", VolumeMode::Auto},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        // Block size 1 on the two large files costs seconds in sanitizer builds; 4 suffices there.
        const bool large = std::string(c.file) == "arnoldusd_smoke.vdb" || std::string(c.file) == "gaffer_vdbtest_sphere.vdb";
        for (int b : large ? std::vector<int>{4} : std::vector<int>{1, 3}) {
            VolumeImportOptions o;
            o.voxels_per_block = b;
            Result<VolumeImport> r = import_volume(data_path(c.file), o);
            if (c.error) {
                EXPECT_TRUE(fails_with(r, c.error));
                continue;
            }
            ASSERT_TRUE(r.ok()) << r.error();
            EXPECT_EQ(r->summary.mode, c.mode);
            EXPECT_GT(r->summary.solid_blocks, 0u);
            EXPECT_EQ(test::count_solid(r->world), r->summary.solid_blocks);
        }
    }
}

TEST(VdbVolume, GridsWithTheSameNameAreSelectedByIndex) {
    const std::string path = test_file(TestFile::ThreeDensities);
    VolumeImportOptions o;
    o.grid_name = "density";
    EXPECT_TRUE(fails_with(import_volume(path, o), "grid_index"));
    o.grid_name.clear();
    uint64_t solid[3];
    for (int i = 0; i < 3; ++i) {
        o.grid_index = i;
        Result<VolumeImport> r = import_volume(path, o);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(r->summary.grid_index, i);
        solid[i] = r->summary.solid_blocks;
    }
    // Grid 1 (voxel 1, identity transform) has voxels (-9,-13,-8)..(9,5,10), centred on those
    // integers, so their cells reach world [-9.5, 9.5] x [-13.5, 5.5] x [-8.5, 10.5]; blocks are
    // floor(world / 1): (-10,-14,-9)..(9,5,10). A block bbox unlike the other two grids'.
    o.grid_index = 1;
    Result<VolumeImport> r = import_volume(path, o);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->summary.blocks.min, BlockPos(-10, -14, -9));
    EXPECT_EQ(r->summary.blocks.max, BlockPos(9, 5, 10));
    EXPECT_NE(solid[0], solid[1]);
    o.grid_index = 3;
    EXPECT_TRUE(fails_with(import_volume(path, o), "out of range"));
    o.grid_index = -1;
    o.grid_name = "nope";
    EXPECT_TRUE(fails_with(import_volume(path, o), "no grid named 'nope'"));
}

TEST(VdbVolume, BadPathsAndOptionsGiveOneLineErrors) {
    EXPECT_TRUE(fails_with(import_volume("/nonexistent/dir/x.vdb"), "no such file"));
    Result<std::vector<GridInfo>> g = list_grids("/nonexistent/x.vdb");
    EXPECT_FALSE(g.ok());
    const std::string path = test_file(TestFile::FogSphere);
    VolumeImportOptions o;
    o.block_size = -1;
    EXPECT_TRUE(fails_with(import_volume(path, o), "block_size"));
    o.block_size = 65.0; // 65 voxels of 1: more than the 64 a block may span.
    EXPECT_TRUE(fails_with(import_volume(path, o), "block_size"));
    o = {};
    o.voxels_per_block = 65;
    EXPECT_TRUE(fails_with(import_volume(path, o), "voxels_per_block"));
    o = {};
    o.threshold = 0.f;
    EXPECT_TRUE(fails_with(import_volume(path, o), "threshold"));
    o = {};
    o.max_blocks = 1000; // The ball spans 25³ = 15625 blocks.
    EXPECT_TRUE(fails_with(import_volume(path, o), "max_blocks"));
    o = {};
    o.block = world::kAir;
    EXPECT_TRUE(fails_with(import_volume(path, o), "air"));
    o = {};
    o.offset = BlockPos(int64_t(1) << 40, 0, 0);
    EXPECT_TRUE(fails_with(import_volume(path, o), "offset"));
    o.offset = BlockPos(0, INT64_MIN, 0);
    EXPECT_TRUE(fails_with(import_volume(path, o), "offset"));
    o.offset = BlockPos(0, 0, (int64_t(1) << 36) - 5); // The ball's 25 blocks cross the edge.
    EXPECT_TRUE(fails_with(import_volume(path, o), "offset"));
    o = {};
    o.mode = VolumeMode::LevelSet; // Fog background 0 is not a level set's positive outside.
    EXPECT_TRUE(fails_with(import_volume(path, o), "background"));
}

TEST(VdbVolume, OffsetShiftsEveryBlock) {
    const std::string path = test_file(TestFile::FogSphere);
    Result<VolumeImport> a = import_volume(path);
    VolumeImportOptions o;
    o.offset = BlockPos(int64_t(1) << 30, -5, 7);
    Result<VolumeImport> b = import_volume(path, o);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->summary.solid_blocks, b->summary.solid_blocks);
    a->world.for_each_chunk([&](world::ChunkCoord c, const world::Chunk& chunk) {
        for (int i = 0; i < world::kChunkVolume; ++i) {
            const BlockPos p = world::chunk_origin(c) + BlockPos(i & 31, (i >> 5) & 31, i >> 10);
            ASSERT_EQ(chunk.get(i), b->world.get_block(p + o.offset));
        }
    });
}

// A volume that ends on the world's last block imports there: its chunk is INT32_MAX, where the
// chunk loops' int counters wrapped and never ended.
TEST(VdbVolume, AVolumeEndingOnTheWorldsLastBlockImports) {
    const std::string path = test_file(TestFile::FogSphere);
    Result<VolumeImport> a = import_volume(path);
    ASSERT_TRUE(a.ok()) << a.error();
    VolumeImportOptions o;
    o.offset = BlockPos(world::kWorldMaxBlock - a->summary.blocks.max.x, 0, world::kWorldMaxBlock - a->summary.blocks.max.z);
    Result<VolumeImport> b = import_volume(path, o);
    ASSERT_TRUE(b.ok()) << b.error();
    EXPECT_EQ(b->summary.blocks.max.x, world::kWorldMaxBlock);
    EXPECT_EQ(a->summary.solid_blocks, b->summary.solid_blocks);
    uint64_t solid = 0;
    b->world.for_each_chunk([&](world::ChunkCoord, const world::Chunk& chunk) {
        for (int i = 0; i < world::kChunkVolume; ++i)
            solid += chunk.get(i) != world::kAir;
    });
    EXPECT_EQ(solid, a->summary.solid_blocks);
}

TEST(VdbVolume, DensityMapsToBlocks) {
    // Density 0..1 rising towards the centre.
    VolumeImportOptions o;
    o.threshold = 0.1f;
    o.density_blocks = {{0.f, 4}, {0.6f, 1}};
    Result<VolumeImport> r = import_volume(test_file(TestFile::FogSphere), o);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->world.get_block(BlockPos(0)), 1);
    uint64_t outer = 0;
    r->world.for_each_chunk([&](world::ChunkCoord, const world::Chunk& c) {
        for (int i = 0; i < world::kChunkVolume; ++i)
            outer += c.get(i) == 4;
    });
    EXPECT_GT(outer, 0u);
}

TEST(VdbVolume, LargerBlocksCoverTheSameShape) {
    // Solid volume in voxels stays about the same as B grows: B³ * solid(B) ~ 8 * solid(2).
    const std::string path = test_file(TestFile::LevelSetSphere);
    VolumeImportOptions o;
    o.voxels_per_block = 2;
    Result<VolumeImport> two = import_volume(path, o);
    ASSERT_TRUE(two.ok());
    const double base = 8.0 * double(two->summary.solid_blocks);
    for (int b : {4, 8}) {
        o.voxels_per_block = b;
        Result<VolumeImport> r = import_volume(path, o);
        ASSERT_TRUE(r.ok()) << r.error();
        const double voxels = double(r->summary.solid_blocks) * b * b * b;
        EXPECT_NEAR(voxels, base, 0.02 * base) << b;
    }
}

TEST(VdbVolume, AdaptiveLevelSetMatchesSupersampledReference) {
    // The goal for level sets: IoU >= 0.999 against 8³ supersampling; centre-only is worse.
    const int sizes[] = {4};
    Result<std::vector<AccuracyRow>> rows = measure_vdb_accuracy(test_file(TestFile::LevelSetSphere), sizes);
    ASSERT_TRUE(rows.ok()) << rows.error();
    ASSERT_EQ(rows->size(), 3u);
    const AccuracyRow& adaptive = (*rows)[0];
    const AccuracyRow& centre = (*rows)[2];
    EXPECT_EQ(adaptive.sampling, VolumeSampling::Adaptive);
    EXPECT_GE(adaptive.iou, 0.999);
    EXPECT_LE(adaptive.max_surface_distance, 1.0);
    EXPECT_LT(centre.iou, 1.0);
    EXPECT_GE(adaptive.iou, centre.iou);
}

} // namespace
} // namespace vx::vdb

namespace vx::vdb {
namespace {

// Fraction of block b (B voxels per edge, cell [B*b, B*b + B) in index space: the grid is a pure
// scale) inside the ball |p| < r (index space), from 8³ samples.
double ball_fraction(BlockPos b, int bs, double r) {
    int in = 0;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const glm::dvec3 p = glm::dvec3(b * int64_t(bs)) + (glm::dvec3(x, y, z) + 0.5) * (bs / 8.0);
                in += glm::dot(p, p) < r * r;
            }
    return in / 512.0;
}

TEST(VdbVolume, LevelSetSphereMatchesTheAnalyticSphere) {
    // Ground truth independent of the importer: the test file is the level set of the sphere of
    // radius 60 voxels at the origin (gaffer_vdbtest_sphere.vdb, radius 3.0 at voxel 0.05, is the
    // same sphere written by another tool; LevelSetSphereFromOldFormatHalfFloats reads that one).
    const double r = 60.0;
    // Block size 1 takes seconds in sanitizer builds; 2, 4 and 8 cover the sampling.
    for (int bs : {2, 4, 8}) {
        VolumeImportOptions o;
        o.voxels_per_block = bs;
        Result<VolumeImport> imp = import_volume(test_file(TestFile::LevelSetSphere), o);
        ASSERT_TRUE(imp.ok()) << imp.error();
        const int64_t n = int64_t(r / bs) + 2;
        uint64_t both = 0, either = 0;
        for (int64_t z = -n; z <= n; ++z)
            for (int64_t y = -n; y <= n; ++y)
                for (int64_t x = -n; x <= n; ++x) {
                    const BlockPos b(x, y, z);
                    // Blocks whose centre is more than half a diagonal from the sphere lie wholly
                    // on one side; only the shell needs the 8³ estimate.
                    const double d = glm::length(glm::dvec3(b * int64_t(bs)) + 0.5 * bs) - r;
                    const double half_diagonal = 0.5 * std::sqrt(3.0) * bs;
                    const bool truth = std::abs(d) > half_diagonal ? d < 0 : ball_fraction(b, bs, r) > 0.5;
                    const bool got = imp->world.get_block(b) != world::kAir;
                    both += truth && got;
                    either += truth || got;
                }
        EXPECT_EQ(test::count_solid(imp->world), imp->summary.solid_blocks); // Nothing outside the ball's box.
        EXPECT_GE(double(both) / double(either), 0.99) << "block size " << bs;
        std::printf("block size %d: IoU vs analytic sphere %.5f\n", bs, double(both) / double(either));
    }
}

} // namespace
} // namespace vx::vdb

#include <fstream>
#include <iterator>

#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_isolated.h"

namespace vx::vdb {
namespace {

TEST(VdbIsolated, SameResultAsInProcess) {
    const std::string path = test_file(TestFile::ThreeDensities);
    VolumeImportOptions o;
    o.grid_index = 1;
    o.voxels_per_block = 2;
    o.offset = BlockPos(-(int64_t(1) << 30), 3, 99);
    Result<VolumeImport> a = import_volume(path, o);
    Result<VolumeImport> b = import_volume_isolated(path, o);
    ASSERT_TRUE(a.ok() && b.ok()) << (b.ok() ? a.error() : b.error());
    EXPECT_TRUE(test::same_blocks(a->world, b->world));
    EXPECT_EQ(a->summary.solid_blocks, b->summary.solid_blocks);
    EXPECT_EQ(a->summary.grid_name, b->summary.grid_name);
    EXPECT_EQ(a->summary.blocks.min, b->summary.blocks.min);
    EXPECT_EQ(a->summary.blocks.max, b->summary.blocks.max);
    EXPECT_EQ(a->summary.max_value, b->summary.max_value);

    Result<std::vector<GridInfo>> g1 = list_grids(path), g2 = list_grids_isolated(path);
    ASSERT_TRUE(g1.ok() && g2.ok());
    ASSERT_EQ(g1->size(), g2->size());
    for (size_t i = 0; i < g1->size(); ++i) {
        EXPECT_EQ((*g1)[i].name, (*g2)[i].name);
        EXPECT_EQ((*g1)[i].active_voxels, (*g2)[i].active_voxels);
        EXPECT_EQ((*g1)[i].bbox_max, (*g2)[i].bbox_max);
    }
}

// A file cut anywhere is refused with one short line: OpenVDB reads garbage from some cuts (a
// type name of hundreds of megabytes was seen at 100 bytes), which the message must not carry.
TEST(VdbIsolated, FilesCutAnywhereGiveOneShortLine) {
    std::ifstream in(test_file(TestFile::FogSphere), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 1000u);
    const std::string path = test_file(TestFile::FogSphere) + ".cut";
    for (size_t n : {size_t(16), size_t(40), size_t(64), size_t(100), size_t(200), bytes.size() / 3, bytes.size() / 2}) {
        SCOPED_TRACE(n);
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, n);
        Result<VolumeImport> r = import_volume_isolated(path);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
        EXPECT_LT(r.error().size(), path.size() + 400) << r.error().substr(0, 400);
    }
    std::remove(path.c_str());
}

TEST(VdbIsolated, MessagesAreFoldedAndCut) {
    const std::string garbage = "KeyError: " + std::string(100000, ' ') + "\x01\x02\tname\n" + std::string(5000, 'x');
    const Error e = detail::make_error("cannot read 'f.vdb'", garbage);
    EXPECT_EQ(e.message.find('\n'), std::string::npos);
    EXPECT_EQ(e.message.find('\t'), std::string::npos);
    EXPECT_EQ(e.message.find("  "), std::string::npos);
    EXPECT_EQ(e.message.rfind("cannot read 'f.vdb': KeyError: name x", 0), 0u) << e.message.substr(0, 80);
    EXPECT_EQ(e.message.size(), std::string("cannot read 'f.vdb': ").size() + 240 + 3);
    EXPECT_EQ(e.message.substr(e.message.size() - 3), "...");
}

TEST(VdbIsolated, ErrorsComeBackFromTheChild) {
    {
        Result<VolumeImport> r = import_volume_isolated(test_file(TestFile::ColourField));
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("vec3s"), std::string::npos) << r.error();
        r = import_volume_isolated(test_file(TestFile::Truncated));
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
        Result<world::World> w = import_world_vdb_isolated(test_file(TestFile::FogSphere));
        ASSERT_FALSE(w.ok());
        EXPECT_NE(w.error().find("'blocks'"), std::string::npos) << w.error();
        // Blocks placed past the +-2^31 a VDB file can index: the result cannot travel back from
        // the reader process. Said so, naming the offset; the export's own error named the
        // temporary file.
        VolumeImportOptions far;
        far.offset = BlockPos(int64_t(1) << 32, 0, 0);
        r = import_volume_isolated(test_file(TestFile::FogSphere), far);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("an isolated import carries"), std::string::npos) << r.error();
        EXPECT_NE(r.error().find("--offset"), std::string::npos) << r.error();
        EXPECT_EQ(r.error().find(".tmp-"), std::string::npos) << r.error();
    }
    VX_REAL_VDB_DATA_OR_RETURN();
    Result<VolumeImport> r = import_volume_isolated(data_path("gaffer_points.vdb"));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("point-data"), std::string::npos) << r.error();
    r = import_volume_isolated(data_path("damaged/oiio_truncated.vdb"));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().find('\n'), std::string::npos);
    Result<world::World> w = import_world_vdb_isolated(data_path("oiio_sphere.vdb"));
    ASSERT_FALSE(w.ok());
    EXPECT_NE(w.error().find("'blocks'"), std::string::npos) << w.error();
}

TEST(VdbIsolated, WorldRoundTrip) {
    world::World w;
    for (int i = 0; i < 100; ++i)
        w.set_block(BlockPos(i * 7 % 61, i, -i * 3), world::BlockId(1 + i % 11));
    w.put_chunk(world::ChunkCoord(5, 5, 5), world::Chunk(world::BlockId(7)));
    test::TempDir dir;
    const std::string path = dir.file("w.vdb");
    ASSERT_TRUE(export_vdb(w, path).ok());
    Result<world::World> back = import_world_vdb_isolated(path);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_TRUE(test::same_blocks(w, *back));
}

} // namespace
} // namespace vx::vdb
