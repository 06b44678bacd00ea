// Volume import in the file's world space: analytic shapes written with rotated, translated and
// non-uniformly scaled transforms (vdb_analytic.h) must come back where and as large as they are
// in world space; frustum transforms and bad block sizes are refused.

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "tests/vdb/vdb_test_util.h"
#include "world/vdb/vdb_accuracy.h"
#include "world/vdb/vdb_analytic.h"
#include "world/vdb/vdb_volume.h"

namespace vx::vdb {
namespace {

using world::BlockPos;

Result<VolumeImport> write_and_import(const test::TempDir& dir, const AnalyticVolume& v, const VolumeImportOptions& o) {
    const std::string path = dir.file(v.name + ".vdb");
    if (Status s = write_analytic_vdb(path, v); !s)
        return Error{s.error()};
    return import_volume(path, o);
}

// A sphere of radius 3 at (10.3, -4.2, 7.7), level set with voxel 0.1 on a grid rotated 35° about
// (1, 2, 3) whose index origin sits at (9.87, -4.01, 7.13): neither axis-aligned nor centred.
AnalyticVolume rotated_sphere() {
    AnalyticVolume v;
    v.name = "rotated_sphere";
    v.centre = {10.3, -4.2, 7.7};
    v.half_extent = glm::dvec3(3.0);
    v.index_to_world = axis_rotation(35, {1, 2, 3}) * 0.1;
    v.translation = {9.87, -4.01, 7.13};
    return v;
}

// A cube of edge 4 rotated 45° about y at (-3.05, 1.63, 2.35), level set on a grid rotated with it
// (voxel 0.1), as a tool that rotates an object's transform writes it. Its top and bottom faces
// (y = 3.63, -0.37) are not on block centres (y = 0.1 + 0.2 k), where half blocks would tie.
AnalyticVolume rotated_box() {
    AnalyticVolume v;
    v.name = "rotated_box";
    v.shape = AnalyticShape::Box;
    v.centre = {-3.05, 1.63, 2.35};
    v.half_extent = glm::dvec3(2.0);
    v.rotation = axis_rotation(45, {0, 1, 0});
    v.index_to_world = v.rotation * 0.1;
    v.translation = {-3.0, 1.5, 2.0};
    return v;
}

// A fog sphere of radius 16 voxels in index space on a grid scaled (0.05, 0.025, 0.075): in world
// space an ellipsoid with semi-axes (0.8, 0.4, 1.2) at (0.4, 0.3, -0.6).
AnalyticVolume scaled_fog_ellipsoid() {
    AnalyticVolume v;
    v.name = "fog_ellipsoid";
    v.level_set = false;
    v.centre = {0.4, 0.3, -0.6};
    v.half_extent = {0.8, 0.4, 1.2};
    v.index_to_world = glm::dmat3(glm::dvec3(0.05, 0, 0), glm::dvec3(0, 0.025, 0), glm::dvec3(0, 0, 0.075));
    v.translation = {0.4, 0.3, -0.6};
    return v;
}

// Tolerances for a majority-vote block set against the exact shape, blocks of edge s:
//  volume of smooth shapes: each block the surface crosses errs by less than its own volume, with
//    both signs, and the errors cancel; for N surface blocks the sum's spread is about
//    sqrt(N / 12) blocks (N ~ 3,000 here: ~16 blocks, 0.1% of ~13,000). Trilinear interpolation
//    of the distance at voxel spacing v flattens curvature by O(v² / R): 0.3% at v = 0.1, R = 3.
//    1% leaves a margin and still catches a lost layer of blocks (~20%) or a wrong scale.
//  volume of flat faces: errors along a plane do not cancel (the pattern repeats), the face
//    moves to the lattice: up to 1/2 block for a face parallel to block faces; for a face at 45°
//    the majority of a block is its centre's side, a staircase whose mean lies within
//    1 / (2 sqrt 2) = 0.354 blocks of the plane. The same rule applied to the exact shape (8³
//    points per block, compare_to_analytic) makes the same moves, so the import must match it
//    tightly (1%), and the analytic volume within the sum of the face bounds.
//  bounds: the solid blocks end on block faces, so an exact bound sits up to 1/2 block from the
//    face the majority vote picks; a smooth cap adds a fraction of a block. A 90° edge (the box's
//    x and z extremes after the 45° turn) fills less than half of the last block until it reaches
//    about 3/4 of it in, so there the gap can reach about 1 1/4 blocks: 1.0 for smooth shapes, 1.5
//    for the box. A transform ignored or applied backwards moves bounds by many blocks.
//  IoU against the same rule on the exact shape: only blocks within interpolation error of a tie
//    may differ; >= 0.98 (a shift by one block drops it to ~0.8 at these sizes).

TEST(VdbTransform, RotatedTranslatedSphereLandsWhereItsWorldCoordinatesSay) {
    test::TempDir dir;
    const AnalyticVolume v = rotated_sphere();
    VolumeImportOptions o;
    o.voxels_per_block = 2; // 0.2 world units: the sphere is 15 blocks in radius.
    Result<VolumeImport> r = write_and_import(dir, v, o);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->summary.mode, VolumeMode::LevelSet);
    EXPECT_NEAR(r->summary.block_size, 0.2, 1e-12);
    const AnalyticComparison c = compare_to_analytic(r->world, v, 0.2);
    EXPECT_EQ(c.solid, r->summary.solid_blocks);
    EXPECT_NEAR(c.volume_error, 0.0, 0.01);
    EXPECT_LE(c.bounds_error, 1.0);
    EXPECT_GE(c.iou, 0.98);
    std::printf("rotated sphere: %llu solid (truth %llu), IoU %.5f, volume error %+.3f%%, bounds error %.2f blocks\n",
                (unsigned long long)c.solid, (unsigned long long)c.truth_solid, c.iou, 100 * c.volume_error,
                c.bounds_error);
    // Centre block (51, -21, 38) = floor((10.3, -4.2, 7.7) / 0.2) is deep inside.
    EXPECT_NE(r->world.get_block(BlockPos(51, -21, 38)), world::kAir);
    EXPECT_EQ(r->world.get_block(BlockPos(0, 0, 0)), world::kAir);
}

TEST(VdbTransform, BoxRotated45DegreesAboutY) {
    test::TempDir dir;
    const AnalyticVolume v = rotated_box();
    VolumeImportOptions o;
    o.block_size = 0.2;
    Result<VolumeImport> r = write_and_import(dir, v, o);
    ASSERT_TRUE(r.ok()) << r.error();
    const AnalyticComparison c = compare_to_analytic(r->world, v, 0.2);
    // Volume 4³ = 64 = 8,000 blocks; faces of 16: four at 45° (0.354 blocks each at most), two
    // parallel to block faces (1/2): (4 * 0.354 + 2 * 0.5) * 0.2 * 16 / 64 = 12% at most.
    EXPECT_NEAR(c.volume_error, 0.0, (4 * 0.354 + 2 * 0.5) * 0.2 * 16 / 64);
    EXPECT_NEAR(double(c.solid), double(c.truth_solid), 0.01 * double(c.truth_solid));
    // World bounds x, z: centre +- 2 * sqrt(2); y: 1.63 +- 2.
    EXPECT_NEAR(c.solid_min.x, -3.05 - 2 * std::sqrt(2.0), 1.5 * 0.2);
    EXPECT_NEAR(c.solid_max.x, -3.05 + 2 * std::sqrt(2.0), 1.5 * 0.2);
    EXPECT_NEAR(c.solid_min.z, 2.35 - 2 * std::sqrt(2.0), 1.5 * 0.2);
    EXPECT_NEAR(c.solid_max.z, 2.35 + 2 * std::sqrt(2.0), 1.5 * 0.2);
    EXPECT_NEAR(c.solid_min.y, -0.37, 1.0 * 0.2);
    EXPECT_NEAR(c.solid_max.y, 3.63, 1.0 * 0.2);
    EXPECT_GE(c.iou, 0.99);
    std::printf("rotated box: %llu solid (truth %llu), IoU %.5f, volume error %+.3f%%, bounds error %.2f blocks\n",
                (unsigned long long)c.solid, (unsigned long long)c.truth_solid, c.iou, 100 * c.volume_error,
                c.bounds_error);
    // The unrotated import (the former behaviour) would be an axis-aligned 4-unit cube: its corner
    // region at x = centre + 1.9, z = centre + 1.9 is outside the rotated box.
    EXPECT_EQ(r->world.get_block(BlockPos(glm::floor(glm::dvec3(-3.05 + 1.9, 1.63, 2.35 + 1.9) / 0.2))), world::kAir);
    EXPECT_NE(r->world.get_block(BlockPos(glm::floor(glm::dvec3(-3.05 + 2.6, 1.63, 2.35) / 0.2))), world::kAir);
}

TEST(VdbTransform, NonUniformlyScaledFogSphereIsAnEllipsoid) {
    test::TempDir dir;
    const AnalyticVolume v = scaled_fog_ellipsoid();
    VolumeImportOptions o;
    o.threshold = 0.5f; // The written density is 0.5 on the surface.
    Result<VolumeImport> r = write_and_import(dir, v, o);
    ASSERT_FALSE(r.ok()); // Non-cubic voxels: no default block size.
    EXPECT_NE(r.error().find("block_size"), std::string::npos) << r.error();
    o.voxels_per_block = 2;
    r = import_volume(dir.file(v.name + ".vdb"), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("voxels_per_block"), std::string::npos) << r.error();

    o.voxels_per_block = 0;
    o.block_size = 0.05;
    r = import_volume(dir.file(v.name + ".vdb"), o);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->summary.mode, VolumeMode::Fog);
    const AnalyticComparison c = compare_to_analytic(r->world, v, 0.05);
    // 4/3 pi 0.8 * 0.4 * 1.2 = 1.608 = 12,868 blocks of 0.05³; extents 1.6 x 0.8 x 2.4 world units
    // = 32 x 16 x 48 blocks (an unscaled import would be a 32-voxel sphere: 32 x 32 x 32).
    EXPECT_NEAR(c.volume_error, 0.0, 0.01);
    EXPECT_LE(c.bounds_error, 1.0);
    const glm::dvec3 extent = (c.solid_max - c.solid_min) / 0.05;
    EXPECT_NEAR(extent.x, 32, 2);
    EXPECT_NEAR(extent.y, 16, 2);
    EXPECT_NEAR(extent.z, 48, 2);
    EXPECT_GE(c.iou, 0.98);
    std::printf("fog ellipsoid: %llu solid (truth %llu), IoU %.5f, volume error %+.3f%%, extent %g x %g x %g blocks\n",
                (unsigned long long)c.solid, (unsigned long long)c.truth_solid, c.iou, 100 * c.volume_error, extent.x,
                extent.y, extent.z);
}

TEST(VdbTransform, FrustumTransformsAreRefused) {
    test::TempDir dir;
    AnalyticVolume v = rotated_sphere();
    v.name = "frustum";
    v.frustum = true;
    Result<VolumeImport> r = write_and_import(dir, v, {});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("frustum"), std::string::npos) << r.error();
    EXPECT_EQ(r.error().find('\n'), std::string::npos);
    Result<std::vector<GridInfo>> g = list_grids(dir.file("frustum.vdb"));
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_EQ((*g)[0].transform, "NonlinearFrustumMap");
}

TEST(VdbTransform, BlockSizeMustBePositiveAndFinite) {
    test::TempDir dir;
    const AnalyticVolume v = rotated_sphere();
    const std::string path = dir.file("s.vdb");
    ASSERT_TRUE(write_analytic_vdb(path, v).ok());
    const double inf = std::numeric_limits<double>::infinity();
    for (double bad : {-0.2, std::nan(""), inf, -inf}) {
        VolumeImportOptions o;
        o.block_size = bad;
        Result<VolumeImport> r = import_volume(path, o);
        ASSERT_FALSE(r.ok()) << bad;
        EXPECT_NE(r.error().find("positive, finite"), std::string::npos) << r.error();
    }
    VolumeImportOptions o;
    o.block_size = 0.2;
    o.voxels_per_block = 2;
    EXPECT_FALSE(import_volume(path, o).ok());
    o = {};
    o.block_size = 6.5; // 65 voxels of 0.1.
    Result<VolumeImport> r = import_volume(path, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("more than 64"), std::string::npos) << r.error();
    o = {};
    o.voxels_per_block = 65;
    EXPECT_FALSE(import_volume(path, o).ok());
    for (double tiny : {1e-300, 1e-6}) { // Refused (range or block count), never undefined.
        o = {};
        o.block_size = tiny;
        r = import_volume(path, o);
        ASSERT_FALSE(r.ok()) << tiny;
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
    }
}

// --voxels-per-block N is --block-size N x voxel, exactly, on a rotated grid and an identity one;
// the default is one block per voxel.
TEST(VdbTransform, VoxelsPerBlockIsBlockSizeTimesVoxel) {
    test::TempDir dir;
    AnalyticVolume identity;
    identity.name = "identity_sphere";
    identity.centre = {0.3, -0.2, 0.1};
    identity.half_extent = glm::dvec3(10.0);
    for (const AnalyticVolume& v : {rotated_sphere(), identity}) {
        SCOPED_TRACE(v.name);
        const std::string path = dir.file(v.name + ".vdb");
        ASSERT_TRUE(write_analytic_vdb(path, v).ok());
        Result<std::vector<GridInfo>> g = list_grids(path);
        ASSERT_TRUE(g.ok()) << g.error();
        const double voxel = (*g)[0].voxel_size.x;
        for (int n : {1, 3}) {
            VolumeImportOptions a, b;
            a.voxels_per_block = n;
            b.block_size = n * voxel;
            Result<VolumeImport> ra = import_volume(path, a), rb = import_volume(path, b);
            ASSERT_TRUE(ra.ok() && rb.ok());
            EXPECT_GT(ra->summary.solid_blocks, 0u);
            EXPECT_TRUE(test::same_blocks(ra->world, rb->world)) << n;
            EXPECT_EQ(ra->summary.blocks.min, rb->summary.blocks.min);
            if (n == 1) {
                Result<VolumeImport> rd = import_volume(path);
                ASSERT_TRUE(rd.ok());
                EXPECT_TRUE(test::same_blocks(ra->world, rd->world));
            }
        }
    }
}

// On a grid whose voxel centres sit at (i + 1/2) * v (vx's own export convention) block b of N
// voxels covers exactly the voxel cells [N*b, N*b + N) per axis, the former lattice: the
// voxel-majority import at N equals the majority of the N³ one-voxel blocks of the import at N = 1
// (which are the voxels' own inside tests).
TEST(VdbTransform, HalfVoxelTranslationGivesTheFormerVoxelLattice) {
    test::TempDir dir;
    AnalyticVolume v;
    v.name = "identity_box";
    v.shape = AnalyticShape::Box;
    v.centre = {0.4, -0.3, 0.2};
    v.half_extent = {9.3, 6.2, 7.7};
    v.rotation = axis_rotation(20, {1, 1, 0});
    v.translation = glm::dvec3(0.5);
    const std::string path = dir.file("b.vdb");
    ASSERT_TRUE(write_analytic_vdb(path, v).ok());
    VolumeImportOptions o;
    o.sampling = VolumeSampling::VoxelMajority;
    Result<VolumeImport> one = import_volume(path, o);
    o.voxels_per_block = 3;
    Result<VolumeImport> three = import_volume(path, o);
    ASSERT_TRUE(one.ok() && three.ok());
    uint64_t solid = 0;
    for (int64_t z = -6; z <= 6; ++z)
        for (int64_t y = -6; y <= 6; ++y)
            for (int64_t x = -6; x <= 6; ++x) {
                int in = 0;
                for (int k = 0; k < 27; ++k)
                    in += one->world.get_block(BlockPos(3 * x + k % 3, 3 * y + k / 3 % 3, 3 * z + k / 9)) != world::kAir;
                const bool expect = 2 * in > 27;
                solid += expect;
                ASSERT_EQ(three->world.get_block(BlockPos(x, y, z)) != world::kAir, expect) << x << "," << y << "," << z;
            }
    EXPECT_EQ(solid, test::count_solid(three->world)); // And nothing beyond +-6 blocks (the box is < 13 voxels out).
    EXPECT_GT(solid, 0u);
}

// OpenVDB's voxel (i, j, k) is centred on world (i, j, k) (identity transform). A level-set cube
// from 0 to 10 has its faces on voxel centres; in world space it fills blocks 0..9 exactly. (The
// former index-space lattice, blocks centred on voxels, made the face blocks ties decided by a
// centre on the surface: 9³ = 729 blocks.)
TEST(VdbTransform, CubeWithFacesOnVoxelCentresHasItsExactVolume) {
    test::TempDir dir;
    AnalyticVolume v;
    v.name = "cube10";
    v.shape = AnalyticShape::Box;
    v.centre = glm::dvec3(5.0);
    v.half_extent = glm::dvec3(5.0);
    Result<VolumeImport> r = write_and_import(dir, v, {});
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->summary.solid_blocks, 1000u);
    const AnalyticComparison c = compare_to_analytic(r->world, v, 1.0);
    EXPECT_EQ(c.solid_min, glm::dvec3(0.0));
    EXPECT_EQ(c.solid_max, glm::dvec3(10.0));
}

} // namespace
} // namespace vx::vdb
