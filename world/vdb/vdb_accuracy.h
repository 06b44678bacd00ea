#pragma once
// Accuracy of volume import: each sampling strategy against a reference classification that
// supersamples every block 8³ times (majority vote), for a list of block sizes. Meant for
// `vx bench vdb` and the vx_vdb_accuracy program; not a test (it takes seconds per file).

#include <span>
#include <string>
#include <vector>

#include "world/base/result.h"
#include "world/vdb/vdb_analytic.h"
#include "world/vdb/vdb_volume.h"

namespace vx::vdb {

struct AccuracyRow {
    std::string grid_name;
    VolumeMode mode = VolumeMode::Auto;   // As resolved by the import (LevelSet or Fog).
    double block_size = 0;                // World units per block edge.
    double voxels_per_block = 0;          // block_size / the grid's smallest voxel edge.
    VolumeSampling sampling = VolumeSampling::Adaptive;
    uint64_t solid = 0;                   // Solid blocks of this import.
    uint64_t reference_solid = 0;         // Solid blocks of the reference.
    uint64_t mismatched = 0;              // Blocks classified differently from the reference.
    double iou = 0;                       // |A ∩ R| / |A ∪ R| over solid blocks (1 when both empty).
    double max_surface_distance = 0;      // Blocks: largest distance of a mismatched block's centre
    double mean_surface_distance = 0;     //   to the reference surface (capped at 8).
    double import_seconds = 0;            // Wall time of import_volume (file read included).
    uint64_t supersampled = 0;            // Blocks the import supersampled.
    double truth_iou = -1;                // Against the analytic shape (see compare_to_analytic); -1: none.
    double volume_error = 0;              // Solid volume / analytic volume - 1 (analytic shapes only).
    double bounds_error = 0;              // Blocks: largest gap between solid and analytic bounds (ditto).
};

// An import against the exact shape it came from. The truth is the same rule as the importer's,
// applied to the exact distance instead of the voxels: a block is solid when more than half of
// 8³ points spread over its world cell are inside, a tie going to the centre (blocks whose centre
// is farther than half a block diagonal from the surface take the centre's side).
struct AnalyticComparison {
    uint64_t solid = 0, truth_solid = 0, both = 0, either = 0;
    double iou = 1;                       // both / either (1 when both are empty).
    double volume_error = 0;              // solid * block_size³ / analytic_volume - 1.
    glm::dvec3 solid_min{0.0}, solid_max{0.0}; // World bounds of the solid blocks (offset removed).
    double bounds_error = 0;              // Largest |solid bound - analytic bound| over the 6 sides, in blocks.
};

// `world` holds an import of `shape` at `block_size` (world units) moved by `offset` blocks.
// Not thread-safe with respect to `world`.
AnalyticComparison compare_to_analytic(const world::World& world, const AnalyticVolume& shape, double block_size,
                                       world::BlockPos offset = world::BlockPos(0));

// Imports grid `base.grid_index` / `base.grid_name` of `path` at each block size with the
// Adaptive, VoxelMajority and CentreOnly samplings (rows in that order per block size) and
// compares each with the 8³ reference, and with `truth` when given. Block size N means
// voxels_per_block = N, or N * base.block_size world units when base.block_size > 0 (grids with
// non-cubic voxels). Not thread-safe (times itself); run it alone for meaningful times.
Result<std::vector<AccuracyRow>> measure_vdb_accuracy(const std::string& path, std::span<const int> block_sizes,
                                                      const VolumeImportOptions& base = {},
                                                      const AnalyticVolume* truth = nullptr);

struct WorldRoundTripStats {
    uint64_t chunks = 0;        // Chunks of the world.
    uint64_t file_bytes = 0;    // Size of the .vdb.
    double export_seconds = 0;  // export_vdb, file write included.
    double import_seconds = 0;  // import_world_vdb, file read included.
    bool exact = false;         // Every block read back equal.
};

// Exports `world` to `path`, reads it back and compares. For `vx bench vdb`. Not thread-safe with
// respect to `world`.
Result<WorldRoundTripStats> measure_world_roundtrip(const world::World& world, const std::string& path,
                                                    const VdbExportOptions& options = {});

// A fixed-width text table of rows, one line each, with a header. Thread-safe.
std::string format_accuracy_table(std::span<const AccuracyRow> rows);

} // namespace vx::vdb
