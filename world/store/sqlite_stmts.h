#pragma once
// SqliteStore's prepared statements and the helpers that bind and read them, shared by
// sqlite_store.cpp and sqlite_store_lod.cpp. Internal to vx_store (includes sqlite3.h).

#include <sqlite3.h>

#include <cstdint>
#include <string>

#include "world/store/chunk_record.h"
#include "world/store/sqlite_store.h"

namespace vx::world::sqlite_detail {

struct Stmt {
    sqlite3_stmt* s = nullptr;
    ~Stmt() { sqlite3_finalize(s); }
};

// Resets a statement when the scope ends, whatever path leaves it.
struct ResetGuard {
    sqlite3_stmt* s;
    ~ResetGuard() {
        sqlite3_reset(s);
        sqlite3_clear_bindings(s);
    }
};

// Level, then the chunk: parameters 1..4.
inline void bind_lod(sqlite3_stmt* s, LodCoord c) {
    sqlite3_bind_int64(s, 1, c.level);
    sqlite3_bind_int64(s, 2, c.chunk.x);
    sqlite3_bind_int64(s, 3, c.chunk.y);
    sqlite3_bind_int64(s, 4, c.chunk.z);
}

// A load's columns: the record's length, and its bytes only when a record can be that long. A
// damaged row of 300 MB was read whole (and its memory held) before the length check failed it.
inline std::string load_columns() {
    const std::string max = std::to_string(max_record_bytes());
    return "SELECT length(data), CASE WHEN length(data) <= " + max + " THEN data END ";
}

// Column `col` of the current row holds a 32-bit integer (a chunk coordinate).
inline bool column_is_i32(sqlite3_stmt* s, int col) {
    if (sqlite3_column_type(s, col) != SQLITE_INTEGER)
        return false;
    const int64_t v = sqlite3_column_int64(s, col);
    return v >= INT32_MIN && v <= INT32_MAX;
}

} // namespace vx::world::sqlite_detail

namespace vx::world {

struct SqliteStore::Stmts {
    sqlite_detail::Stmt load, put, del, has, count, list, meta_get, meta_put, q_put, q_count;
};

struct SqliteStore::LodStmts {
    sqlite_detail::Stmt load, put, del, list, dirty_put, dirty_del, dirty_list, q_put, q_count;
};

struct SqliteStore::LevelStmts {
    sqlite3_stmt* load = nullptr;
    sqlite3_stmt* put = nullptr;
    sqlite3_stmt* del = nullptr;
    sqlite3_stmt* q_put = nullptr;
    LevelStmts() = default;
    template <class S> // Stmts or LodStmts.
    explicit LevelStmts(const S& s) : load(s.load.s), put(s.put.s), del(s.del.s), q_put(s.q_put.s) {}
};

} // namespace vx::world
