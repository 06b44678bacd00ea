#include "world/vdb/vdb_overlay_store.h"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <unordered_set>
#include <vector>

#include <xxhash.h>

#include "world/store/pg_store.h"
#include "world/store/store_open.h"
#include "world/vdb/vdb_stream.h"

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

namespace {

// Opens the overlay of info.vdb_path (whose id is `id`) and checks its binding.
Result<std::unique_ptr<world::ChunkStore>> open_overlay(const VdbOverlayOpenInfo& info, const std::string& name,
                                                        const VdbFileId& id) {
    std::error_code ec;
    if (info.read_only && !world::is_pg_uri(name) && !std::filesystem::exists(name, ec))
        return Error{"'" + info.vdb_path + "' has no edits overlay ('" + name +
                     "'): the file alone is the whole world"};
    auto overlay = world::open_store(
        {.name = name, .read_only = info.read_only, .create = !info.read_only, .listen = !info.read_only});
    if (!overlay)
        return Error{"the edits of '" + info.vdb_path + "': " + overlay.error()};
    if (Status s = check_binding(**overlay, name, info.vdb_path, id, info.read_only); !s)
        return Error{s.error()};
    if (!info.read_only) // The binding is durable before any edit can be.
        if (Status s = (*overlay)->flush(); !s)
            return Error{s.error()};
    return std::move(*overlay);
}

bool node_less(world::ChunkCoord a, world::ChunkCoord b) { return file_order_less(node_of(a) * 4, node_of(b) * 4); }

// The streaming merge: VDB nodes and the overlay's chunks in file order into `writer`. Errors of
// the VDB file come back in `vdb_error` (the caller falls back), others as the result.
Status merge_stream(VdbStreamReader& reader, world::ChunkStore& overlay, std::vector<world::ChunkCoord>& edits,
                    VdbStreamWriter& writer, std::string& vdb_error) {
    std::vector<std::pair<world::ChunkCoord, world::Chunk>> node;
    const auto next = [&]() -> bool {
        Result<bool> more = reader.next(node);
        if (!more)
            vdb_error = more.error();
        return more && *more;
    };
    const auto add_edit = [&](world::ChunkCoord c) -> Status {
        Result<world::ChunkLoad> load = overlay.load(c);
        if (!load)
            return Error{load.error()};
        if (load->state == world::LoadState::Corrupt) {
            char where[96];
            std::snprintf(where, sizeof where, "chunk (%d, %d, %d) of the edits is damaged: ", c.x, c.y, c.z);
            return Error{where + load->problem};
        }
        return load->state == world::LoadState::Present ? writer.add(c, *load->chunk) : Status{};
    };
    bool more = next();
    size_t e = 0;
    while (vdb_error.empty() && (more || e < edits.size())) {
        const bool vdb_first = more && (e == edits.size() || !node_less(edits[e], node[0].first));
        const bool edits_first = e < edits.size() && (!more || !node_less(node[0].first, edits[e]));
        const size_t e_end = edits_first ? size_t(std::find_if(edits.begin() + ptrdiff_t(e), edits.end(),
                                                               [&](world::ChunkCoord c) {
                                                                   return node_of(c) != node_of(edits[e]);
                                                               }) - edits.begin())
                                         : e;
        if (vdb_first) { // This node's VDB chunks, less those the overlay replaces.
            for (const auto& [c, chunk] : node)
                if (std::find(edits.begin() + ptrdiff_t(e), edits.begin() + ptrdiff_t(e_end), c) ==
                    edits.begin() + ptrdiff_t(e_end))
                    if (Status s = writer.add(c, chunk); !s)
                        return s;
            more = next();
        }
        for (; e < e_end; ++e)
            if (Status s = add_edit(edits[e]); !s)
                return s;
    }
    return {};
}

} // namespace

Result<std::unique_ptr<VdbOverlayStore>> VdbOverlayStore::open(const VdbOverlayOpenInfo& info) {
    const std::string name = info.overlay.empty() ? default_overlay_name(info.vdb_path) : info.overlay;
    // The id first: it reads the file in this process, but only as bytes.
    Result<VdbFileId> id = vdb_file_id(info.vdb_path);
    if (!id)
        return Error{id.error()};
    auto base = VdbStore::open(info.vdb_path, info.read);
    if (!base)
        return Error{base.error()};
    auto overlay = open_overlay(info, name, *id);
    if (!overlay)
        return Error{overlay.error()};
    return std::unique_ptr<VdbOverlayStore>(new VdbOverlayStore(std::move(*base), std::move(*overlay), name));
}

Result<VdbOverlayExport> export_overlay_vdb(const VdbOverlayOpenInfo& info_in, const std::string& out,
                                            const VdbExportOptions& options) {
    VdbOverlayOpenInfo info = info_in;
    info.read_only = true;
    const std::string name = info.overlay.empty() ? default_overlay_name(info.vdb_path) : info.overlay;
    Result<VdbFileId> id = vdb_file_id(info.vdb_path);
    if (!id)
        return Error{id.error()};
    VdbOverlayExport result;
    {
        auto overlay = open_overlay(info, name, *id);
        if (!overlay)
            return Error{overlay.error()};
        auto reader = VdbStreamReader::open(info.vdb_path);
        if (reader) {
            Result<std::vector<world::ChunkCoord>> edits = (*overlay)->list_coords();
            if (!edits)
                return Error{edits.error()};
            std::sort(edits->begin(), edits->end(), file_order_less);
            auto writer = VdbStreamWriter::create(out, (*reader)->registry(), options);
            if (!writer)
                return Error{writer.error()};
            if (Status s = merge_stream(**reader, **overlay, *edits, **writer, result.fallback); !s)
                return Error{"cannot export to '" + out + "': " + s.error()};
            if (result.fallback.empty()) {
                if (Status s = (*writer)->finish(); !s)
                    return Error{s.error()};
                result.chunks = (*writer)->chunks_written();
                return result;
            }
        } else {
            result.fallback = reader.error();
        }
    } // The streaming attempt's files are closed (its temporary removed) before the fallback.
    auto merged = VdbOverlayStore::open(info);
    if (!merged)
        return Error{merged.error()};
    Result<uint64_t> written = export_store_vdb(**merged, (*merged)->registry(), out, options);
    if (!written)
        return Error{written.error()};
    result.chunks = *written; // Those in the box: the store's count was all of them.
    return result;
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
