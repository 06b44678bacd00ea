// PgStore's coarse levels of detail (pg_store.h): the vx_lod_* tables and their statements, the
// queue's coarse records and dirty marks, the listings, and the coarse chunks other processes wrote.
#include "world/store/pg_store.h"

#include <mutex>
#include <string>
#include <vector>

#include "world/store/pg_listener.h"
#include "world/store/pg_wire.h"

namespace vx::world {

Result<bool> PgStore::lod_tables(bool create) {
    if (m_lod_ready)
        return true;
    const char* probe = "SELECT to_regclass('vx_lod_chunks') IS NOT NULL";
    pg::ResultPtr r = pg::run(m_conn, probe, deadline(), m_timed_out);
    if (!pg::ok(r.get()) || PQntuples(r.get()) != 1)
        return error("cannot read the database's tables");
    if (PQgetvalue(r.get(), 0, 0)[0] != 't') {
        if (!create)
            return false; // A world made before coarse levels, or none saved yet.
        // As init_schema: the advisory lock orders processes creating them at once.
        const std::string sql =
            std::string("BEGIN; SELECT pg_advisory_xact_lock(7942519736); ") + pg::kLodSchemaSql + "COMMIT;";
        pg::ResultPtr c = pg::run(m_conn, sql.c_str(), deadline(), m_timed_out);
        if (!pg::ok(c.get())) {
            Error e = error("cannot create the coarse-level tables");
            if (m_conn)
                pg::run(m_conn, "ROLLBACK", deadline(), m_timed_out);
            return e;
        }
    }
    for (size_t i = 0; i < pg::kLodStatementCount; ++i) {
        const pg::Statement& st = pg::kLodStatements[i];
        pg::ResultPtr p = pg::prepare(m_conn, st.name, st.sql, deadline(), m_timed_out);
        if (!pg::ok(p.get()))
            return error(std::string("cannot prepare ") + pg::kLodStatements[i].name);
    }
    m_lod_ready = true;
    return true;
}

Result<ChunkLoad> PgStore::load_lod(LodCoord c) {
    if (Status s = check_coarse(c); !s)
        return Error{s.error()};
    return load_level(c);
}

Status PgStore::save_lod(std::span<const LodWrite> batch) {
    if (m_info.read_only)
        return Error{"PostgreSQL world '" + m_name + "' is open read-only"};
    if (Status s = m_queue.save_lods(batch, m_encoder, m_codec); !s)
        return s;
    return queued();
}

Status PgStore::mark_lod_dirty(std::span<const LodCoord> coords) {
    if (m_info.read_only)
        return Error{"PostgreSQL world '" + m_name + "' is open read-only"};
    if (Status s = m_queue.mark_dirty(coords); !s)
        return s;
    std::lock_guard lock(m_health_mutex);
    m_health.pending_edits = pending_edits();
    return {};
}

Result<std::vector<LodCoord>> PgStore::list_lod(const char* statement, const char* what) {
    if (Status s = commit(); !s)
        return Error{s.error()};
    if (Status s = ensure_connected(true); !s)
        return Error{s.error()};
    std::vector<LodCoord> out;
    Result<bool> ready = lod_tables(false);
    if (!ready)
        return Error{ready.error()};
    if (!*ready)
        return out;
    pg::ResultPtr r = pg::exec(m_conn, statement, pg::Params(), deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error(std::string("cannot list ") + what);
    for (int i = 0, n = PQntuples(r.get()); i < n; ++i) {
        const ChunkCoord c(pg::get_i32(r.get(), i, 1), pg::get_i32(r.get(), i, 2), pg::get_i32(r.get(), i, 3));
        out.push_back({int(pg::get_i16(r.get(), i, 0)), c});
    }
    return out;
}

Result<std::vector<LodCoord>> PgStore::list_lod_dirty() {
    return list_lod("vx_lod_dirty_list", "dirty coarse chunks");
}

Result<std::vector<LodCoord>> PgStore::list_lod_coords() { return list_lod("vx_lod_list", "coarse chunks"); }

void PgStore::poll_lod_changes(std::vector<LodCoord>& out) {
    if (m_listener)
        m_listener->take_lod(out);
}

} // namespace vx::world
