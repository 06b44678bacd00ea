#pragma once
// SqliteStore: a ChunkStore in one SQLite 3 database file (WAL mode).
//   chunks(x, y, z, data)                  one chunk record per chunk coordinate
//   meta(key, value)                        metadata strings
//   quarantine(id, x, y, z, data, reason, time)  records that failed verification, kept verbatim
// Coarse levels of detail, in tables created by the first commit that writes one (files made
// before levels existed open unchanged, also read-only; a missing table reads as empty):
//   lod_chunks(level, x, y, z, data)       one record per coarse chunk (chunk_record.h, level seeded)
//   lod_dirty(level, x, y, z)              coarse chunks made stale by a committed level-0 edit
//   lod_quarantine(id, level, x, y, z, data, reason, time)  coarse records that failed verification
// Edits queue in memory and commit in one transaction (see chunk_store.h for the write model).
// The file carries application_id "VXWD" and user_version 1; any other SQLite file is refused.
// One read-write store per file at a time, in all processes (FileLock on "<path>-lock"); readers
// are not limited.
// Thread affinity: not thread-safe; one serial I/O lane thread only (as every ChunkStore).

#include <atomic>
#include <chrono>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "world/base/file_lock.h"
#include "world/store/chunk_record.h"
#include "world/store/chunk_store.h"
#include "world/store/pending_writes.h"
#include "world/store/record_batch_encoder.h"

struct sqlite3;
struct sqlite3_stmt;

namespace vx::world {

struct SqliteStoreCreateInfo {
    std::string path;                               // Database file; its directory must exist.
    bool read_only = false;                         // Open an existing store for reading only.
    bool create = true;                             // Create the file if missing (read-write only).
    std::chrono::milliseconds max_pending_age{1000}; // tick() commits edits older than this.
    size_t max_pending_bytes = size_t(32) << 20;    // save() commits when the queue holds more.
    int zstd_level = 1;                             // 1..3.
    // Threads encoding the chunks of a save() batch that come without records (the caller
    // included; 0: the machine's hardware threads, at most 8; 1: the caller alone).
    unsigned encode_threads = 0;
    bool log_corrupt = true;                        // Log each corrupt record found (once).
};

class SqliteStore final : public ChunkStore {
public:
    // Opens or creates a store. Errors (one line, naming the path): directory missing, file not a
    // database or not a vx store, read-only file opened for writing, unsupported version.
    static Result<std::unique_ptr<SqliteStore>> open(const SqliteStoreCreateInfo& info);
    // Commits queued edits (errors are logged: call flush() first to see them) and closes.
    ~SqliteStore() override;
    SqliteStore(const SqliteStore&) = delete;
    SqliteStore& operator=(const SqliteStore&) = delete;

    Result<ChunkLoad> load(ChunkCoord c) override;
    using ChunkStore::save;
    Status save(std::span<const ChunkWrite> batch) override;
    Status tick(Clock::time_point now) override;
    Status flush() override;
    Result<bool> contains(ChunkCoord c) override;
    Result<uint64_t> count() override;
    Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override;
    Result<std::optional<std::string>> get_meta(std::string_view key) override;
    Status set_meta(std::string_view key, std::string_view value) override;
    bool read_only() const override { return m_info.read_only; }
    using ChunkStore::save_lod;
    bool supports_lod() const override { return true; }
    Result<ChunkLoad> load_lod(LodCoord c) override;
    Status save_lod(std::span<const LodWrite> batch) override;
    Status mark_lod_dirty(std::span<const LodCoord> coords) override;
    Result<std::vector<LodCoord>> list_lod_dirty() override;
    Result<std::vector<LodCoord>> list_lod_coords() override;

    // Queued edits (chunks, coarse chunks, dirty marks and metadata) not yet committed.
    size_t pending_edits() const override { return m_queue.edits(); }
    // Thread-safe: pending_edits as of the last call that changed the queue (the rest of
    // StoreHealth is a server's; a file is always "connected").
    StoreHealth health() const override;
    // Records in the quarantine tables (level 0 and coarse).
    Result<uint64_t> quarantine_count();
    // Rows whose keys name no chunk (a coordinate that is not a 32-bit integer, a level outside
    // 1..kMaxLodLevel): written by something else, they are left out of every listing (cast to
    // 32 bits they named real chunks: x + 2^32 listed as x) and left in place.
    Result<uint64_t> stray_rows();
    // Runs SQLite's PRAGMA quick_check over the whole file (O(size)); the error names the first
    // problem found.
    Status verify_database();
    // Commits queued edits without forcing durability beyond the synchronous setting (which is
    // FULL, so in practice the same as flush()).
    Status commit();

private:
    struct Stmts;
    struct LodStmts;
    struct LevelStmts; // The statements of one level's records.
    explicit SqliteStore(SqliteStoreCreateInfo info);
    Status init();
    Status init_schema();
    // Prepares the coarse-level statements once their tables exist; `create`: creates the tables
    // first (read-write only). Returns false when they do not exist (and `create` is false).
    Result<bool> lod_tables(bool create);
    // The statements of level `level` (0: the chunks table); all null when the coarse-level tables
    // do not exist yet.
    Result<LevelStmts> level_stmts(int level);
    // load() and load_lod() (level 0: the chunks table).
    Result<ChunkLoad> load_level(LodCoord c);
    Status quarantine(LodCoord c, const std::string& reason);
    // Writes one queued record of `c` (nullopt: deletes it), inside commit()'s transaction.
    Status write_record(LodCoord c, const std::optional<std::vector<uint8_t>>& record, const LevelStmts& stmts);
    Status commit_lod(); // Inside commit()'s transaction.
    Status queued();     // After a save: commits when the queue passed its byte bound.
    void show_pending(); // Publishes the queue's size to health().
    Result<std::vector<LodCoord>> list_lod(bool dirty); // Dirty marks, or stored coarse chunks.
    Status exec(const char* sql);
    Error db_error(const std::string& what) const;
    // SQLite's message (`msg`, else the connection's), with the file operation that failed where
    // the file system failed it ("disk I/O error (writing the file failed: ...)").
    std::string sqlite_message(const char* msg = nullptr) const;
    Status commit_queue(); // commit()'s transaction: every queued write, or none.
    // A commit's failure, saying the queue is kept.
    Error commit_error(const Status& s) const;

    SqliteStoreCreateInfo m_info;
    sqlite3* m_db = nullptr;
    FileLock m_lock; // Read-write stores: one writer per file (file_lock.h).
    std::unique_ptr<Stmts> m_stmts;
    std::unique_ptr<LodStmts> m_lod_stmts; // Null until the coarse-level tables are found.
    RecordCodec m_codec;
    RecordBatchEncoder m_encoder;
    StoreQueue<> m_queue; // Edits not yet committed.
    std::atomic<size_t> m_pending_shown{0}; // Its size for health() (show_pending()).
    std::set<std::tuple<int, int, int, int>> m_reported; // Corrupt records logged (read-only): level, x, y, z.
};

// Result of check_store: every record read and verified.
struct StoreCheck {
    uint64_t records = 0;     // Rows in the chunks and lod_chunks tables.
    uint64_t corrupt = 0;     // Of those, records that failed verification.
    uint64_t quarantined = 0; // Rows in the quarantine tables (moved aside earlier).
    bool database_ok = true;  // SQLite's own PRAGMA quick_check passed.
    std::vector<std::string> problems; // The first few problems found, one line each.
};

// Opens the store at `path` read-only and verifies every record (checksum, coordinates, content)
// and the database structure. Moves nothing. Not thread-safe with respect to other writers in
// this process; safe beside a writer in another process (WAL readers see a snapshot).
Result<StoreCheck> check_store(const std::string& path);

} // namespace vx::world
