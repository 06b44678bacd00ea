#pragma once
// A read-only ChunkStore backed by a vx-world VDB file (vdb_world.h), so the streaming engine can
// use an exported world as its source. The file is read once at open into palette chunks (the
// compact in-memory form, uniform chunks 16 bytes each); load() hands out copies. By default the
// file is read in a forked, capped child first (vdb_isolated.h), so a damaged file gives one line
// instead of taking the process down; VdbOverlayStore (vdb_overlay_store.h) layers edits over it.
// Limitation: the whole file (or the box given) is held in memory as chunks; very large VDB worlds
// should be imported into an SqliteStore instead (vx import-vdb). Exports need no VdbStore:
// export_overlay_vdb (vdb_overlay_store.h) streams the file (vdb_stream.h).
// Thread affinity: not thread-safe, like every ChunkStore: one thread (the engine's I/O lane).

#include <memory>
#include <string>

#include "world/store/chunk_store.h"
#include "world/vdb/vdb_isolated.h"
#include "world/vdb/vdb_world.h"
#include "world/world.h"

namespace vx::vdb {

struct VdbReadOptions {
    VdbWorldImportOptions import;
    // Read in a forked child under `isolation`'s caps (the caller must be single-threaded at the
    // call, see vdb_isolated.h). False: read in the calling process (files vx just wrote).
    bool isolated = true;
    IsolationOptions isolation;
};

class VdbStore final : public world::ChunkStore {
public:
    // Reads `path` as `options` says. Errors are one line naming the file.
    static Result<std::unique_ptr<VdbStore>> open(const std::string& path, const VdbReadOptions& options = {});

    Result<world::ChunkLoad> load(world::ChunkCoord c) override;
    Status save(std::span<const world::ChunkWrite> batch) override;
    using world::ChunkStore::save;
    Status tick(Clock::time_point) override { return {}; }
    Status flush() override { return {}; }
    Result<bool> contains(world::ChunkCoord c) override { return m_world.find_chunk(c) != nullptr; }
    Result<uint64_t> count() override { return uint64_t(m_world.chunk_count()); }
    Status for_each_coord(const std::function<bool(world::ChunkCoord)>& fn) override;
    Result<std::optional<std::string>> get_meta(std::string_view key) override;
    Status set_meta(std::string_view, std::string_view) override;
    bool read_only() const override { return true; }

    const world::World& world() const { return m_world; }

private:
    explicit VdbStore(world::World w, std::string path) : m_world(std::move(w)), m_path(std::move(path)) {}
    world::World m_world;
    std::string m_path;
};

} // namespace vx::vdb
