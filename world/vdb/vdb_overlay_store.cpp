#include "world/vdb/vdb_overlay_store.h"

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <unordered_set>
#include <vector>

#include <xxhash.h>

#include "world/store/pg_store.h"
#include "world/store/store_open.h"

namespace vx::vdb {
namespace {

constexpr const char* kBindingKey = "vdb_file";

std::string format_id(const VdbFileId& id) {
    char s[128];
    std::snprintf(s, sizeof s, "size=%" PRIu64 " mtime_ns=%" PRId64 " xxh64=%016" PRIx64, id.size, id.mtime_ns,
                  id.xxh64);
    return s;
}

std::optional<VdbFileId> parse_id(const std::string& s) {
    VdbFileId id;
    if (std::sscanf(s.c_str(), "size=%" SCNu64 " mtime_ns=%" SCNd64 " xxh64=%" SCNx64, &id.size, &id.mtime_ns,
                    &id.xxh64) != 3)
        return std::nullopt;
    return id;
}

// Records the file's id in a new overlay, accepts a copy of the same bytes (updating its mtime),
// refuses another file.
Status check_binding(world::ChunkStore& overlay, const std::string& overlay_name, const std::string& vdb_path,
                     const VdbFileId& id, bool read_only) {
    auto stored = overlay.get_meta(kBindingKey);
    if (!stored)
        return Error{stored.error()};
    std::string shown = "'"; // Appended piecewise: g++ 12 warns (-Wrestrict) on "'" + std::string&&.
    shown += world::store_display_name(overlay_name);
    shown += "'";
    if (!*stored) {
        Result<uint64_t> n = overlay.count();
        if (!n)
            return Error{n.error()};
        if (*n > 0)
            return Error{shown + " holds chunks but names no VDB file: it is not an edit overlay of '" + vdb_path + "'"};
        return read_only ? Status{} : overlay.set_meta(kBindingKey, format_id(id));
    }
    const std::optional<VdbFileId> was = parse_id(**stored);
    if (!was)
        return Error{shown + " has a damaged VDB binding ('" + **stored + "')"};
    if (was->size != id.size || was->xxh64 != id.xxh64)
        return Error{shown + " holds edits of another VDB file (" + format_id(*was) + ") than '" + vdb_path + "' (" +
                     format_id(id) + "): open that file, or name another overlay"};
    if (was->mtime_ns != id.mtime_ns && !read_only)
        return overlay.set_meta(kBindingKey, format_id(id));
    return {};
}

} // namespace

std::string default_overlay_name(const std::string& vdb_path) { return vdb_path + ".edits.sqlite"; }

Result<VdbFileId> vdb_file_id(const std::string& path) {
    std::error_code ec;
    const auto mtime = std::filesystem::last_write_time(path, ec);
    if (ec)
        return Error{"cannot read '" + path + "': " + ec.message()};
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f)
        return Error{"cannot read '" + path + "'"};
    XXH64_state_t* state = XXH64_createState();
    XXH64_reset(state, 0);
    std::vector<char> buf(size_t(1) << 20);
    VdbFileId id;
    size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) {
        XXH64_update(state, buf.data(), n);
        id.size += n;
    }
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    id.xxh64 = XXH64_digest(state);
    XXH64_freeState(state);
    if (failed)
        return Error{"cannot read '" + path + "': read error"};
    id.mtime_ns = int64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(mtime.time_since_epoch()).count());
    return id;
}

Result<std::unique_ptr<VdbOverlayStore>> VdbOverlayStore::open(const VdbOverlayOpenInfo& info) {
    const std::string name = info.overlay.empty() ? default_overlay_name(info.vdb_path) : info.overlay;
    // The id first: it reads the file in this process, but only as bytes.
    Result<VdbFileId> id = vdb_file_id(info.vdb_path);
    if (!id)
        return Error{id.error()};
    auto base = VdbStore::open(info.vdb_path, info.read);
    if (!base)
        return Error{base.error()};
    std::error_code ec;
    if (info.read_only && !world::is_pg_uri(name) && !std::filesystem::exists(name, ec))
        return Error{"'" + info.vdb_path + "' has no edits overlay ('" + name +
                     "'): the file alone is the whole world"};
    auto overlay = world::open_store(
        {.name = name, .read_only = info.read_only, .create = !info.read_only, .listen = !info.read_only});
    if (!overlay)
        return Error{"the edits of '" + info.vdb_path + "': " + overlay.error()};
    if (Status s = check_binding(**overlay, name, info.vdb_path, *id, info.read_only); !s)
        return Error{s.error()};
    if (!info.read_only) // The binding is durable before any edit can be.
        if (Status s = (*overlay)->flush(); !s)
            return Error{s.error()};
    return std::unique_ptr<VdbOverlayStore>(new VdbOverlayStore(std::move(*base), std::move(*overlay), name));
}

Result<world::ChunkLoad> VdbOverlayStore::load(world::ChunkCoord c) {
    Result<world::ChunkLoad> mine = m_overlay->load(c);
    if (!mine || mine->state != world::LoadState::Absent)
        return mine;
    return m_base->load(c);
}

Status VdbOverlayStore::save(std::span<const world::ChunkWrite> batch) {
    // An erase must hide the VDB's chunk: store air instead of removing the overlay's record.
    static const world::Chunk kAirChunk(world::kAir);
    std::vector<world::ChunkWrite> writes(batch.begin(), batch.end());
    for (world::ChunkWrite& w : writes)
        if (!w.chunk) {
            w.chunk = &kAirChunk;
            w.edits = {};
            w.record = {};
        }
    return m_overlay->save(writes);
}

Result<bool> VdbOverlayStore::contains(world::ChunkCoord c) {
    Result<bool> mine = m_overlay->contains(c);
    if (!mine || *mine)
        return mine;
    return m_base->contains(c);
}

Result<uint64_t> VdbOverlayStore::count() {
    uint64_t n = 0;
    auto counter = [&](world::ChunkCoord) {
        ++n;
        return true;
    };
    if (Status s = for_each_coord(counter); !s)
        return Error{s.error()};
    return n;
}

Status VdbOverlayStore::for_each_coord(const std::function<bool(world::ChunkCoord)>& fn) {
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> mine;
    bool go = true;
    if (Status s = m_overlay->for_each_coord([&](world::ChunkCoord c) {
            mine.insert(c);
            return go = fn(c);
        });
        !s)
        return s;
    if (!go)
        return {};
    return m_base->for_each_coord([&](world::ChunkCoord c) { return mine.count(c) ? true : fn(c); });
}

Result<std::optional<std::string>> VdbOverlayStore::get_meta(std::string_view key) {
    auto mine = m_overlay->get_meta(key);
    if (!mine || *mine)
        return mine;
    return m_base->get_meta(key);
}

} // namespace vx::vdb
