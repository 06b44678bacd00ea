#pragma once
// Small helpers over libpq shared by PgStore and its listener: owned results, binary parameters
// in network byte order, and the SQL the store speaks. Internal to vx_store (includes libpq).
// Thread affinity: none of their own; a connection is used by one thread at a time.

#include <chrono>
#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <libpq-fe.h>

#include "world/coords.h"

namespace vx::world::pg {

struct ResultDeleter {
    void operator()(PGresult* r) const { PQclear(r); }
};
using ResultPtr = std::unique_ptr<PGresult, ResultDeleter>;

inline uint32_t to_be32(uint32_t v) { return __builtin_bswap32(v); }
inline uint64_t to_be64(uint64_t v) { return __builtin_bswap64(v); }

// Parameters of one statement, binary format (text for add_text). Values live in a deque, whose
// elements never move, so the pointers handed to libpq stay valid.
class Params {
public:
    void add_i32(int32_t v) {
        const uint32_t be = to_be32(uint32_t(v));
        add_owned(std::string(reinterpret_cast<const char*>(&be), 4), 1);
    }
    void add_i64(int64_t v) {
        const uint64_t be = to_be64(uint64_t(v));
        add_owned(std::string(reinterpret_cast<const char*>(&be), 8), 1);
    }
    void add_i16(int16_t v) {
        const uint16_t be = __builtin_bswap16(uint16_t(v));
        add_owned(std::string(reinterpret_cast<const char*>(&be), 2), 1);
    }
    void add_coord(ChunkCoord c) {
        add_i32(c.x);
        add_i32(c.y);
        add_i32(c.z);
    }
    void add_text(std::string s) { add_owned(std::move(s), 0); }
    // Binary bytes by reference: `data` must outlive the statement's send.
    void add_ref(const void* data, size_t n) {
        m_values.push_back(static_cast<const char*>(data));
        m_lengths.push_back(int(n));
        m_formats.push_back(1);
    }
    int count() const { return int(m_values.size()); }
    const char* const* values() const { return m_values.data(); }
    const int* lengths() const { return m_lengths.data(); }
    const int* formats() const { return m_formats.data(); }

private:
    void add_owned(std::string s, int format) {
        m_owned.push_back(std::move(s));
        m_values.push_back(m_owned.back().data());
        m_lengths.push_back(int(m_owned.back().size()));
        m_formats.push_back(format);
    }
    std::deque<std::string> m_owned;
    std::vector<const char*> m_values;
    std::vector<int> m_lengths, m_formats;
};

inline int64_t get_i64(const PGresult* r, int row, int col) {
    uint64_t be = 0;
    std::memcpy(&be, PQgetvalue(r, row, col), 8);
    return int64_t(to_be64(be));
}
inline int16_t get_i16(const PGresult* r, int row, int col) {
    uint16_t be = 0;
    std::memcpy(&be, PQgetvalue(r, row, col), 2);
    return int16_t(__builtin_bswap16(be));
}
inline int32_t get_i32(const PGresult* r, int row, int col) {
    uint32_t be = 0;
    std::memcpy(&be, PQgetvalue(r, row, col), 4);
    return int32_t(to_be32(be));
}

// Connects (blocking) to `conninfo` (a URI or key=value string) with a connect timeout. Never
// null; check PQstatus.
PGconn* connect(const std::string& conninfo, int connect_timeout_s);
// The same, started without blocking (PQconnectStartParams): the caller drives PQconnectPoll and
// enforces the timeout. Null only when libpq is out of memory.
PGconn* connect_start(const std::string& conninfo, int connect_timeout_s);

// Whether a result is a success (a command, or rows).
inline bool ok(const PGresult* r) {
    const ExecStatusType s = PQresultStatus(r);
    return s == PGRES_COMMAND_OK || s == PGRES_TUPLES_OK;
}

// Round trips with a deadline: a server that is alive but stopped answering (a frozen process, a
// stuck disk) is not noticed by keepalives (the kernel still answers them), so a blocking libpq
// call would wait for ever. These take steady_clock deadlines (time_point::max(): none) and need
// the connection in nonblocking mode (PQsetnonblocking), so sends and PQfinish never block either.
using Deadline = std::chrono::steady_clock::time_point;
// The deadline `timeout` from now (0: none).
Deadline deadline_in(std::chrono::milliseconds timeout);
// Sends what `conn` has queued and waits until PQgetResult would not block. False: `deadline`
// passed first; the connection is then out of step with the server and must be dropped.
bool wait_result(PGconn* conn, Deadline deadline);
// The last result of the command sent (PQexec's rule), null when the send failed or `deadline`
// passed (`timed_out` set).
ResultPtr finish(PGconn* conn, Deadline deadline, bool& timed_out);
// SQL text, one or more statements, as PQexec.
ResultPtr run(PGconn* conn, const char* sql, Deadline deadline, bool& timed_out);
// Prepares statement `name`, as PQprepare.
ResultPtr prepare(PGconn* conn, const char* name, const char* sql, Deadline deadline, bool& timed_out);
// Runs prepared statement `name`, results in binary format.
ResultPtr exec(PGconn* conn, const char* name, const Params& p, Deadline deadline, bool& timed_out);

// "x,y,z": chunk coordinates in messages and NOTIFY payloads.
inline std::string coord_str(ChunkCoord c) {
    return std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
}

// The message of a failed result or connection, one line.
std::string message(PGconn* conn, const PGresult* r = nullptr);

// Prepared statement names and SQL.
inline constexpr const char* kFormat = "vx-world-1";
// SQLSTATE of a versioned upsert that met a newer version (division_by_zero; see vx_put).
inline constexpr const char* kConflictState = "22012";
extern const char* const kSchemaSql;
struct Statement {
    const char* name;
    const char* sql;
};
extern const Statement kStatements[];
extern const size_t kStatementCount;
// Coarse levels: tables created by the first commit that writes one, statements prepared once
// the tables exist (parameters: level int2, then x, y, z).
extern const char* const kLodSchemaSql;
extern const Statement kLodStatements[];
extern const size_t kLodStatementCount;
// NOTIFY payloads of coarse chunks start with this ("lod;level,x,y,z;..."): a listener of a build
// before coarse levels fails to read a number there and ignores the whole payload.
inline constexpr const char* kLodNotifyPrefix = "lod;";

} // namespace vx::world::pg
