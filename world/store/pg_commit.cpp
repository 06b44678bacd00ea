// PgStore's transactions: the pipelined, versioned commit and its conflict resolution, and the
// queries that read the whole world (count, list, metadata).
#include <algorithm>
#include <cstring>
#include <tuple>

#include "world/base/log.h"
#include "world/store/pg_store.h"
#include "world/store/pg_wire.h"

namespace vx::world {

namespace {

constexpr size_t kNotifyPayloadMax = 7900; // NOTIFY payloads must be shorter than 8000 bytes.

bool coord_less(ChunkCoord a, ChunkCoord b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
}

bool send(PGconn* conn, const char* name, const pg::Params& p) {
    return PQsendQueryPrepared(conn, name, p.count(), p.values(), p.lengths(), p.formats(), 1) == 1;
}

// Coordinates as NOTIFY payloads ("x,y,z;x,y,z;..."), each under the size limit.
std::vector<std::string> notify_payloads(const std::vector<ChunkCoord>& coords) {
    std::vector<std::string> out(1);
    for (ChunkCoord c : coords) {
        std::string item = pg::coord_str(c) + ";";
        if (out.back().size() + item.size() > kNotifyPayloadMax)
            out.emplace_back();
        out.back() += item;
    }
    if (out.back().empty())
        out.pop_back();
    return out;
}

// Coarse coordinates as NOTIFY payloads ("lod;level,x,y,z;..."), each under the size limit.
std::vector<std::string> lod_notify_payloads(const std::vector<LodCoord>& coords) {
    std::vector<std::string> out;
    for (const LodCoord& c : coords) {
        std::string item = std::to_string(c.level) + "," + pg::coord_str(c.chunk) + ";";
        if (out.empty() || out.back().size() + item.size() > kNotifyPayloadMax)
            out.emplace_back(pg::kLodNotifyPrefix);
        out.back() += item;
    }
    return out;
}

// Whether the server refuses a statement for what it holds (bad data, a constraint, a trigger's
// exception), so sending it again fails again. Transient classes (connection 08, rollback 40
// (deadlock, serialization), resources 53, lock not available 55, operator intervention 57,
// system 58, internal XX) are not: the queue waits for a later commit.
bool refused_for_good(const char* state) {
    if (!state || std::strlen(state) != 5)
        return false;
    const std::string_view cls(state, 2);
    for (const char* transient : {"08", "25", "40", "53", "55", "57", "58", "XX"})
        if (cls == transient)
            return false;
    return true;
}

// Reads the results of one pipelined command (results up to the NULL that ends it).
struct PipelineReader {
    PGconn* conn = nullptr;
    pg::Deadline deadline = pg::Deadline::max(); // Of the whole read.
    bool timed_out = false; // The deadline passed: nothing more is read (drop the connection).
    std::string first_error{};
    size_t commands = 0;             // Commands read so far.
    size_t first_error_at = 0;       // The command that failed first (when first_error is set).
    std::string first_error_state{}; // Its SQLSTATE ("" when the connection failed).

    // The command's last result (null if the connection failed); records the first error.
    pg::ResultPtr next() {
        pg::ResultPtr last;
        while (PGresult* r = get()) {
            last.reset(r);
            const ExecStatusType s = PQresultStatus(r);
            if (s != PGRES_COMMAND_OK && s != PGRES_TUPLES_OK && first_error.empty()) {
                first_error = s == PGRES_PIPELINE_ABORTED ? "pipeline aborted" : pg::message(conn, r);
                first_error_at = commands;
                const char* state = PQresultErrorField(r, PG_DIAG_SQLSTATE);
                first_error_state = state ? state : "";
            }
        }
        if (!last && first_error.empty()) {
            first_error = pg::message(conn);
            first_error_at = commands;
        }
        ++commands;
        return last;
    }
    // Consumes the sync point.
    bool sync() {
        pg::ResultPtr r(get());
        return r && PQresultStatus(r.get()) == PGRES_PIPELINE_SYNC;
    }
    // PQgetResult within the deadline (null once it passed).
    PGresult* get() {
        timed_out = timed_out || !pg::wait_result(conn, deadline);
        return timed_out ? nullptr : PQgetResult(conn);
    }
};

// Reads the results of the chunk upserts into `versions` (one each); true when one conflicted.
bool read_versions(PipelineReader& reader, std::vector<uint64_t>& versions) {
    bool conflicted = false;
    for (size_t i = 0; i < versions.size(); ++i) {
        pg::ResultPtr r = reader.next();
        if (r && PQresultStatus(r.get()) == PGRES_TUPLES_OK && PQntuples(r.get()) == 1) {
            versions[i] = uint64_t(pg::get_i64(r.get(), 0, 0));
        } else if (r && PQresultStatus(r.get()) == PGRES_FATAL_ERROR) {
            const char* state = PQresultErrorField(r.get(), PG_DIAG_SQLSTATE);
            conflicted |= state && std::string_view(state) == pg::kConflictState;
        }
    }
    return conflicted;
}

} // namespace

// The queue in the order a commit sends it, and the notifications it sends.
struct PgStore::CommitOrder {
    std::vector<ChunkCoord> chunks;
    std::vector<LodCoord> lods, dirty;
    std::vector<std::string> payloads;
};

// One round trip: every versioned upsert, the metadata and the notifications, pipelined up to one
// sync point, so they run as one implicit transaction that the server commits at the sync (and
// rolls back whole if any statement fails). An upsert that finds a newer version fails on purpose
// (vx_put, pg_wire.cpp); only then a second query finds every chunk that conflicted, which are
// returned for the caller to re-apply its edits before the next attempt. True: committed.
Result<bool> PgStore::try_commit(std::vector<ChunkCoord>& conflicts) {
    const CommitOrder order = commit_order();
    if (PQenterPipelineMode(m_conn) != 1)
        return error("cannot start a pipeline");
    const bool sent = send_chunk_writes(order) && send_lod_writes(order) && send_meta_and_notify(order);
    if (!sent || PQpipelineSync(m_conn) != 1) {
        Error e = error("cannot send a commit");
        if (m_conn)
            PQexitPipelineMode(m_conn);
        return e;
    }
    PipelineReader reader{m_conn, deadline()};
    std::vector<uint64_t> versions(order.chunks.size(), 0);
    const bool conflicted = read_versions(reader, versions);
    for (size_t i = 0; i < order.lods.size() + order.dirty.size() + m_queue.meta.size() + order.payloads.size(); ++i)
        reader.next();
    const bool synced = reader.sync(); // The commit (or the rollback) is done when it arrives.
    m_timed_out = reader.timed_out; // Then the server may still commit it: a retry meets a conflict.
    if (!synced || PQexitPipelineMode(m_conn) != 1) {
        const std::string why = reader.first_error.empty() ? "pipeline out of step" : reader.first_error;
        return error("cannot write " + std::to_string(order.chunks.size()) + " chunks", why);
    }
    if (!conflicted && !reader.first_error.empty()) {
        // Metadata the server refuses for good is dropped (and reported by commit_attempts), so
        // one bad key cannot keep every queued chunk edit from ever committing.
        const size_t meta_begin = order.chunks.size() + order.lods.size() + order.dirty.size();
        if (reader.first_error_at >= meta_begin &&
            drop_refused_meta(reader.first_error_at - meta_begin, reader.first_error_state, reader.first_error))
            return false; // No conflicts: the caller tries again without it.
        return error("cannot write " + std::to_string(order.chunks.size()) + " chunks", reader.first_error);
    }
    if (conflicted) {
        if (Status s = find_conflicts(order.chunks, conflicts); !s)
            return Error{s.error()};
        return false;
    }
    note_committed(order.chunks, versions);
    return true;
}

PgStore::CommitOrder PgStore::commit_order() const {
    CommitOrder order;
    // Upserts take row locks in the order sent: two writers with overlapping batches in hash
    // order could each hold a row the other waits for (a deadlock, one of them aborted). Sorted
    // by coordinate, every writer locks in the same order.
    order.chunks.reserve(m_queue.chunks.size());
    for (const auto& [c, p] : m_queue.chunks)
        order.chunks.push_back(c);
    std::sort(order.chunks.begin(), order.chunks.end(), coord_less);
    // Coarse chunks and dirty marks: plain upserts and deletes (last writer wins), in a fixed
    // order for the same reason as above.
    for (const auto& [c, pending] : m_queue.lods)
        order.lods.push_back(c);
    for (const auto& [c, dirty] : m_queue.dirty)
        order.dirty.push_back(c);
    std::sort(order.lods.begin(), order.lods.end(), lod_coord_less);
    std::sort(order.dirty.begin(), order.dirty.end(), lod_coord_less);
    order.payloads = notify_payloads(order.chunks);
    for (std::string& p : lod_notify_payloads(order.lods))
        order.payloads.push_back(std::move(p));
    return order;
}

bool PgStore::send_chunk_writes(const CommitOrder& order) {
    bool sent = true;
    static const uint8_t kEmpty = 0;
    for (size_t i = 0; sent && i < order.chunks.size(); ++i) {
        const Pending& p = m_queue.chunks[order.chunks[i]];
        pg::Params params;
        params.add_coord(order.chunks[i]);
        params.add_i64(int64_t(p.base));
        if (p.record)
            params.add_ref(p.record->data(), p.record->size());
        else
            params.add_ref(&kEmpty, 0); // A tombstone (see pg_wire.cpp).
        sent = send(m_conn, "vx_put", params);
    }
    return sent;
}

bool PgStore::send_lod_writes(const CommitOrder& order) {
    bool sent = true;
    for (size_t i = 0; sent && i < order.lods.size(); ++i) {
        const std::optional<std::vector<uint8_t>>& record = m_queue.lods[order.lods[i]].record;
        pg::Params params;
        params.add_i16(int16_t(order.lods[i].level));
        params.add_coord(order.lods[i].chunk);
        if (record)
            params.add_ref(record->data(), record->size());
        sent = send(m_conn, record ? "vx_lod_put" : "vx_lod_del", params);
    }
    for (size_t i = 0; sent && i < order.dirty.size(); ++i) {
        pg::Params params;
        params.add_i16(int16_t(order.dirty[i].level));
        params.add_coord(order.dirty[i].chunk);
        sent = send(m_conn, m_queue.dirty[order.dirty[i]] ? "vx_lod_dirty_put" : "vx_lod_dirty_del", params);
    }
    return sent;
}

bool PgStore::send_meta_and_notify(const CommitOrder& order) {
    bool sent = true;
    for (auto it = m_queue.meta.begin(); sent && it != m_queue.meta.end(); ++it) {
        pg::Params params;
        params.add_text(it->first);
        params.add_ref(it->second.data(), it->second.size());
        sent = send(m_conn, "vx_meta_put", params);
    }
    for (size_t i = 0; sent && i < order.payloads.size(); ++i) {
        pg::Params params;
        params.add_text(order.payloads[i]);
        sent = send(m_conn, "vx_notify", params);
    }
    return sent;
}

bool PgStore::drop_refused_meta(size_t index, const std::string& state, const std::string& why) {
    if (index >= m_queue.meta.size() || !refused_for_good(state.c_str()))
        return false;
    auto it = std::next(m_queue.meta.begin(), std::ptrdiff_t(index));
    m_refused_meta.push_back("metadata '" + it->first + "' refused by the server and dropped (" + why + ")");
    VX_LOG_ERROR("PostgreSQL world '%s': %s", m_name.c_str(), m_refused_meta.back().c_str());
    m_queue.meta.erase(it);
    return true;
}

Status PgStore::find_conflicts(const std::vector<ChunkCoord>& order, std::vector<ChunkCoord>& conflicts) {
    const auto base = [this](ChunkCoord c) { return m_queue.chunks[c].base; };
    if (Status s = changed_since(order, base, conflicts); !s)
        return s;
    if (conflicts.empty())
        return error("a write conflicted", "yet every stored version is the one it replaces");
    return {};
}

void PgStore::note_committed(const std::vector<ChunkCoord>& order, const std::vector<uint64_t>& versions) {
    for (size_t i = 0; i < order.size(); ++i) {
        note_version(order[i], versions[i]);
        const Pending& p = m_queue.chunks[order[i]];
        if (p.caller_base && !p.merged)
            m_lineage[order[i]] = {*p.caller_base, versions[i]};
        else
            m_lineage.erase(order[i]); // The caller's copy lacks what was merged: it must reload.
    }
}

// Another process wrote chunk `c` since this store last saw it: take its version, and where this
// process recorded its own edits, re-apply them to that version (theirs + ours). A write without
// edits (a whole chunk) replaces theirs: the last writer wins, as documented in chunk_store.h.
Status PgStore::resolve_conflict(ChunkCoord c) {
    pg::Params params;
    params.add_coord(c);
    pg::ResultPtr r = pg::exec(m_conn, "vx_load", params, deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot reload chunk " + pg::coord_str(c) + " after a conflict");
    Pending& p = m_queue.chunks[c];
    std::optional<Chunk> theirs;
    uint64_t version = 0;
    if (PQntuples(r.get()) == 1) {
        version = uint64_t(pg::get_i64(r.get(), 0, 0));
        const auto* data = reinterpret_cast<const uint8_t*>(PQgetvalue(r.get(), 0, 1));
        const size_t n = size_t(PQgetlength(r.get(), 0, 1));
        if (n > 0) {
            Result<Chunk> chunk = m_codec.decode(std::span<const uint8_t>(data, n), c);
            if (chunk)
                theirs = std::move(*chunk);
            else if (Status s = quarantine(lod_key(c), version, chunk.error()); !s)
                return s;
            else
                version = known_version(c); // The tombstone's version.
        }
    }
    note_version(c, version);
    p.base = version;
    if (p.if_absent && theirs) { // Theirs is kept: drop ours (`p` dangles from here).
        m_queue.chunks.erase(c);
        return {};
    }
    if (p.whole || !p.record || !theirs)
        return {};
    p.merged = true;
    for (const BlockEdit& e : p.edits)
        theirs->set(e.pos, e.id);
    m_queue.chunks.reencode(c, p, *theirs, m_codec);
    std::lock_guard lock(m_health_mutex);
    m_local_changes.add(std::span(&c, 1)); // This process's copy lacks their edits: it should reload.
    return {};
}

Result<bool> PgStore::contains(ChunkCoord c) {
    if (const auto* queued = m_queue.chunks.find(c))
        return queued->has_value();
    if (Status s = ensure_connected(false); !s)
        return Error{s.error()};
    pg::Params p;
    p.add_coord(c);
    pg::ResultPtr r = pg::exec(m_conn, "vx_has", p, deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot look up chunk " + pg::coord_str(c));
    return PQntuples(r.get()) > 0;
}

Result<uint64_t> PgStore::count() {
    if (Status s = commit(); !s)
        return Error{s.error()};
    if (Status s = ensure_connected(true); !s)
        return Error{s.error()};
    pg::ResultPtr r = pg::exec(m_conn, "vx_count", pg::Params(), deadline(), m_timed_out);
    if (!pg::ok(r.get()) || PQntuples(r.get()) != 1)
        return error("cannot count chunks");
    return uint64_t(pg::get_i64(r.get(), 0, 0));
}

Status PgStore::for_each_coord(const std::function<bool(ChunkCoord)>& fn) {
    if (Status s = commit(); !s)
        return s;
    if (Status s = ensure_connected(true); !s)
        return s;
    pg::ResultPtr r = pg::exec(m_conn, "vx_list", pg::Params(), deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot list chunks");
    for (int i = 0, n = PQntuples(r.get()); i < n; ++i)
        if (!fn(ChunkCoord(pg::get_i32(r.get(), i, 0), pg::get_i32(r.get(), i, 1), pg::get_i32(r.get(), i, 2))))
            break;
    return {};
}

Result<std::optional<std::string>> PgStore::get_meta(std::string_view key) {
    if (auto it = m_queue.meta.find(key); it != m_queue.meta.end())
        return std::optional<std::string>(it->second);
    if (Status s = ensure_connected(false); !s)
        return Error{s.error()};
    pg::Params p;
    p.add_text(std::string(key));
    pg::ResultPtr r = pg::exec(m_conn, "vx_meta_get", p, deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot read metadata '" + std::string(key) + "'");
    if (PQntuples(r.get()) == 0)
        return std::optional<std::string>();
    return std::optional<std::string>(std::string(PQgetvalue(r.get(), 0, 0), size_t(PQgetlength(r.get(), 0, 0))));
}

Status PgStore::set_meta(std::string_view key, std::string_view value) {
    if (m_info.read_only)
        return Error{"PostgreSQL world '" + m_name + "' is open read-only"};
    if (Status s = m_queue.set_meta(key, value); !s)
        return Error{"PostgreSQL world '" + m_name + "': " + s.error()};
    return {};
}

} // namespace vx::world
