// check_store (sqlite_store.h): verifies every record of a SqliteStore file, read-only.
#include "world/store/sqlite_store.h"

namespace vx::world {

namespace {

std::string coord_str(ChunkCoord c) {
    return std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
}

// Whatever the level, also one out of range (a damaged row).
std::string lod_str(LodCoord c) { return "level " + std::to_string(c.level) + " chunk " + coord_str(c.chunk); }

} // namespace

Result<StoreCheck> check_store(const std::string& path) {
    SqliteStoreCreateInfo info;
    info.path = path;
    info.read_only = true;
    info.log_corrupt = false;
    Result<std::unique_ptr<SqliteStore>> opened = SqliteStore::open(info);
    if (!opened)
        return Error{opened.error()};
    SqliteStore& store = **opened;
    StoreCheck out;
    constexpr size_t kMaxProblems = 16;
    auto note = [&](std::string line) {
        if (out.problems.size() < kMaxProblems)
            out.problems.push_back(std::move(line));
    };
    if (Status s = store.verify_database(); !s) {
        out.database_ok = false;
        note(s.error());
    }
    // Coordinates first, then one load each: the list statement is not kept open across loads.
    Result<std::vector<ChunkCoord>> coords = store.list_coords();
    if (!coords)
        return Error{coords.error()};
    for (ChunkCoord c : *coords) {
        ++out.records;
        Result<ChunkLoad> r = store.load(c);
        if (!r)
            return Error{r.error()};
        if (r->state == LoadState::Corrupt) {
            ++out.corrupt;
            note("chunk " + coord_str(c) + ": " + r->problem);
        } else if (r->state == LoadState::Absent) {
            ++out.corrupt; // Listed, then gone: a writer erased it meanwhile (rows of no chunk: below).
            note("chunk " + coord_str(c) + ": listed, then not found");
        }
    }
    Result<std::vector<LodCoord>> lods = store.list_lod_coords();
    if (!lods)
        return Error{lods.error()};
    for (LodCoord c : *lods) {
        ++out.records;
        Result<ChunkLoad> r = store.load_lod(c); // Listed levels are 1..kMaxLodLevel (stray_rows: the rest).
        if (!r)
            return Error{r.error()};
        if (r->state == LoadState::Corrupt) {
            ++out.corrupt;
            note(lod_str(c) + ": " + r->problem);
        } else if (r->state == LoadState::Absent) {
            ++out.corrupt; // As above.
            note(lod_str(c) + ": listed, then not found");
        }
    }
    Result<uint64_t> stray = store.stray_rows();
    if (!stray)
        return Error{stray.error()};
    if (*stray > 0) {
        out.records += *stray;
        out.corrupt += *stray;
        note(std::to_string(*stray) + " rows whose keys name no chunk (coordinates outside 32 bits or not integers, " +
             "or a level outside 1.." + std::to_string(kMaxLodLevel) + "), left in place");
    }
    Result<uint64_t> q = store.quarantine_count();
    if (!q)
        return Error{q.error()};
    out.quarantined = *q;
    return out;
}

} // namespace vx::world
