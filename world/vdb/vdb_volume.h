#pragma once
// Import of arbitrary OpenVDB volumes (level sets and fog volumes made by other tools) as blocks.
//
// Block lattice: with a block size of B voxels, block (bx, by, bz) covers the B³ voxels with index
// coordinates [B*bx, B*bx + B) per axis. OpenVDB index coordinates name voxel centres, so in
// continuous index space the block spans [B*bx - 0.5, B*bx + B - 0.5) and its centre lies at
// B*bx + (B - 1) / 2 (a voxel centre for odd B, between voxels for even B, where the value is
// interpolated trilinearly). The world block is (bx, by, bz) + offset.
//
// Classification (VolumeSampling::Adaptive, the default): the volume is the trilinear
// interpolation of the voxel values; a block is solid when more than half of its volume is inside,
// estimated by supersampling (samples_per_axis³ points, redone at twice the rate per axis when
// the solid fraction is within 0.075 of one half; an exact tie goes to the centre sample). Blocks
// that cannot straddle the surface skip supersampling:
//   level set: inside = negative signed distance. A block whose centre lies farther than half a
//     block diagonal + one voxel from the zero crossing takes the sign at its centre. Values
//     outside the narrow band are inactive and carry +-background; their sign is used as is (the
//     interior is inside; no pruneInactive, which would flip it).
//   fog: inside = value >= threshold * (the grid's largest active value). A block whose
//     neighbourhood voxels are all on one side of the threshold is decided without sampling
//     (trilinear values lie between their corners'). Inactive voxels count as the background,
//     which must be below the threshold.
// Chunks no leaf or active tile touches are decided by one sample (uniform).
// Untrusted input: bounds come from the tree (never from file metadata), empty grids, point grids,
// vector grids and sizes above max_blocks are refused, every OpenVDB exception is caught.

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
    glm::dvec3 voxel_size{0.0};    // World units per voxel (per axis).
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
    VoxelMajority, // More than half of the block's B³ voxels inside (box filter, no interpolation).
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
    int block_size = 1;      // Voxels per block edge, 1..64.
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
    glm::dvec3 voxel_size{0.0};
    int block_size = 1;
    double threshold_absolute = 0.0;          // Fog: threshold * max; level set: 0.
    double max_value = 0.0;                   // Largest active value.
    uint64_t solid_blocks = 0;
    uint64_t supersampled_blocks = 0;
    BlockBox blocks;                          // World block bbox considered (inclusive), offset applied.
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
