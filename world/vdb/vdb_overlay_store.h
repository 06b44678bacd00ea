#pragma once
// A VDB world that keeps its edits: a writable ChunkStore (the overlay: a SQLite file, or a
// PostgreSQL URI, opened through world/store/store_open.h) layered over the read-only VdbStore.
// Reads ask the overlay first, then the VDB grid; saves, commits, flushes and metadata go to the
// overlay only, so unloading, flush() and crashes behave as for any stored world and the VDB file
// is never written. An erased chunk is stored in the overlay as an all-air chunk (a tombstone
// that hides the VDB's chunk). export_overlay_vdb (below) writes the two merged without a
// VdbOverlayStore, streaming the file. Coarse levels (load_lod, save_lod, dirty marks) are the
// overlay's alone: they are derived from the combined world, and a VDB holds level 0 only.
//
// The overlay remembers which VDB file it edits (meta "vdb_file": size, modification time and
// xxh64 of the file's bytes, i.e. of its header and tree); opened against a file of another size
// or hash it is refused with one line. A file that was only copied (new mtime, same bytes) is
// accepted and the recorded mtime updated.
//
// Thread affinity: not thread-safe, like every ChunkStore (the engine's I/O lane); open() from
// one thread, which must be the only one running if the VDB is read isolated (vdb_isolated.h: it
// forks).

#include <cstdint>
#include <memory>
#include <string>

#include "world/store/chunk_store.h"
#include "world/vdb/vdb_store.h"

namespace vx::vdb {

struct VdbOverlayOpenInfo {
    std::string vdb_path;      // The VDB world (vx export-vdb); read, never written.
    std::string overlay;       // Store name (SQLite path or postgresql:// URI); empty:
                               // default_overlay_name(vdb_path).
    bool read_only = false;    // Open the overlay for reading only (it must exist): exports.
    VdbReadOptions read;       // How the VDB file is read (isolated by default).
};

// "<vdb_path>.edits.sqlite": the overlay beside the file. Thread-safe.
std::string default_overlay_name(const std::string& vdb_path);

// Identity of a VDB file as the overlay records it. A plain value.
struct VdbFileId {
    uint64_t size = 0;     // Bytes.
    int64_t mtime_ns = 0;  // Last modification, nanoseconds since the file-clock epoch.
    uint64_t xxh64 = 0;    // xxh64 (seed 0) of every byte of the file.
};
// Reads `path` once to compute its id (streamed in 1 MiB blocks). Thread-safe.
Result<VdbFileId> vdb_file_id(const std::string& path);

// What export_overlay_vdb did. A plain value.
struct VdbOverlayExport {
    uint64_t chunks = 0;  // Non-empty chunks written.
    std::string fallback; // Why the whole file was read through OpenVDB; empty when it streamed.
};

// Writes the VDB world info.vdb_path with its edits overlay merged (the overlay's chunks win; an
// erased chunk stays air) to `out`, atomically, as export_vdb does. The VDB file is read by the
// streaming reader (vdb_stream.h) in step with the writer, so memory stays flat in world size:
// one Internal4 node of each plus the overlay's chunk coordinates (12 bytes each). A file the
// streaming reader refuses (Blosc, other layouts, damage) is exported through VdbOverlayStore
// instead (OpenVDB's reader as info.read says, the whole file in memory), and the reason is
// returned. The overlay is opened read-only and must exist (info.read_only is ignored). Errors
// are one line. Not thread-safe; the fallback forks when info.read is isolated (vdb_isolated.h).
Result<VdbOverlayExport> export_overlay_vdb(const VdbOverlayOpenInfo& info, const std::string& out,
                                            const VdbExportOptions& options = {});

class VdbOverlayStore final : public world::ChunkStore {
public:
    // Reads the VDB (info.read), opens or creates the overlay and checks its binding. Errors are
    // one line naming the file or the overlay.
    static Result<std::unique_ptr<VdbOverlayStore>> open(const VdbOverlayOpenInfo& info);

    Result<world::ChunkLoad> load(world::ChunkCoord c) override;
    Status save(std::span<const world::ChunkWrite> batch) override;
    using world::ChunkStore::save;
    Status tick(Clock::time_point now) override { return m_overlay->tick(now); }
    Status flush() override { return m_overlay->flush(); }
    Result<bool> contains(world::ChunkCoord c) override;
    Result<uint64_t> count() override;
    // Overlay coordinates first, then the VDB's not in the overlay (memory: one set of the
    // overlay's coordinates).
    Status for_each_coord(const std::function<bool(world::ChunkCoord)>& fn) override;
    Result<std::optional<std::string>> get_meta(std::string_view key) override;
    Status set_meta(std::string_view key, std::string_view value) override { return m_overlay->set_meta(key, value); }
    bool read_only() const override { return m_overlay->read_only(); }
    using world::ChunkStore::save_lod;
    bool supports_lod() const override { return m_overlay->supports_lod(); }
    Result<world::ChunkLoad> load_lod(world::LodCoord c) override { return m_overlay->load_lod(c); }
    Status save_lod(std::span<const world::LodWrite> batch) override { return m_overlay->save_lod(batch); }
    Status mark_lod_dirty(std::span<const world::LodCoord> coords) override {
        return m_overlay->mark_lod_dirty(coords);
    }
    Result<std::vector<world::LodCoord>> list_lod_dirty() override { return m_overlay->list_lod_dirty(); }
    Result<std::vector<world::LodCoord>> list_lod_coords() override { return m_overlay->list_lod_coords(); }
    void poll_lod_changes(std::vector<world::LodCoord>& out) override { m_overlay->poll_lod_changes(out); }
    size_t pending_edits() const override { return m_overlay->pending_edits(); }
    bool poll_changes(std::vector<world::ChunkCoord>& out) override { return m_overlay->poll_changes(out); }
    world::StoreHealth health() const override { return m_overlay->health(); }

    // The VDB world's block registry (from the file's metadata).
    const world::BlockRegistry& registry() const { return m_base->world().registry(); }
    const std::string& overlay_name() const { return m_overlay_name; }

private:
    VdbOverlayStore(std::unique_ptr<VdbStore> base, std::unique_ptr<world::ChunkStore> overlay, std::string name)
        : m_base(std::move(base)), m_overlay(std::move(overlay)), m_overlay_name(std::move(name)) {}

    std::unique_ptr<VdbStore> m_base;
    std::unique_ptr<world::ChunkStore> m_overlay;
    std::string m_overlay_name;
};

} // namespace vx::vdb
