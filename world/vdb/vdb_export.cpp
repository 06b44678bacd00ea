// export_vdb and export_store_vdb (vdb_world.h) through the streaming writer (vdb_stream.h): the
// chunks go out in file order, one Internal4 node held at a time. No OpenVDB here.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "world/vdb/vdb_stream.h"
#include "world/vdb/vdb_world.h"

namespace vx::vdb {
namespace {

bool outside(world::ChunkCoord c, const VdbExportOptions& options) {
    if (!options.box)
        return false;
    const world::BlockPos lo = world::chunk_origin(c), hi = lo + world::BlockPos(world::kChunkSize - 1);
    const BlockBox& b = *options.box;
    return hi.x < b.min.x || hi.y < b.min.y || hi.z < b.min.z || lo.x > b.max.x || lo.y > b.max.y || lo.z > b.max.z;
}

} // namespace

Status export_vdb(const world::World& w, const std::string& path, const VdbExportOptions& options) {
    std::vector<world::ChunkCoord> coords;
    coords.reserve(w.chunk_count());
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) {
        if (!outside(c, options))
            coords.push_back(c);
    });
    std::sort(coords.begin(), coords.end(), file_order_less);
    auto writer = VdbStreamWriter::create(path, w.registry(), options);
    if (!writer)
        return Error{writer.error()};
    for (const world::ChunkCoord c : coords)
        if (Status s = (*writer)->add(c, *w.find_chunk(c)); !s)
            return s;
    return (*writer)->finish();
}

Result<uint64_t> export_store_vdb(world::ChunkStore& store, const world::BlockRegistry& registry, const std::string& path,
                        const VdbExportOptions& options) {
    // The coordinates first (12 bytes each): for_each_coord's callback may not call the store.
    Result<std::vector<world::ChunkCoord>> coords = store.list_coords();
    if (!coords)
        return Error{"cannot export to '" + path + "': " + coords.error()};
    std::erase_if(*coords, [&](world::ChunkCoord c) { return outside(c, options); });
    std::sort(coords->begin(), coords->end(), file_order_less);
    auto writer = VdbStreamWriter::create(path, registry, options);
    if (!writer)
        return Error{writer.error()};
    for (const world::ChunkCoord c : *coords) {
        Result<world::ChunkLoad> load = store.load(c);
        if (!load)
            return Error{"cannot export to '" + path + "': " + load.error()};
        if (load->state == world::LoadState::Corrupt) {
            char where[96];
            std::snprintf(where, sizeof where, "chunk (%d, %d, %d) is damaged: ", c.x, c.y, c.z);
            return Error{"cannot export to '" + path + "': " + where + load->problem};
        }
        if (load->state == world::LoadState::Present)
            if (Status s = (*writer)->add(c, *load->chunk); !s)
                return Error{s.error()};
    }
    if (Status s = (*writer)->finish(); !s)
        return Error{s.error()};
    return (*writer)->chunks_written();
}

} // namespace vx::vdb
