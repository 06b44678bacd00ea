#pragma once
// Wavefront OBJ export of chunk meshes. Vertices in world block units (exact 64-bit integers),
// one quad per face line, counter-clockwise seen from the air side, grouped by `usemtl block_<id>`.
// A companion .mtl gives each block its registry albedo. Not thread-safe.

#include <string>

#include "world/base/result.h"
#include "world/mesh/edit_mesher.h"

namespace vx::world {

struct ObjStats {
    uint64_t quads = 0;
    uint64_t vertices = 0;
};

// Writes every mesh of `meshes` to `path` (and mtl_path_for(path) for materials).
Result<ObjStats> write_obj(const std::string& path, const MeshMap& meshes, const BlockRegistry& registry);

// The materials file beside an OBJ: `path` with its extension replaced by .mtl (added if none).
std::string mtl_path_for(const std::string& path);

} // namespace vx::world
