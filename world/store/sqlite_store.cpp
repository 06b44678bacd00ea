// SqliteStore (sqlite_store.h): opening the file, level-0 chunks, metadata and the commit; the
// coarse levels are in sqlite_store_lod.cpp.
#include "world/store/sqlite_store.h"

#include <sqlite3.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "world/base/file_lock.h"
#include "world/base/log.h"
#include "world/store/sqlite_stmts.h"

namespace vx::world {

using namespace sqlite_detail;

namespace {

constexpr int64_t kApplicationId = 0x56585744; // "VXWD"
constexpr int64_t kSchemaVersion = 1;

// Durability (why synchronous=FULL). In WAL mode a transaction is committed once its frames and
// the commit frame are write()n to the -wal file. write() puts the bytes in the kernel page cache,
// which outlives the process, so even synchronous=NORMAL survives SIGKILL; what NORMAL can lose
// is the last transactions on an OS crash or power cut, because it fsyncs only at checkpoints.
// FULL fsyncs the WAL at every commit, so a flush() that returned success survives both. Commits
// are batched (one when tick() finds the oldest queued edit older than max_pending_age, 1 s by
// default; when the queue passes max_pending_bytes, 32 MiB; or on flush()), so the fsync costs
// little per chunk.
// https://www.sqlite.org/pragma.html#pragma_synchronous, https://www.sqlite.org/wal.html
const char* const kSchema = R"sql(
CREATE TABLE IF NOT EXISTS chunks(
  x INTEGER NOT NULL, y INTEGER NOT NULL, z INTEGER NOT NULL, data BLOB NOT NULL,
  PRIMARY KEY(x, y, z));
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY NOT NULL, value BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS quarantine(
  id INTEGER PRIMARY KEY, x INTEGER, y INTEGER, z INTEGER, data BLOB, reason TEXT, time INTEGER);
)sql";

void bind_coord(sqlite3_stmt* s, ChunkCoord c) {
    sqlite3_bind_int64(s, 1, c.x);
    sqlite3_bind_int64(s, 2, c.y);
    sqlite3_bind_int64(s, 3, c.z);
}

// column_is_i32's test (sqlite_stmts.h) in SQL, for counting (stray_rows).
const char* const kNotChunkKey =
    "NOT (typeof(x) = 'integer' AND typeof(y) = 'integer' AND typeof(z) = 'integer' AND "
    "x BETWEEN -2147483648 AND 2147483647 AND y BETWEEN -2147483648 AND 2147483647 AND "
    "z BETWEEN -2147483648 AND 2147483647)";

// Binds the key of `c` (level 0: x, y, z; coarse: level, x, y, z); returns the next parameter.
int bind_key(sqlite3_stmt* s, LodCoord c) {
    if (c.level > 0) {
        bind_lod(s, c);
        return 5;
    }
    bind_coord(s, c.chunk);
    return 4;
}

} // namespace

SqliteStore::SqliteStore(SqliteStoreCreateInfo info) : m_info(std::move(info)), m_codec(m_info.zstd_level),
      m_encoder(m_info.zstd_level, m_info.encode_threads) {}

SqliteStore::~SqliteStore() {
    if (m_db && pending_edits() > 0) {
        if (Status s = commit_queue(); !s) // Its error without "kept in memory": they go with the store.
            VX_LOG_ERROR("closing store '%s' lost %zu queued edits: %s", m_info.path.c_str(), pending_edits(),
                         s.error().c_str());
    }
    m_stmts.reset(); // Statements are finalized before the connection closes.
    m_lod_stmts.reset();
    sqlite3_close_v2(m_db);
}

std::string SqliteStore::sqlite_message(const char* msg) const {
    if (!m_db)
        return "out of memory";
    std::string out = msg ? msg : sqlite3_errmsg(m_db);
    // SQLite says "disk I/O error" for every failed file operation; its extended code names the
    // operation (https://www.sqlite.org/rescode.html). The OS's errno is often gone by then.
    const char* what = nullptr;
    switch (sqlite3_extended_errcode(m_db)) {
    case SQLITE_IOERR_WRITE: what = "writing the file failed: a full disk, a quota or a failing device"; break;
    case SQLITE_IOERR_FSYNC: what = "flushing the file to the disk failed"; break;
    case SQLITE_IOERR_READ: what = "reading the file failed"; break;
    case SQLITE_IOERR_SHORT_READ: what = "the file ended early"; break;
    case SQLITE_IOERR_TRUNCATE: what = "truncating the file failed"; break;
    default: break;
    }
    if (what)
        return out + " (" + what + ")";
    const int code = sqlite3_errcode(m_db) & 0xff, os = sqlite3_system_errno(m_db);
    if (os != 0 && (code == SQLITE_IOERR || code == SQLITE_CANTOPEN)) // Else a stale errno.
        out += std::string(" (") + std::strerror(os) + ")";
    return out;
}

Error SqliteStore::db_error(const std::string& what) const {
    return Error{"store '" + m_info.path + "': " + what + ": " + sqlite_message()};
}

Error SqliteStore::commit_error(const Status& s) const {
    return Error{s.error() + "; " + std::to_string(pending_edits()) + " edits kept in memory"};
}

Status SqliteStore::exec(const char* sql) {
    char* msg = nullptr;
    if (sqlite3_exec(m_db, sql, nullptr, nullptr, &msg) != SQLITE_OK) {
        Error e{"store '" + m_info.path + "': " + sqlite_message(msg)};
        sqlite3_free(msg);
        return e;
    }
    return {};
}

Result<std::unique_ptr<SqliteStore>> SqliteStore::open(const SqliteStoreCreateInfo& info) {
    VX_ASSERT_RETURN(info.zstd_level >= 1 && info.zstd_level <= 19, Error{"zstd level out of range"});
    std::unique_ptr<SqliteStore> store(new SqliteStore(info));
    if (Status s = store->init(); !s)
        return Error{s.error()};
    return store;
}

Status SqliteStore::init() {
    if (std::error_code ec; std::filesystem::is_directory(m_info.path, ec)) // SQLite said "disk I/O error".
        return Error{"store '" + m_info.path + "': is a folder, not a world file"};
    int flags = SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_EXRESCODE;
    flags |= m_info.read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
    if (!m_info.read_only && m_info.create)
        flags |= SQLITE_OPEN_CREATE;
    if (sqlite3_open_v2(m_info.path.c_str(), &m_db, flags, nullptr) != SQLITE_OK)
        return db_error("cannot open");
    if (!m_info.read_only && sqlite3_db_readonly(m_db, "main") == 1)
        return Error{"store '" + m_info.path + "': the file is read-only"};
    if (!m_info.read_only) { // Readers may look at a world a writer has open (WAL snapshots).
        auto lock = FileLock::acquire(m_info.path);
        if (!lock)
            return Error{"store " + lock.error()};
        m_lock = std::move(*lock);
    }
    sqlite3_busy_timeout(m_db, 2000);
    sqlite3_extended_result_codes(m_db, 1);
    if (Status s = init_schema(); !s)
        return s;
    m_stmts = std::make_unique<Stmts>();
    auto prep = [&](Stmt& st, const char* sql) {
        return sqlite3_prepare_v3(m_db, sql, -1, SQLITE_PREPARE_PERSISTENT, &st.s, nullptr) == SQLITE_OK;
    };
    Stmts& s = *m_stmts;
    const bool ok = prep(s.load, (load_columns() + "FROM chunks WHERE x=?1 AND y=?2 AND z=?3").c_str()) &&
                    prep(s.put, "INSERT OR REPLACE INTO chunks(x, y, z, data) VALUES(?1, ?2, ?3, ?4)") &&
                    prep(s.del, "DELETE FROM chunks WHERE x=?1 AND y=?2 AND z=?3") &&
                    prep(s.has, "SELECT 1 FROM chunks WHERE x=?1 AND y=?2 AND z=?3") &&
                    prep(s.count, "SELECT count(*) FROM chunks") && prep(s.list, "SELECT x, y, z FROM chunks") &&
                    prep(s.meta_get, "SELECT value FROM meta WHERE key=?1") &&
                    prep(s.meta_put, "INSERT OR REPLACE INTO meta(key, value) VALUES(?1, ?2)") &&
                    prep(s.q_put, "INSERT INTO quarantine(x, y, z, data, reason, time) "
                                  "SELECT x, y, z, data, ?4, strftime('%s', 'now') FROM chunks "
                                  "WHERE x=?1 AND y=?2 AND z=?3") &&
                    prep(s.q_count, "SELECT count(*) FROM quarantine");
    if (!ok)
        return db_error("cannot prepare statements");
    return {};
}

Status SqliteStore::init_schema() {
    // Reading the header pragmas is the first access to the file: a non-SQLite file fails here.
    auto query_int = [&](const char* sql, int64_t& out) {
        Stmt st;
        if (sqlite3_prepare_v2(m_db, sql, -1, &st.s, nullptr) != SQLITE_OK || sqlite3_step(st.s) != SQLITE_ROW)
            return false;
        out = sqlite3_column_int64(st.s, 0);
        return true;
    };
    int64_t app = 0, version = 0, objects = 0;
    if (!query_int("PRAGMA application_id", app) || !query_int("PRAGMA user_version", version) ||
        !query_int("SELECT count(*) FROM sqlite_schema", objects))
        return db_error("cannot read the database");
    const bool fresh = app == 0 && version == 0 && objects == 0;
    if (!fresh && app != kApplicationId)
        return Error{"store '" + m_info.path + "': not a vx world store (another SQLite database)"};
    if (!fresh && version != kSchemaVersion)
        return Error{"store '" + m_info.path + "': unsupported store version " + std::to_string(version)};
    if (m_info.read_only) {
        if (fresh)
            return Error{"store '" + m_info.path + "': empty database, not a vx world store"};
        return {};
    }
    {
        // The pragma answers with the mode in force: a file system without shared memory support
        // would silently keep a rollback journal, whose durability argument differs.
        Stmt st;
        if (sqlite3_prepare_v2(m_db, "PRAGMA journal_mode=WAL", -1, &st.s, nullptr) != SQLITE_OK ||
            sqlite3_step(st.s) != SQLITE_ROW)
            return db_error("cannot enable WAL mode");
        const auto* mode = reinterpret_cast<const char*>(sqlite3_column_text(st.s, 0));
        if (!mode || std::string(mode) != "wal")
            return Error{"store '" + m_info.path + "': WAL mode unavailable (journal mode " +
                         (mode ? mode : "?") + ")"};
    }
    if (Status s = exec("PRAGMA synchronous=FULL;"); !s)
        return s;
    if (!fresh)
        return {};
    const std::string init = std::string("BEGIN IMMEDIATE;") + kSchema +
                             "PRAGMA application_id=" + std::to_string(kApplicationId) +
                             "; PRAGMA user_version=" + std::to_string(kSchemaVersion) + "; COMMIT;";
    if (Status s = exec(init.c_str()); !s) {
        exec("ROLLBACK");
        return s;
    }
    return {};
}

Result<ChunkLoad> SqliteStore::load(ChunkCoord c) { return load_level(lod_key(c)); }

Result<SqliteStore::LevelStmts> SqliteStore::level_stmts(int level) {
    if (level == 0)
        return LevelStmts(*m_stmts);
    Result<bool> ready = lod_tables(false);
    if (!ready)
        return Error{ready.error()};
    if (!*ready)
        return LevelStmts{};
    return LevelStmts(*m_lod_stmts);
}

Result<ChunkLoad> SqliteStore::load_level(LodCoord c) {
    if (const auto* queued = c.level == 0 ? m_queue.chunks.find(c.chunk) : m_queue.lods.find(c))
        return load_queued(*queued, c, m_codec);
    Result<LevelStmts> stmts = level_stmts(c.level);
    if (!stmts)
        return Error{stmts.error()};
    if (!stmts->load)
        return ChunkLoad{}; // No coarse level saved yet.
    sqlite3_stmt* st = stmts->load;
    ResetGuard guard{st};
    bind_key(st, c);
    const int rc = sqlite3_step(st);
    if (rc == SQLITE_DONE)
        return ChunkLoad{};
    if (rc != SQLITE_ROW)
        return db_error("cannot load " + record_name(c));
    ChunkLoad out;
    if (const int64_t length = sqlite3_column_int64(st, 0); length > int64_t(max_record_bytes())) {
        out.state = LoadState::Corrupt; // As read_record_header says it, without reading it.
        out.problem = "corrupt chunk record: too long (" + std::to_string(length) + " bytes)";
    } else {
        // Decoded straight from SQLite's buffer, which stays valid until the statement is reset.
        const auto* p = static_cast<const uint8_t*>(sqlite3_column_blob(st, 1));
        const size_t n = size_t(sqlite3_column_bytes(st, 1));
        out = load_stored(std::span<const uint8_t>(p, p ? n : 0), c, m_codec);
    }
    if (out.state != LoadState::Corrupt)
        return out;
    sqlite3_reset(st);
    if (Status s = quarantine(c, out.problem); !s)
        return Error{s.error()};
    return out;
}

Status SqliteStore::quarantine(LodCoord c, const std::string& reason) {
    if (m_info.read_only) {
        // Nothing can be moved: log each bad record once per session.
        if (m_reported.insert({c.level, c.chunk.x, c.chunk.y, c.chunk.z}).second && m_info.log_corrupt)
            VX_LOG_WARN("store '%s': %s: %s", m_info.path.c_str(), record_name(c).c_str(), reason.c_str());
        return {};
    }
    // Logged once: after the move, the coordinate reads as absent.
    if (m_info.log_corrupt)
        VX_LOG_WARN("store '%s': %s: %s; moved to quarantine", m_info.path.c_str(), record_name(c).c_str(),
                    reason.c_str());
    Result<LevelStmts> stmts = level_stmts(c.level); // The tables exist: the record was read.
    if (!stmts)
        return Error{stmts.error()};
    if (Status s = exec("BEGIN IMMEDIATE"); !s)
        return s;
    // The row is copied inside SQLite (INSERT ... SELECT): its bytes are kept verbatim, whatever
    // their size, without passing through us.
    ResetGuard gq{stmts->q_put}, gd{stmts->del};
    const int reason_param = bind_key(stmts->q_put, c);
    sqlite3_bind_text(stmts->q_put, reason_param, reason.c_str(), int(reason.size()), SQLITE_STATIC);
    bind_key(stmts->del, c);
    if (sqlite3_step(stmts->q_put) != SQLITE_DONE || sqlite3_step(stmts->del) != SQLITE_DONE || !exec("COMMIT")) {
        Error e = db_error("cannot quarantine " + record_name(c));
        exec("ROLLBACK");
        return e;
    }
    return {};
}

Status SqliteStore::save(std::span<const ChunkWrite> batch) {
    if (m_info.read_only)
        return Error{"store '" + m_info.path + "' is open read-only"};
    m_queue.start(batch.size());
    // Records the caller did not encode are encoded together afterwards, on several threads.
    RecordBatchEncoder::Batch encodes;
    for (const ChunkWrite& w : batch)
        m_queue.chunks.write(w.coord, w.chunk, w.record, encodes);
    m_queue.chunks.encode(encodes, m_encoder, m_codec);
    return queued();
}

Status SqliteStore::queued() {
    if (m_queue.bytes() > m_info.max_pending_bytes)
        return commit();
    show_pending();
    return {};
}

void SqliteStore::show_pending() { m_pending_shown.store(m_queue.edits(), std::memory_order_relaxed); }

StoreHealth SqliteStore::health() const {
    StoreHealth h;
    h.pending_edits = m_pending_shown.load(std::memory_order_relaxed);
    return h;
}

Status SqliteStore::tick(Clock::time_point now) {
    if (m_queue.since && now - *m_queue.since >= m_info.max_pending_age)
        return commit();
    return {};
}

Status SqliteStore::flush() {
    // synchronous=FULL: the commit fsyncs the WAL before returning (see kSchema's comment).
    return commit();
}

Status SqliteStore::commit() {
    if (pending_edits() == 0)
        return {};
    if (Status s = commit_queue(); !s)
        return commit_error(s); // The queue is kept: a later commit retries.
    return {};
}

Status SqliteStore::commit_queue() {
    struct Shown { // Every way out, committed or not.
        SqliteStore& store;
        ~Shown() { store.show_pending(); }
    } shown{*this};
    if (!m_queue.lods.empty() || !m_queue.dirty.empty()) {
        Result<bool> ready = lod_tables(/*create=*/true);
        if (!ready)
            return Error{ready.error()};
    }
    // A file deleted (or replaced) under the open connection takes every later commit with it,
    // each reported durable; the queue is kept instead, and every flush says why it failed.
    int moved = 0;
    if (sqlite3_file_control(m_db, "main", SQLITE_FCNTL_HAS_MOVED, &moved) == SQLITE_OK && moved)
        return Error{"store '" + m_info.path +
                     "': the file was deleted or replaced while open; nothing more is saved to it"};
    if (Status s = exec("BEGIN IMMEDIATE"); !s)
        return s;
    if (Status s = commit_lod(); !s) {
        exec("ROLLBACK"); // The queue is kept: a later commit retries.
        return s;
    }
    const LevelStmts chunks(*m_stmts);
    for (const auto& [c, pending] : m_queue.chunks) {
        if (Status s = write_record(lod_key(c), pending.record, chunks); !s) {
            exec("ROLLBACK"); // The queue is kept: a later commit retries.
            return s;
        }
    }
    for (const auto& [key, value] : m_queue.meta) {
        sqlite3_stmt* st = m_stmts->meta_put.s;
        ResetGuard guard{st};
        sqlite3_bind_text(st, 1, key.data(), int(key.size()), SQLITE_STATIC);
        sqlite3_bind_blob(st, 2, value.data(), int(value.size()), SQLITE_STATIC);
        if (sqlite3_step(st) != SQLITE_DONE) {
            Error e = db_error("cannot write metadata '" + key + "'");
            exec("ROLLBACK");
            return e;
        }
    }
    if (Status s = exec("COMMIT"); !s) {
        exec("ROLLBACK");
        return s;
    }
    m_queue.clear();
    return {};
}

Status SqliteStore::write_record(LodCoord c, const std::optional<std::vector<uint8_t>>& record,
                                 const LevelStmts& stmts) {
    sqlite3_stmt* st = record ? stmts.put : stmts.del;
    ResetGuard guard{st};
    const int data_param = bind_key(st, c);
    if (record)
        sqlite3_bind_blob(st, data_param, record->data(), int(record->size()), SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_DONE)
        return db_error("cannot write " + record_name(c));
    return {};
}

Result<bool> SqliteStore::contains(ChunkCoord c) {
    if (const auto* queued = m_queue.chunks.find(c))
        return queued->has_value();
    sqlite3_stmt* st = m_stmts->has.s;
    ResetGuard guard{st};
    bind_coord(st, c);
    const int rc = sqlite3_step(st);
    if (rc != SQLITE_ROW && rc != SQLITE_DONE)
        return db_error("cannot look up " + record_name(lod_key(c)));
    return rc == SQLITE_ROW;
}

Result<uint64_t> SqliteStore::count() {
    if (Status s = commit(); !s)
        return Error{s.error()};
    sqlite3_stmt* st = m_stmts->count.s;
    ResetGuard guard{st};
    if (sqlite3_step(st) != SQLITE_ROW)
        return db_error("cannot count chunks");
    return uint64_t(sqlite3_column_int64(st, 0));
}

Result<uint64_t> SqliteStore::stray_rows() {
    if (Status s = commit(); !s)
        return Error{s.error()};
    Result<bool> lod = lod_tables(false);
    if (!lod)
        return Error{lod.error()};
    std::string sql = std::string("SELECT (SELECT count(*) FROM chunks WHERE ") + kNotChunkKey + ")";
    if (*lod)
        sql += std::string(" + (SELECT count(*) FROM lod_chunks WHERE ") + kNotChunkKey +
               " OR typeof(level) != 'integer' OR level NOT BETWEEN 1 AND " + std::to_string(kMaxLodLevel) + ")";
    Stmt st;
    if (sqlite3_prepare_v2(m_db, sql.c_str(), -1, &st.s, nullptr) != SQLITE_OK || sqlite3_step(st.s) != SQLITE_ROW)
        return db_error("cannot count stray rows");
    return uint64_t(sqlite3_column_int64(st.s, 0));
}

Result<uint64_t> SqliteStore::quarantine_count() {
    uint64_t n = 0;
    {
        sqlite3_stmt* st = m_stmts->q_count.s;
        ResetGuard guard{st};
        if (sqlite3_step(st) != SQLITE_ROW)
            return db_error("cannot count quarantined records");
        n = uint64_t(sqlite3_column_int64(st, 0));
    }
    Result<bool> ready = lod_tables(false);
    if (!ready)
        return Error{ready.error()};
    if (!*ready)
        return n;
    sqlite3_stmt* st = m_lod_stmts->q_count.s;
    ResetGuard guard{st};
    if (sqlite3_step(st) != SQLITE_ROW)
        return db_error("cannot count quarantined coarse records");
    return n + uint64_t(sqlite3_column_int64(st, 0));
}

Status SqliteStore::verify_database() {
    Stmt st;
    if (sqlite3_prepare_v2(m_db, "PRAGMA quick_check", -1, &st.s, nullptr) != SQLITE_OK)
        return db_error("cannot check the database");
    const int rc = sqlite3_step(st.s);
    if (rc != SQLITE_ROW)
        return db_error("cannot check the database");
    const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(st.s, 0));
    const std::string first = text ? text : "";
    if (first != "ok")
        return Error{"store '" + m_info.path + "': damaged database: " + first};
    return {};
}

Status SqliteStore::for_each_coord(const std::function<bool(ChunkCoord)>& fn) {
    if (Status s = commit(); !s)
        return s;
    sqlite3_stmt* st = m_stmts->list.s;
    ResetGuard guard{st};
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        if (!column_is_i32(st, 0) || !column_is_i32(st, 1) || !column_is_i32(st, 2))
            continue; // Not a chunk's row (stray_rows).
        const ChunkCoord c(int32_t(sqlite3_column_int64(st, 0)), int32_t(sqlite3_column_int64(st, 1)),
                           int32_t(sqlite3_column_int64(st, 2)));
        if (!fn(c))
            return {};
    }
    if (rc != SQLITE_DONE)
        return db_error("cannot list chunks");
    return {};
}

Result<std::optional<std::string>> SqliteStore::get_meta(std::string_view key) {
    if (auto it = m_queue.meta.find(key); it != m_queue.meta.end())
        return std::optional<std::string>(it->second);
    sqlite3_stmt* st = m_stmts->meta_get.s;
    ResetGuard guard{st};
    sqlite3_bind_text(st, 1, key.data(), int(key.size()), SQLITE_STATIC);
    const int rc = sqlite3_step(st);
    if (rc == SQLITE_DONE)
        return std::optional<std::string>();
    if (rc != SQLITE_ROW)
        return db_error("cannot read metadata '" + std::string(key) + "'");
    const auto* p = static_cast<const char*>(sqlite3_column_blob(st, 0));
    return std::optional<std::string>(std::string(p ? p : "", size_t(sqlite3_column_bytes(st, 0))));
}

Status SqliteStore::set_meta(std::string_view key, std::string_view value) {
    if (m_info.read_only)
        return Error{"store '" + m_info.path + "' is open read-only"};
    if (Status s = m_queue.set_meta(key, value); !s)
        return Error{"store '" + m_info.path + "': " + s.error()};
    show_pending();
    return {};
}

} // namespace vx::world
