// PgStore (pg_store.h): URI redaction, connecting, the schema, loads, saves, catching up and health;
// the coarse levels are in pg_store_lod.cpp, the commit and the world-wide queries in pg_commit.cpp.
#include "world/store/pg_store.h"

#include <algorithm>
#include <cctype>

#include "world/base/log.h"
#include "world/store/pg_listener.h"
#include "world/store/pg_uri_params.h"
#include "world/store/pg_wire.h"

namespace vx::world {

namespace {

// Each attempt resolves every conflict it met; more than a few rounds means a hot spot written
// by many processes at once.
constexpr int kMaxCommitAttempts = 32;
constexpr std::chrono::milliseconds kMaxBackoff{8000};

} // namespace

bool is_pg_uri(std::string_view s) { return s.starts_with("postgresql://") || s.starts_with("postgres://"); }

namespace {

// libpq percent-decodes URI parameter names too: "pass%77ord=" sets the password.
std::string percent_decode(std::string_view s) {
    std::string out;
    const auto hex = [](char c) { return std::isxdigit(uint8_t(c)) != 0; };
    const auto digit = [](char c) { return std::isdigit(uint8_t(c)) ? c - '0' : (std::tolower(uint8_t(c)) - 'a') + 10; };
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && hex(s[i + 1]) && hex(s[i + 2])) {
            out += char(digit(s[i + 1]) * 16 + digit(s[i + 2]));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// scheme://user:password@host/db?key=value&...
std::string redact_uri(std::string_view uri) {
    const size_t start = uri.find("://") + 3;
    const size_t query = std::min(uri.find('?', start), uri.size());
    std::string out(uri.substr(0, query));
    // The credentials end at the last '@' before the query: a password may hold '/', ':' or '@'.
    if (const size_t at = out.rfind('@'); at != std::string::npos && at >= start)
        if (const size_t colon = out.find(':', start); colon < at)
            out.replace(colon + 1, at - colon - 1, "***");
    for (size_t p = query; p < uri.size();) {
        const size_t end = std::min(uri.find('&', p + 1), uri.size());
        const std::string_view param = uri.substr(p + 1, end - p - 1);
        const size_t eq = param.find('=');
        out += uri[p];
        out += eq != std::string_view::npos && percent_decode(param.substr(0, eq)) == "password"
                   ? std::string(param.substr(0, eq)) + "=***"
                   : std::string(param);
        p = end;
    }
    return out;
}

// key = value ... (a value may be quoted, with backslash escapes).
std::string redact_key_values(std::string_view s) {
    std::string out;
    const auto space = [&](size_t i) { return i < s.size() && std::isspace(uint8_t(s[i])) != 0; };
    for (size_t i = 0; i < s.size();) {
        if (space(i)) {
            out += s[i++];
            continue;
        }
        const size_t key = i;
        while (i < s.size() && s[i] != '=' && !space(i))
            ++i;
        const bool password = s.substr(key, i - key) == "password";
        out += s.substr(key, i - key);
        while (space(i) || (i < s.size() && s[i] == '='))
            out += s[i++];
        const size_t value = i;
        const bool quoted = i < s.size() && s[i] == '\'';
        for (i += quoted ? 1 : 0; i < s.size() && (quoted ? s[i] != '\'' : !space(i)); ++i)
            if (s[i] == '\\')
                ++i;
        i = std::min(i + (quoted ? 1 : 0), s.size());
        out += password ? std::string("***") : std::string(s.substr(value, i - value));
    }
    return out;
}

} // namespace

std::string redact_pg_uri(std::string_view uri) { return is_pg_uri(uri) ? redact_uri(uri) : redact_key_values(uri); }

PgStore::PgStore(PgStoreCreateInfo info)
    : m_info(std::move(info)), m_name(redact_pg_uri(m_info.uri)), m_codec(m_info.zstd_level),
      m_encoder(m_info.zstd_level, m_info.encode_threads), m_local_changes(m_info.max_pending_changes) {}

PgStore::~PgStore() {
    if (m_conn && pending_edits() > 0) {
        if (Status s = commit(); !s)
            VX_LOG_ERROR("%s (%zu edits not saved)", s.error().c_str(), pending_edits());
    } else if (pending_edits() > 0) {
        VX_LOG_ERROR("PostgreSQL world '%s' is not reachable: %zu edits not saved", m_name.c_str(),
                     pending_edits());
    }
    m_listener.reset();
    if (m_conn)
        PQfinish(m_conn);
}

Result<std::unique_ptr<PgStore>> PgStore::open(const PgStoreCreateInfo& given) {
    // vx's own URI parameters win over `given`, as the URI's connect_timeout does; libpq (the
    // listener's connection too) gets the URI without them.
    Result<PgUriParams> params = split_pg_uri_params(given.uri);
    if (!params)
        return Error{"PostgreSQL world '" + redact_pg_uri(given.uri) + "': " + params.error() + "; nothing opened"};
    PgStoreCreateInfo info = given;
    info.uri = std::move(params->uri);
    if (params->query_timeout)
        info.query_timeout = *params->query_timeout;
    std::unique_ptr<PgStore> store(new PgStore(info));
    if (Status s = store->connect(); !s)
        return Error{s.error()};
    if (Status s = store->init_schema(); !s)
        return Error{s.error()};
    if (info.listen) {
        store->m_listener = std::make_unique<pg::ChangeListener>(info.uri, info.connect_timeout_s,
                                                                info.max_pending_changes);
        store->m_listener->set_own_pid(PQbackendPID(store->m_conn));
    }
    return store;
}

Status PgStore::connect() {
    if (m_conn)
        PQfinish(m_conn);
    m_timed_out = false;
    {
        std::lock_guard lock(m_health_mutex);
        ++m_health.connect_attempts;
    }
    m_conn = pg::connect(m_info.uri, m_info.connect_timeout_s);
    if (PQstatus(m_conn) != CONNECTION_OK) {
        Error e{"cannot connect to PostgreSQL world '" + m_name + "': " + pg::message(m_conn)};
        PQfinish(m_conn);
        m_conn = nullptr;
        std::lock_guard lock(m_health_mutex);
        m_health.connected = false;
        m_health.last_error = e.message;
        return e;
    }
    PQsetnonblocking(m_conn, 1); // For the deadlines (pg_wire.h); cannot fail with nothing queued yet.
    if (m_listener)
        m_listener->set_own_pid(PQbackendPID(m_conn));
    if (m_info.lock_timeout.count() > 0) { // Only where the URI (options=-c ...) set none.
        const std::string sql = "SELECT set_config('lock_timeout', '" + std::to_string(m_info.lock_timeout.count()) +
                                "ms', false) WHERE current_setting('lock_timeout') = '0'";
        if (pg::ResultPtr r = pg::run(m_conn, sql.c_str(), deadline(), m_timed_out); !pg::ok(r.get()))
            return error("cannot set lock_timeout");
    }
    if (!m_schema_ready)
        return {};
    if (Status s = prepare(); !s)
        return s;
    if (m_lod_ready) { // Prepared statements belong to the connection: again on a new one.
        m_lod_ready = false;
        if (Result<bool> r = lod_tables(false); !r)
            return Error{r.error()};
    }
    return {};
}

Status PgStore::init_schema() {
    pg::ResultPtr r = pg::run(m_conn,
                              "SELECT to_regclass('vx_meta') IS NOT NULL, "
                              "(SELECT count(*) FROM pg_tables WHERE schemaname = current_schema())",
                              deadline(), m_timed_out);
    if (!pg::ok(r.get()) || PQntuples(r.get()) != 1)
        return error("cannot read the database's tables");
    const bool has_world = PQgetvalue(r.get(), 0, 0)[0] == 't';
    const std::string tables = PQgetvalue(r.get(), 0, 1);
    if (!has_world) {
        if (tables != "0")
            return Error{"database '" + m_name + "' holds " + tables +
                         " other tables and no vx world: refusing to use it (give vx an empty database)"};
        if (m_info.read_only || !m_info.create)
            return Error{"database '" + m_name + "' holds no vx world"};
        // Several processes may create the world at once: an advisory lock orders them, and
        // IF NOT EXISTS / ON CONFLICT make the later ones no-ops.
        const std::string sql = std::string("BEGIN; SELECT pg_advisory_xact_lock(7942519736); ") + pg::kSchemaSql +
                                "INSERT INTO vx_meta VALUES ('format', convert_to('" + pg::kFormat +
                                "', 'UTF8')) ON CONFLICT DO NOTHING; COMMIT;";
        pg::ResultPtr c = pg::run(m_conn, sql.c_str(), deadline(), m_timed_out);
        if (!pg::ok(c.get())) {
            Error e = error("cannot create the world's tables");
            if (m_conn)
                pg::run(m_conn, "ROLLBACK", deadline(), m_timed_out);
            return e;
        }
    }
    pg::ResultPtr f = pg::run(m_conn, "SELECT convert_from(value, 'UTF8') FROM vx_meta WHERE key = 'format'",
                              deadline(), m_timed_out);
    if (!pg::ok(f.get()))
        return error("cannot read the world's format");
    const std::string format = PQntuples(f.get()) == 1 ? PQgetvalue(f.get(), 0, 0) : "";
    if (format != pg::kFormat)
        return Error{"database '" + m_name + "' holds a vx world of format '" + format + "'; this build reads '" +
                     pg::kFormat + "'"};
    m_schema_ready = true;
    return prepare();
}

Status PgStore::prepare() {
    for (size_t i = 0; i < pg::kStatementCount; ++i) {
        const pg::Statement& st = pg::kStatements[i];
        pg::ResultPtr r = pg::prepare(m_conn, st.name, st.sql, deadline(), m_timed_out);
        if (!pg::ok(r.get()))
            return error(std::string("cannot prepare ") + pg::kStatements[i].name);
    }
    return {};
}

Error PgStore::error(const std::string& what, const std::string& why) {
    std::string cause = why.empty() ? pg::message(m_conn) : why;
    if (m_timed_out) // The connection is out of step with the server: only a new one is usable.
        cause = "no answer within query_timeout (" + std::to_string(m_info.query_timeout.count()) +
                " ms); connection dropped";
    Error e{"PostgreSQL world '" + m_name + "': " + what + ": " + cause};
    if (m_timed_out || !m_conn || PQstatus(m_conn) != CONNECTION_OK)
        lost(e.message);
    std::lock_guard lock(m_health_mutex);
    m_health.last_error = e.message;
    return e;
}

void PgStore::lost(const std::string& what) {
    if (m_conn) {
        PQfinish(m_conn);
        m_conn = nullptr;
    }
    m_next_retry = Clock::now() + m_backoff;
    std::lock_guard lock(m_health_mutex);
    if (m_health.connected)
        VX_LOG_WARN("%s; edits are kept in memory, reconnecting", what.c_str());
    m_health.connected = false;
    m_health.last_error = what;
}

PgStore::Clock::time_point PgStore::deadline() const { return pg::deadline_in(m_info.query_timeout); }

Status PgStore::ensure_connected(bool now) {
    if (m_conn && PQstatus(m_conn) == CONNECTION_OK)
        return {};
    if (m_conn)
        lost("PostgreSQL world '" + m_name + "': connection lost");
    if (!now && Clock::now() < m_next_retry)
        return Error{"PostgreSQL world '" + m_name + "' is not reachable; " + std::to_string(pending_edits()) +
                     " edits kept in memory"};
    if (Status s = connect(); !s) {
        m_backoff = std::min(m_backoff * 2, kMaxBackoff);
        m_next_retry = Clock::now() + m_backoff;
        return Error{s.error() + "; " + std::to_string(pending_edits()) + " edits kept in memory"};
    }
    m_backoff = std::chrono::milliseconds(250);
    std::lock_guard lock(m_health_mutex);
    m_health.connected = true;
    ++m_health.reconnects;
    VX_LOG_WARN("PostgreSQL world '%s': reconnected", m_name.c_str());
    return {};
}

Result<ChunkLoad> PgStore::load(ChunkCoord c) { return load_level(lod_key(c)); }

namespace {

// Level 0: x, y, z; coarse levels: level, x, y, z.
void add_key(pg::Params& p, LodCoord c) {
    if (c.level > 0)
        p.add_i16(int16_t(c.level));
    p.add_coord(c.chunk);
}

} // namespace

Result<ChunkLoad> PgStore::load_level(LodCoord c) {
    if (const auto* queued = c.level == 0 ? m_queue.chunks.find(c.chunk) : m_queue.lods.find(c)) {
        ChunkLoad out = load_queued(*queued, c, m_codec);
        if (c.level == 0) // The caller's own copy, not yet written: what it was loaded as.
            out.version = m_queue.chunks[c.chunk].caller_base.value_or(known_version(c.chunk));
        return out;
    }
    if (Status s = ensure_connected(false); !s)
        return Error{s.error()};
    if (c.level > 0) {
        Result<bool> ready = lod_tables(false);
        if (!ready)
            return Error{ready.error()};
        if (!*ready)
            return ChunkLoad{}; // No coarse level saved yet.
    }
    pg::Params p;
    add_key(p, c);
    pg::ResultPtr r = pg::exec(m_conn, c.level == 0 ? "vx_load" : "vx_lod_load", p, deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot load " + record_name(c));
    const bool found = PQntuples(r.get()) != 0;
    const uint64_t version = found ? uint64_t(pg::get_i64(r.get(), 0, 0)) : 0;
    if (c.level == 0)
        note_version(c.chunk, version); // 0, known absent: catch_up() notices when another process creates it.
    if (!found)
        return ChunkLoad{};
    const auto* data = reinterpret_cast<const uint8_t*>(PQgetvalue(r.get(), 0, 1));
    const size_t n = size_t(PQgetlength(r.get(), 0, 1));
    if (n == 0 && c.level == 0)
        return ChunkLoad{}; // A tombstone: erased.
    ChunkLoad out = load_stored(std::span<const uint8_t>(data, n), c, m_codec);
    if (c.level == 0 && out.state == LoadState::Present)
        out.version = version;
    if (out.state == LoadState::Corrupt)
        if (Status s = quarantine(c, version, out.problem); !s)
            return Error{s.error()};
    return out;
}

Status PgStore::quarantine(LodCoord c, uint64_t version, const std::string& reason) {
    VX_LOG_WARN("PostgreSQL world '%s': %s: %s%s", m_name.c_str(), record_name(c).c_str(), reason.c_str(),
                m_info.read_only ? "" : "; moved to quarantine");
    if (m_info.read_only)
        return {};
    pg::Params p;
    add_key(p, c);
    p.add_i64(int64_t(version));
    p.add_text(reason);
    const char* statement = c.level == 0 ? "vx_quarantine" : "vx_lod_quarantine";
    pg::ResultPtr r = pg::exec(m_conn, statement, p, deadline(), m_timed_out);
    if (!pg::ok(r.get()))
        return error("cannot quarantine " + record_name(c));
    if (c.level == 0 && PQntuples(r.get()) == 1)
        note_version(c.chunk, uint64_t(pg::get_i64(r.get(), 0, 0)));
    return {}; // No row: another process replaced the record meanwhile; nothing to move.
}

Status PgStore::save(std::span<const ChunkWrite> batch) {
    if (m_info.read_only)
        return Error{"PostgreSQL world '" + m_name + "' is open read-only"};
    m_queue.start(batch.size());
    // Records the caller did not encode are encoded together afterwards, on several threads.
    RecordBatchEncoder::Batch encodes;
    for (const ChunkWrite& w : batch) {
        const bool first = !m_queue.chunks.contains(w.coord);
        const uint64_t base = base_of(w);
        Pending& p = m_queue.chunks.write(w.coord, w.chunk, w.record, encodes);
        // A later write of a queued chunk keeps the first one's base: if another process wrote
        // since, all the queued edits are re-applied to its version. A write if absent expects
        // no row (0): a tombstone or another process's chunk then meets a conflict.
        const bool if_absent = w.if_absent && w.chunk && (first || p.if_absent);
        if (first)
            p.base = if_absent ? 0 : base;
        p.if_absent = if_absent;
        p.caller_base = w.base_version;
        if (!w.chunk || w.edits.empty()) {
            p.whole = true;
            p.edits.clear();
        } else if (!p.whole) {
            p.edits.insert(p.edits.end(), w.edits.begin(), w.edits.end());
        }
    }
    m_queue.chunks.encode(encodes, m_encoder, m_codec);
    return queued();
}

Status PgStore::queued() {
    {
        std::lock_guard lock(m_health_mutex);
        m_health.pending_edits = pending_edits();
    }
    if (m_queue.bytes() > m_info.max_pending_bytes)
        return commit();
    return {};
}

Status PgStore::tick(Clock::time_point now) {
    // While the server is away ticks stay quiet (health() says so; the queue waits) and try to
    // reconnect once the back-off has passed; flush() reports the error to whoever waits.
    if (!m_conn && (now < m_next_retry || !ensure_connected(false)))
        return {};
    if (Status s = catch_up(); !s)
        return m_conn ? s : Status{}; // Lost meanwhile: retried once reconnected.
    if (m_queue.since && now - *m_queue.since >= m_info.max_pending_age)
        return commit();
    return {};
}

Status PgStore::flush() { return commit(); }

Status PgStore::commit() {
    if (pending_edits() == 0)
        return {};
    // A connection that was up may have died unnoticed (a server restart): libpq learns it only
    // when it is used. Then once more, on a new connection. Safe even if the first attempt
    // committed before the link broke: this store's versions are then stale, so the retry meets a
    // conflict and re-applies the same edits (a whole-chunk write rewrites the same record).
    // Not after a timeout: the caller gets its error within query_timeout, and a later call
    // reconnects.
    const bool was_up = m_conn != nullptr;
    Status s = commit_attempts();
    if (!s && was_up && !m_conn && !m_timed_out)
        s = commit_attempts();
    return s;
}

Status PgStore::commit_attempts() {
    if (Status s = ensure_connected(true); !s)
        return s;
    if (!m_queue.lods.empty() || !m_queue.dirty.empty())
        if (Result<bool> r = lod_tables(true); !r)
            return Error{r.error() + "; " + std::to_string(pending_edits()) + " edits kept in memory"};
    std::vector<ChunkCoord> conflicts;
    for (int attempt = 0; attempt < kMaxCommitAttempts; ++attempt) {
        conflicts.clear();
        Result<bool> done = try_commit(conflicts);
        if (!done)
            return Error{done.error() + "; " + std::to_string(pending_edits()) + " edits kept in memory"};
        if (*done) {
            m_queue.clear();
            trim_versions();
            {
                std::lock_guard lock(m_health_mutex);
                m_health.pending_edits = 0;
            }
            return refused_meta();
        }
        for (ChunkCoord c : conflicts)
            if (Status s = resolve_conflict(c); !s)
                return s;
        std::lock_guard lock(m_health_mutex);
        m_health.conflicts += conflicts.size();
    }
    return Error{"PostgreSQL world '" + m_name + "': gave up after " + std::to_string(kMaxCommitAttempts) +
                 " conflicting attempts; edits kept in memory"};
}

Status PgStore::refused_meta() {
    if (m_refused_meta.empty())
        return {};
    std::string why;
    for (const std::string& r : m_refused_meta)
        why += (why.empty() ? "" : "; ") + r;
    m_refused_meta.clear();
    Error e{"PostgreSQL world '" + m_name + "': " + why + "; every other queued edit was committed"};
    std::lock_guard lock(m_health_mutex);
    m_health.last_error = e.message;
    return e;
}

Status PgStore::changed_since(const std::vector<ChunkCoord>& coords,
                             const std::function<uint64_t(ChunkCoord)>& expected, std::vector<ChunkCoord>& changed) {
    std::unordered_map<ChunkCoord, uint64_t, ChunkCoordHash> stored;
    constexpr size_t kBatch = 8192; // Coordinates per query (a few hundred KB of text).
    for (size_t begin = 0; begin < coords.size(); begin += kBatch) {
        const size_t end = std::min(coords.size(), begin + kBatch);
        std::string xs = "{", ys = "{", zs = "{";
        for (size_t i = begin; i < end; ++i) {
            const char* sep = i + 1 < end ? "," : "}";
            xs += std::to_string(coords[i].x) + sep;
            ys += std::to_string(coords[i].y) + sep;
            zs += std::to_string(coords[i].z) + sep;
        }
        pg::Params p;
        p.add_text(std::move(xs));
        p.add_text(std::move(ys));
        p.add_text(std::move(zs));
        pg::ResultPtr r = pg::exec(m_conn, "vx_versions", p, deadline(), m_timed_out);
        if (!pg::ok(r.get()))
            return error("cannot read the stored versions of " + std::to_string(end - begin) + " chunks");
        stored.clear();
        for (int i = 0, n = PQntuples(r.get()); i < n; ++i) {
            const ChunkCoord c(pg::get_i32(r.get(), i, 0), pg::get_i32(r.get(), i, 1), pg::get_i32(r.get(), i, 2));
            stored[c] = uint64_t(pg::get_i64(r.get(), i, 3));
        }
        for (size_t i = begin; i < end; ++i) {
            const auto it = stored.find(coords[i]);
            if ((it == stored.end() ? 0 : it->second) != expected(coords[i]))
                changed.push_back(coords[i]);
        }
    }
    return {};
}

Status PgStore::catch_up() {
    if (!m_listener)
        return {};
    // Read before the scan: a restart during it bumps the epoch again and the next tick rescans.
    const uint64_t epoch = m_listener->listen_epoch();
    if (epoch == m_caught_up_epoch)
        return {};
    if (m_forgot_versions) {
        // The caller may still hold chunks whose versions were forgotten (trim_versions), and
        // no scan of what is remembered can tell whether those moved on: everything is re-checked.
        m_caught_up_epoch = epoch;
        std::lock_guard lock(m_health_mutex);
        ++m_health.resyncs;
        m_local_changes.overflow();
        return {};
    }
    // The listener listens before the scan reads: a commit is either notified or seen here.
    std::vector<ChunkCoord> coords;
    coords.reserve(m_versions.size());
    for (const auto& [c, v] : m_versions)
        coords.push_back(c);
    std::vector<ChunkCoord> changed;
    if (Status s = changed_since(coords, [this](ChunkCoord c) { return known_version(c); }, changed); !s)
        return s;
    m_caught_up_epoch = epoch;
    std::lock_guard lock(m_health_mutex);
    m_health.caught_up += changed.size();
    m_local_changes.add(changed);
    return {};
}

void PgStore::note_version(ChunkCoord c, uint64_t version) {
    m_versions.erase(c);
    trim_versions(); // Before inserting, so `c` itself is kept.
    m_versions[c] = version;
}

void PgStore::trim_versions() {
    const size_t keep = m_info.max_known_versions / 2;
    if (m_versions.size() <= m_info.max_known_versions || m_queue.chunks.size() >= keep)
        return; // (A commit of more than `keep` chunks trims once it is done.)
    // Forget (in hash order: no recency is kept, forgetting is only slower) until half remain.
    // A forgotten lineage costs a conflict and a merge, as a forgotten version does.
    for (auto it = m_versions.begin(); it != m_versions.end() && m_versions.size() > keep;) {
        if (m_queue.chunks.contains(it->first)) {
            ++it;
            continue;
        }
        m_lineage.erase(it->first);
        it = m_versions.erase(it);
        m_forgot_versions = true;
    }
}

uint64_t PgStore::base_of(const ChunkWrite& w) const {
    if (!w.base_version)
        return known_version(w.coord);
    const auto it = m_lineage.find(w.coord);
    return it != m_lineage.end() && it->second.caller_base == *w.base_version ? it->second.latest : *w.base_version;
}

uint64_t PgStore::known_version(ChunkCoord c) const {
    const auto it = m_versions.find(c);
    return it == m_versions.end() ? 0 : it->second;
}

bool PgStore::poll_changes(std::vector<ChunkCoord>& out) {
    const bool missed = m_listener && m_listener->take(out);
    std::lock_guard lock(m_health_mutex);
    return m_local_changes.take(out) || missed;
}

StoreHealth PgStore::health() const {
    StoreHealth h;
    {
        std::lock_guard lock(m_health_mutex);
        h = m_health;
    }
    h.listener_down = m_listener && !m_listener->listening(); // Set at open, then only read.
    return h;
}

} // namespace vx::world
