#include "world/io/obj_export.h"

#include "world/base/file_replace.h"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

namespace vx::world {

std::string mtl_path_for(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
        return path.substr(0, dot) + ".mtl";
    return path + ".mtl";
}

namespace {

std::string base_name(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

} // namespace

Result<ObjStats> write_obj(const std::string& path, const MeshMap& meshes, const BlockRegistry& registry) {
    // Group quads by block so each material appears once; chunks sorted for a stable file.
    std::vector<ChunkCoord> coords;
    for (const auto& [c, mc] : meshes)
        coords.push_back(c);
    std::sort(coords.begin(), coords.end(), [](const ChunkCoord& a, const ChunkCoord& b) {
        return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
    });
    std::map<BlockId, std::vector<std::pair<ChunkCoord, Quad>>> by_block;
    for (const ChunkCoord& c : coords)
        meshes.at(c).mesh.for_each_quad([&](const Quad& q) { by_block[q.block].push_back({c, q}); });

    // Both files go through temporaries: a failed export leaves the previous pair, not a cut one.
    const std::string mtl = mtl_path_for(path);
    ReplacingFile m;
    if (Status s = m.open(mtl, "w"); !s)
        return Error{s.error()};
    for (const auto& [id, quads] : by_block) {
        const glm::vec3 a = registry.info(id).albedo;
        std::fprintf(m.get(), "newmtl block_%u\nKd %.4f %.4f %.4f\n", unsigned(id), a.r, a.g, a.b);
    }
    if (Status s = m.finish(); !s)
        return Error{s.error()};

    ReplacingFile f;
    if (Status s = f.open(path, "w"); !s)
        return Error{s.error()};
    std::fprintf(f.get(), "# vx mesh export: world block units, CCW faces seen from the air side\nmtllib %s\n",
                 base_name(mtl).c_str());
    ObjStats stats;
    for (const auto& [id, quads] : by_block) {
        std::fprintf(f.get(), "usemtl block_%u\n", unsigned(id));
        for (const auto& [c, q] : quads) {
            const BlockPos o = chunk_origin(c);
            glm::ivec3 corners[4];
            quad_corners(q, corners);
            for (const glm::ivec3& p : corners)
                std::fprintf(f.get(), "v %" PRId64 " %" PRId64 " %" PRId64 "\n", o.x + p.x, o.y + p.y, o.z + p.z);
            std::fprintf(f.get(), "f -4 -3 -2 -1\n");
            stats.quads += 1;
            stats.vertices += 4;
        }
    }
    for (ReplacingFile* file : {&f, &m})
        if (Status s = file->commit(); !s)
            return Error{s.error()};
    return stats;
}

} // namespace vx::world
