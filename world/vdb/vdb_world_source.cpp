// Registers VdbOverlayStore (or, read-only, VdbStore) as the opener of VDB world sources
// (world/store/store_open.h) when vx_vdb is linked into a program. Nothing references this object, so vx_vdb's target passes the linker
// `--undefined=vx_vdb_world_source` (world/vdb/CMakeLists.txt), which pulls it out of the archive.
#include "world/store/store_open.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world/vdb/vdb_store.h"

namespace {

vx::Result<std::unique_ptr<vx::world::ChunkStore>> open_vdb_world(const vx::world::VdbWorldOpenInfo& info) {
    if (info.read_only) {
        auto store = vx::vdb::VdbStore::open(info.path);
        if (!store)
            return vx::Error{store.error()};
        return std::unique_ptr<vx::world::ChunkStore>(std::move(*store));
    }
    auto store = vx::vdb::VdbOverlayStore::open(
        {.vdb_path = info.path, .overlay = info.overlay, .read_only = false, .read = {}});
    if (!store)
        return vx::Error{store.error()};
    return std::unique_ptr<vx::world::ChunkStore>(std::move(*store));
}

} // namespace

// Dynamic initialisation before main: the engine reads the opener only from Engine::create.
extern "C" int vx_vdb_world_source;
int vx_vdb_world_source = (vx::world::set_vdb_store_opener(&open_vdb_world), 1);
