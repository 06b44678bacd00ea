#include "world/vdb/vdb_store.h"

namespace vx::vdb {

Result<std::unique_ptr<VdbStore>> VdbStore::open(const std::string& path, const VdbReadOptions& options) {
    Result<world::World> w = options.isolated ? import_world_vdb_isolated(path, options.import, options.isolation)
                                              : import_world_vdb(path, options.import);
    if (!w)
        return Error{w.error()};
    return std::unique_ptr<VdbStore>(new VdbStore(std::move(*w), path));
}

Result<world::ChunkLoad> VdbStore::load(world::ChunkCoord c) {
    world::ChunkLoad out;
    if (const world::Chunk* chunk = m_world.find_chunk(c)) {
        out.state = world::LoadState::Present;
        out.chunk = *chunk;
    }
    return out;
}

Status VdbStore::save(std::span<const world::ChunkWrite>) {
    return Error{"'" + m_path + "' is a read-only VDB world: import it into a store (vx import-vdb) to edit it"};
}

Status VdbStore::for_each_coord(const std::function<bool(world::ChunkCoord)>& fn) {
    bool go = true;
    m_world.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) {
        if (go)
            go = fn(c);
    });
    return {};
}

Result<std::optional<std::string>> VdbStore::get_meta(std::string_view key) {
    if (key == "source")
        return std::optional<std::string>(m_path);
    return std::optional<std::string>();
}

Status VdbStore::set_meta(std::string_view, std::string_view) {
    return Error{"'" + m_path + "' is a read-only VDB world"};
}

} // namespace vx::vdb
