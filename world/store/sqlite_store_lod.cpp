// SqliteStore's coarse levels of detail (sqlite_store.h): the lod_chunks, lod_dirty and
// lod_quarantine tables, their statements, and the queue's coarse records and dirty marks.
#include "world/store/sqlite_store.h"

#include <sqlite3.h>

#include <memory>
#include <string>
#include <vector>

#include "world/base/assert.h"
#include "world/store/sqlite_stmts.h"

namespace vx::world {

using namespace sqlite_detail;

namespace {

// Coarse levels, created by the first commit that writes one (existing files open unchanged).
const char* const kLodSchema = R"sql(
CREATE TABLE IF NOT EXISTS lod_chunks(
  level INTEGER NOT NULL, x INTEGER NOT NULL, y INTEGER NOT NULL, z INTEGER NOT NULL, data BLOB NOT NULL,
  PRIMARY KEY(level, x, y, z));
CREATE TABLE IF NOT EXISTS lod_dirty(
  level INTEGER NOT NULL, x INTEGER NOT NULL, y INTEGER NOT NULL, z INTEGER NOT NULL,
  PRIMARY KEY(level, x, y, z));
CREATE TABLE IF NOT EXISTS lod_quarantine(
  id INTEGER PRIMARY KEY, level INTEGER, x INTEGER, y INTEGER, z INTEGER, data BLOB, reason TEXT, time INTEGER);
)sql";

LodCoord lod_row(sqlite3_stmt* s) {
    return {int(sqlite3_column_int64(s, 0)), ChunkCoord(int32_t(sqlite3_column_int64(s, 1)),
                                                        int32_t(sqlite3_column_int64(s, 2)),
                                                        int32_t(sqlite3_column_int64(s, 3)))};
}

} // namespace

Result<bool> SqliteStore::lod_tables(bool create) {
    if (m_lod_stmts)
        return true;
    if (create) {
        VX_ASSERT(!m_info.read_only);
        if (Status s = exec(kLodSchema); !s)
            return Error{s.error()};
    } else {
        Stmt st;
        if (sqlite3_prepare_v2(m_db, "SELECT 1 FROM sqlite_schema WHERE type='table' AND name='lod_chunks'", -1,
                               &st.s, nullptr) != SQLITE_OK)
            return db_error("cannot read the schema");
        const int rc = sqlite3_step(st.s);
        if (rc == SQLITE_DONE)
            return false; // A world made before coarse levels, or none saved yet.
        if (rc != SQLITE_ROW)
            return db_error("cannot read the schema");
    }
    auto lod = std::make_unique<LodStmts>();
    auto prep = [&](Stmt& st, const char* sql) {
        return sqlite3_prepare_v3(m_db, sql, -1, SQLITE_PREPARE_PERSISTENT, &st.s, nullptr) == SQLITE_OK;
    };
    const char* const where = " WHERE level=?1 AND x=?2 AND y=?3 AND z=?4";
    const bool ok =
        prep(lod->load, (load_columns() + "FROM lod_chunks" + where).c_str()) &&
        prep(lod->put, "INSERT OR REPLACE INTO lod_chunks(level, x, y, z, data) VALUES(?1, ?2, ?3, ?4, ?5)") &&
        prep(lod->del, (std::string("DELETE FROM lod_chunks") + where).c_str()) &&
        prep(lod->list, "SELECT level, x, y, z FROM lod_chunks") &&
        prep(lod->dirty_put, "INSERT OR IGNORE INTO lod_dirty(level, x, y, z) VALUES(?1, ?2, ?3, ?4)") &&
        prep(lod->dirty_del, (std::string("DELETE FROM lod_dirty") + where).c_str()) &&
        prep(lod->dirty_list, "SELECT level, x, y, z FROM lod_dirty") &&
        prep(lod->q_put, (std::string("INSERT INTO lod_quarantine(level, x, y, z, data, reason, time) "
                                      "SELECT level, x, y, z, data, ?5, strftime('%s', 'now') FROM lod_chunks") +
                          where).c_str()) &&
        prep(lod->q_count, "SELECT count(*) FROM lod_quarantine");
    if (!ok)
        return db_error("cannot prepare the coarse-level statements");
    m_lod_stmts = std::move(lod);
    return true;
}

Result<ChunkLoad> SqliteStore::load_lod(LodCoord c) {
    if (Status s = check_coarse(c); !s)
        return Error{s.error()};
    return load_level(c);
}

Status SqliteStore::save_lod(std::span<const LodWrite> batch) {
    if (m_info.read_only)
        return Error{"store '" + m_info.path + "' is open read-only"};
    if (Status s = m_queue.save_lods(batch, m_encoder, m_codec); !s)
        return s;
    return queued();
}

Status SqliteStore::mark_lod_dirty(std::span<const LodCoord> coords) {
    if (m_info.read_only)
        return Error{"store '" + m_info.path + "' is open read-only"};
    Status s = m_queue.mark_dirty(coords);
    show_pending();
    return s;
}

Status SqliteStore::commit_lod() {
    if (m_queue.lods.empty() && m_queue.dirty.empty())
        return {};
    const LevelStmts lods(*m_lod_stmts);
    for (const auto& [c, pending] : m_queue.lods)
        if (Status s = write_record(c, pending.record, lods); !s)
            return s;
    for (const auto& [c, dirty] : m_queue.dirty) {
        sqlite3_stmt* st = dirty ? m_lod_stmts->dirty_put.s : m_lod_stmts->dirty_del.s;
        ResetGuard guard{st};
        bind_lod(st, c);
        if (sqlite3_step(st) != SQLITE_DONE)
            return db_error("cannot write the dirty mark of " + record_name(c));
    }
    return {};
}

Result<std::vector<LodCoord>> SqliteStore::list_lod_dirty() { return list_lod(true); }

Result<std::vector<LodCoord>> SqliteStore::list_lod_coords() { return list_lod(false); }

Result<std::vector<LodCoord>> SqliteStore::list_lod(bool dirty) {
    if (Status s = commit(); !s)
        return Error{s.error()};
    std::vector<LodCoord> out;
    Result<bool> ready = lod_tables(false);
    if (!ready)
        return Error{ready.error()};
    if (!*ready)
        return out;
    sqlite3_stmt* st = dirty ? m_lod_stmts->dirty_list.s : m_lod_stmts->list.s;
    ResetGuard guard{st};
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW)
        if (column_is_i32(st, 1) && column_is_i32(st, 2) && column_is_i32(st, 3) &&
            sqlite3_column_type(st, 0) == SQLITE_INTEGER && sqlite3_column_int64(st, 0) >= 1 &&
            sqlite3_column_int64(st, 0) <= kMaxLodLevel) // Else not a coarse chunk's row (stray_rows).
            out.push_back(lod_row(st));
    if (rc != SQLITE_DONE)
        return db_error(dirty ? "cannot list dirty coarse chunks" : "cannot list coarse chunks");
    return out;
}

} // namespace vx::world
