#pragma once
// The whole-tree export through OpenVDB (the library's export before the streaming writer): the
// reference that tests compare the streaming writer and reader with. Test code only.

#include <map>
#include <string>

#include "world/vdb/vdb_world.h"

namespace vx::vdb::test {

// Builds the tree of `w` in memory (uniform chunks as tiles, then prune()) and writes it with
// openvdb::io::File, metadata as vdb_world.h describes. Not thread-safe.
// With `blosc`, the values are Blosc-compressed (OpenVDB's default when built with it, as
// Debian's is; the streaming reader refuses it) instead of options.compression.
Status write_world_openvdb(const world::World& w, const std::string& path, const VdbExportOptions& options = {},
                           bool blosc = false);

// A "blocks" grid with one active root tile (4096³ blocks of id 3 from the origin) and one voxel
// of id 5 at (-1, -1, -1), as OpenVDB writes it.
Status write_root_tile_openvdb(const std::string& path);

// The "blocks" grid of `in` written to `out` with a linear transform of `voxel_size` world units
// per voxel (the blocks stay where their index coordinates say).
Status rescale_openvdb(const std::string& in, const std::string& out, double voxel_size);

// The "blocks" grid of `in` written to `out` after two others: "terrain" (an int32 tree) and
// "terrain_copy", which shares its tree, so OpenVDB writes it as an instance (no tree, block
// offset 0).
Status prepend_instanced_grids_openvdb(const std::string& in, const std::string& out);

// The "blocks" grid's metadata read by OpenVDB, as key -> Metadata::str(); empty on failure.
std::map<std::string, std::string> grid_meta_openvdb(const std::string& path);

} // namespace vx::vdb::test
