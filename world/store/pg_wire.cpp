#include "world/store/pg_wire.h"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <climits>

namespace vx::world::pg {

namespace {

// expand_dbname = 1: `conninfo` is parsed as a URI or key=value string at dbname's place, and a
// later keyword overrides an earlier one, so our defaults come first and whatever the URI sets
// wins. Keepalives and tcp_user_timeout find a dead peer on TCP (a crashed host, a dropped link)
// in about half a minute instead of the kernel's hours; Unix sockets ignore them. Server notices
// ("relation already exists, skipping", shutdown notes) are not ours to print: errors reach the
// caller through results.
template <class Start>
PGconn* connect_with(const std::string& conninfo, int connect_timeout_s, Start start) {
    const std::string timeout = std::to_string(connect_timeout_s);
    const char* keys[] = {"connect_timeout", "application_name", "keepalives", "keepalives_idle",
                          "keepalives_interval", "keepalives_count", "tcp_user_timeout", "dbname", nullptr};
    const char* values[] = {timeout.c_str(), "vx", "1", "10", "5", "3", "30000", conninfo.c_str(), nullptr};
    PGconn* conn = start(keys, values);
    if (conn)
        PQsetNoticeProcessor(conn, [](void*, const char*) {}, nullptr);
    return conn;
}

} // namespace

PGconn* connect(const std::string& conninfo, int connect_timeout_s) {
    return connect_with(conninfo, connect_timeout_s, [](const char* const* keys, const char* const* values) {
        return PQconnectdbParams(keys, values, 1);
    });
}

PGconn* connect_start(const std::string& conninfo, int connect_timeout_s) {
    return connect_with(conninfo, connect_timeout_s, [](const char* const* keys, const char* const* values) {
        return PQconnectStartParams(keys, values, 1);
    });
}

Deadline deadline_in(std::chrono::milliseconds timeout) {
    return timeout.count() > 0 ? std::chrono::steady_clock::now() + timeout : Deadline::max();
}

namespace {

// Milliseconds for poll() until `deadline` (-1: none; 0: passed).
int poll_ms(Deadline deadline) {
    if (deadline == Deadline::max())
        return -1;
    using namespace std::chrono;
    const auto left = ceil<milliseconds>(deadline - steady_clock::now());
    return int(std::clamp<int64_t>(left.count(), 0, INT_MAX));
}

} // namespace

bool wait_result(PGconn* conn, Deadline deadline) {
    for (;;) {
        // 1: output still queued; -1: the send failed (PQgetResult then reports why).
        const bool sending = PQflush(conn) == 1;
        if (!sending && !PQisBusy(conn))
            return true;
        const int ms = poll_ms(deadline);
        if (ms == 0)
            return false;
        pollfd fd{PQsocket(conn), short(POLLIN | (sending ? POLLOUT : 0)), 0};
        const int ready = ::poll(&fd, 1, ms);
        if (ready < 0 && errno != EINTR)
            return false; // Cannot wait: drop the connection rather than block in PQgetResult.
        // A read error marks the connection bad, and PQisBusy() is then false.
        if (ready > 0 && (fd.revents & (POLLIN | POLLERR | POLLHUP)))
            PQconsumeInput(conn);
    }
}

ResultPtr finish(PGconn* conn, Deadline deadline, bool& timed_out) {
    ResultPtr last;
    for (;;) {
        if (!wait_result(conn, deadline)) {
            timed_out = true;
            return {};
        }
        PGresult* r = PQgetResult(conn);
        if (!r)
            return last;
        last.reset(r);
    }
}

ResultPtr run(PGconn* conn, const char* sql, Deadline deadline, bool& timed_out) {
    if (PQsendQuery(conn, sql) != 1)
        return {};
    return finish(conn, deadline, timed_out);
}

ResultPtr prepare(PGconn* conn, const char* name, const char* sql, Deadline deadline, bool& timed_out) {
    if (PQsendPrepare(conn, name, sql, 0, nullptr) != 1)
        return {};
    return finish(conn, deadline, timed_out);
}

ResultPtr exec(PGconn* conn, const char* name, const Params& p, Deadline deadline, bool& timed_out) {
    if (PQsendQueryPrepared(conn, name, p.count(), p.values(), p.lengths(), p.formats(), 1) != 1)
        return {};
    return finish(conn, deadline, timed_out);
}

std::string message(PGconn* conn, const PGresult* r) {
    std::string m = r ? PQresultErrorMessage(r) : "";
    if (m.empty() && conn)
        m = PQerrorMessage(conn);
    // libpq's messages end in a newline and may span lines ("DETAIL: ..."): keep the first line.
    if (const size_t nl = m.find('\n'); nl != std::string::npos)
        m.resize(nl);
    return m.empty() ? "unknown error" : m;
}

// Versions only ever grow: an erase writes an empty record (a tombstone) with the next version
// rather than deleting the row, so a version a process remembers can never be reused by a later
// insert (the ABA case of delete + re-insert).
const char* const kSchemaSql = R"sql(
CREATE TABLE IF NOT EXISTS vx_meta(key text PRIMARY KEY, value bytea NOT NULL);
CREATE TABLE IF NOT EXISTS vx_chunks(
  x int4 NOT NULL, y int4 NOT NULL, z int4 NOT NULL,
  version int8 NOT NULL, data bytea NOT NULL,
  PRIMARY KEY (x, y, z));
CREATE TABLE IF NOT EXISTS vx_quarantine(
  id bigserial PRIMARY KEY, x int4, y int4, z int4, version int8, data bytea, reason text,
  at timestamptz NOT NULL DEFAULT now());
)sql";

const Statement kStatements[] = {
    {"vx_load", "SELECT version, data FROM vx_chunks WHERE x = $1 AND y = $2 AND z = $3"},
    // The versioned upsert: a row is written only when its version is still the one this process
    // last saw ($4; 0 = "absent"); the new version comes back. When another process wrote it
    // first (a conflict) nothing is written and the statement fails with division_by_zero
    // (kConflictState, from 0 / count(*) over no row; the HAVING filter runs before the division),
    // which rolls the commit's whole implicit transaction back without a round trip of its own.
    {"vx_put", "WITH up AS (INSERT INTO vx_chunks AS c (x, y, z, version, data) VALUES ($1, $2, $3, 1, $5) "
               "ON CONFLICT (x, y, z) DO UPDATE SET version = c.version + 1, data = EXCLUDED.data "
               "WHERE c.version = $4 RETURNING version) "
               "SELECT version FROM up UNION ALL SELECT 0 / count(*) FROM up HAVING count(*) = 0"},
    // The stored versions of a list of chunks (text arrays of x, y and z): catch_up().
    {"vx_versions", "SELECT c.x, c.y, c.z, c.version FROM vx_chunks c JOIN "
                    "unnest($1::int4[], $2::int4[], $3::int4[]) AS k(x, y, z) "
                    "ON c.x = k.x AND c.y = k.y AND c.z = k.z"},
    {"vx_has", "SELECT 1 FROM vx_chunks WHERE x = $1 AND y = $2 AND z = $3 AND length(data) > 0"},
    {"vx_count", "SELECT count(*) FROM vx_chunks WHERE length(data) > 0"},
    {"vx_list", "SELECT x, y, z FROM vx_chunks WHERE length(data) > 0"},
    {"vx_meta_get", "SELECT value FROM vx_meta WHERE key = $1"},
    {"vx_meta_put", "INSERT INTO vx_meta (key, value) VALUES ($1, $2) "
                    "ON CONFLICT (key) DO UPDATE SET value = EXCLUDED.value"},
    // Moves a record that failed verification aside (verbatim, inside the server) and leaves a
    // tombstone, in one statement: both or neither.
    {"vx_quarantine", "WITH q AS (INSERT INTO vx_quarantine (x, y, z, version, data, reason) "
                      "SELECT x, y, z, version, data, $5 FROM vx_chunks "
                      "WHERE x = $1 AND y = $2 AND z = $3 AND version = $4 RETURNING 1) "
                      "UPDATE vx_chunks SET version = version + 1, data = '' "
                      "WHERE x = $1 AND y = $2 AND z = $3 AND version = $4 RETURNING version"},
    {"vx_notify", "SELECT pg_notify('vx_chunks', $1)"},
};
const size_t kStatementCount = sizeof(kStatements) / sizeof(kStatements[0]);

// Coarse chunks are derived data (the downsampling of the level below): the last writer wins, so
// no versioned upsert; the version only counts writes (a quarantine moves the one it read).
const char* const kLodSchemaSql = R"sql(
CREATE TABLE IF NOT EXISTS vx_lod_chunks(
  level int2 NOT NULL, x int4 NOT NULL, y int4 NOT NULL, z int4 NOT NULL,
  version int8 NOT NULL, data bytea NOT NULL,
  PRIMARY KEY (level, x, y, z));
CREATE TABLE IF NOT EXISTS vx_lod_dirty(
  level int2 NOT NULL, x int4 NOT NULL, y int4 NOT NULL, z int4 NOT NULL,
  PRIMARY KEY (level, x, y, z));
CREATE TABLE IF NOT EXISTS vx_lod_quarantine(
  id bigserial PRIMARY KEY, level int2, x int4, y int4, z int4, version int8, data bytea, reason text,
  at timestamptz NOT NULL DEFAULT now());
)sql";

#define VX_LOD_KEY "level = $1 AND x = $2 AND y = $3 AND z = $4"
const Statement kLodStatements[] = {
    {"vx_lod_load", "SELECT version, data FROM vx_lod_chunks WHERE " VX_LOD_KEY},
    {"vx_lod_put", "INSERT INTO vx_lod_chunks AS c (level, x, y, z, version, data) VALUES ($1, $2, $3, $4, 1, $5) "
                   "ON CONFLICT (level, x, y, z) DO UPDATE SET version = c.version + 1, data = EXCLUDED.data"},
    {"vx_lod_del", "DELETE FROM vx_lod_chunks WHERE " VX_LOD_KEY},
    {"vx_lod_list", "SELECT level, x, y, z FROM vx_lod_chunks"},
    {"vx_lod_dirty_put", "INSERT INTO vx_lod_dirty (level, x, y, z) VALUES ($1, $2, $3, $4) ON CONFLICT DO NOTHING"},
    {"vx_lod_dirty_del", "DELETE FROM vx_lod_dirty WHERE " VX_LOD_KEY},
    {"vx_lod_dirty_list", "SELECT level, x, y, z FROM vx_lod_dirty"},
    // As vx_quarantine, without a tombstone (no versions to protect): the row read ($5) moves.
    {"vx_lod_quarantine", "WITH q AS (INSERT INTO vx_lod_quarantine (level, x, y, z, version, data, reason) "
                          "SELECT level, x, y, z, version, data, $6 FROM vx_lod_chunks "
                          "WHERE " VX_LOD_KEY " AND version = $5 RETURNING 1) "
                          "DELETE FROM vx_lod_chunks WHERE " VX_LOD_KEY " AND version = $5"},
};
#undef VX_LOD_KEY
const size_t kLodStatementCount = sizeof(kLodStatements) / sizeof(kLodStatements[0]);

} // namespace vx::world::pg
