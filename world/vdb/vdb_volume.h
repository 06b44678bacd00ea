#pragma once
// Import of arbitrary OpenVDB volumes (level sets and fog volumes made by other tools) as blocks.
//
// Block lattice, in the file's world space: with a block size of s world units, block
// (bx, by, bz) is the world cell [s*bx, s*bx + s) x [s*by, ...) x [s*bz, ...), i.e. a world point p
// lies in block floor(p / s); the world block is (bx, by, bz) + offset. The grid's transform is
// honoured whole (rotation, non-uniform scale, shear, translation): a block's cell maps to a
// parallelepiped in index space, sampled through the inverse map. OpenVDB index coordinates name
// voxel centres, so with an identity transform and s = B the block (bx, ...) spans index
// [B*bx, B*bx + B) and holds the voxels B*bx .. B*bx + B - 1 (their centres lie in its cell).
// Non-linear (frustum) transforms are refused: blocks of one size cannot follow voxels that grow
// with depth.
//
// Classification (VolumeSampling::Adaptive, the default): the volume is the trilinear
// interpolation of the voxel values; a block is solid when more than half of its volume is inside,
// estimated by supersampling (samples_per_axis³ points evenly spread over the block's cell,
// redone at twice the rate per axis when the solid fraction is within 0.075 of one half; an exact
// tie goes to the centre sample). Blocks that cannot straddle the surface skip supersampling:
//   level set: inside = negative signed distance. A block whose centre lies farther than half
//     its longest diagonal + one voxel (in index space) from the zero crossing takes the sign at
//     its centre; distances are taken as world units of the grid's largest voxel edge (exact for
//     uniform voxels, conservative otherwise). Values outside the narrow band are inactive and
//     carry +-background; their sign is used as is (the interior is inside; no pruneInactive,
//     which would flip it).
//   fog: inside = value >= threshold * (the grid's largest active value). A block whose
//     neighbourhood voxels are all on one side of the threshold is decided without sampling
//     (trilinear values lie between their corners'). Inactive voxels count as the background,
//     which must be below the threshold.
// Chunks no leaf or active tile touches are decided by one sample (uniform).
// Untrusted input: bounds come from the tree (never from file metadata), empty grids, point grids,
// vector grids, degenerate or non-linear transforms and sizes above max_blocks are refused, every
// OpenVDB exception is caught.

#include <cstdint>
#include <string>
#include <vector>

#include "world/base/result.h"
#include "world/coords.h"
#include "world/vdb/vdb_world.h"
#include "world/world.h"

namespace vx::vdb {

// One grid of a file as list_grids reports it.
struct GridInfo {
    int index = 0;                 // Position in the file (names may repeat or be empty).
    std::string name;
    std::string value_type;        // OpenVDB value type: "float", "double", "vec3s", "ptdataidx32", ...
    std::string grid_class;        // "level set", "fog volume", "staggered" or "unknown".
    glm::dvec3 voxel_size{0.0};    // World units per voxel (per index axis).
    std::string transform;         // OpenVDB map type: "UniformScaleMap", "AffineMap", "NonlinearFrustumMap", ...
    uint64_t active_voxels = 0;    // Counted from the tree (tiles count all their voxels).
    bool empty = true;             // No active voxels; the bbox is then meaningless.
    glm::ivec3 bbox_min{0};        // Active voxels, index space, inclusive; computed from the tree.
    glm::ivec3 bbox_max{-1};
    bool saved_as_half = false;    // File metadata "is_saved_as_half_float".
};

// Lists every grid of a VDB file (reading all of them). Runs in the calling thread. Thread-safe.
Result<std::vector<GridInfo>> list_grids(const std::string& path);

enum class VolumeMode {
    Auto,     // The grid's class; an "unknown" class is a level set when background > 0 and some value < 0.
    LevelSet, // Solid where the signed distance is negative.
    Fog,      // Solid where the density is at least threshold * max.
};

enum class VolumeSampling {
    Adaptive,      // Supersample (with refinement) where the block may straddle the surface: level
                   // sets test the centre's distance first; fog tests the block's neighbourhood range.
    CentreOnly,    // One (trilinear) sample at each block centre. Cheapest, least accurate.
    VoxelMajority, // More than half of the block inside with box reconstruction (each voxel fills its
                   // cell, no interpolation): 2 nearest-voxel samples per voxel spacing and axis (<= 32).
    Supersample,   // samples_per_axis³ trilinear samples per block, majority vote (the reference).
};

// Maps a fog block's mean relative density (mean of its voxels / max) to a block id: the entry
// with the largest min_density <= the mean wins (entries need not be sorted).
struct DensityBlock {
    float min_density = 0.f; // Relative to the grid's max, 0..1.
    world::BlockId block = 1;
};

struct VolumeImportOptions {
    std::string grid_name;   // Select by name (must be unique in the file) ...
    int grid_index = -1;     // ... or by index (list_grids); neither: the first scalar grid.
    // Block edge in the file's world units (finite, > 0), at most 64 of the grid's smallest
    // voxel edges. 0: the grid's voxel size (one block per voxel; grids with uniform voxels only).
    double block_size = 0;
    // > 0: block_size = voxels_per_block * the grid's voxel size (uniform voxels only; 1..64),
    // the former meaning of an integer block size. Exclusive with block_size.
    int voxels_per_block = 0;
    VolumeMode mode = VolumeMode::Auto;
    float threshold = 0.25f; // Fog: relative to the grid's largest active value, in (0, 1].
    world::BlockId block = 1; // Id of solid blocks (1 = stone in the default registry).
    std::vector<DensityBlock> density_blocks; // Fog only: overrides `block` when not empty.
    world::BlockPos offset{0};                // Added to every block coordinate.
    VolumeSampling sampling = VolumeSampling::Adaptive;
    int samples_per_axis = 4;                 // Supersampling density, 1..16 (refinement doubles it, up to 16).
    uint64_t max_blocks = uint64_t(1) << 28;  // Refuse volumes whose block bbox holds more blocks.
};

struct VolumeImportSummary {
    int grid_index = 0;
    std::string grid_name;
    VolumeMode mode = VolumeMode::Auto;       // The mode used (never Auto).
    glm::dvec3 voxel_size{0.0};               // World units per voxel (per index axis).
    double block_size = 0;                    // World units per block edge, as used.
    double threshold_absolute = 0.0;          // Fog: threshold * max; level set: 0.
    double max_value = 0.0;                   // Largest active value.
    uint64_t solid_blocks = 0;
    uint64_t supersampled_blocks = 0;
    BlockBox blocks;                          // Block bbox considered (inclusive), offset applied: the
                                              // blocks the active voxels' cells reach in world space.
};

struct VolumeImport {
    world::World world;
    VolumeImportSummary summary;
};

// Converts one grid of a VDB file to blocks (see the top of this header). The result is a new
// World with the default registry; nothing on disk changes, so a failed import leaves any output
// untouched. Fails with a one-line reason naming the option to change. Runs in the calling thread.
// Thread-safe. For untrusted files see import_volume_isolated (vdb_isolated.h).
Result<VolumeImport> import_volume(const std::string& path, const VolumeImportOptions& options = {});

// Option names as a CLI would spell them ("levelset", "centre", ...). Thread-safe.
const char* to_string(VolumeMode mode);
const char* to_string(VolumeSampling sampling);

} // namespace vx::vdb
