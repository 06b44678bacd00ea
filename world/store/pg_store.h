#pragma once
// PgStore: a ChunkStore in a PostgreSQL database, for worlds that several processes use at once
// (a generation farm, game servers over one map, an editor beside a game). One world per
// database, named by a libpq connection URI (postgresql://[user@]host[:port]/dbname?...).
//
// Tables (created when absent; a database holding other tables and no vx world is refused):
//   vx_meta(key, value)                       metadata; key 'format' = 'vx-world-1'
//   vx_chunks(x, y, z, version, data)         one chunk record (chunk_record.h) per coordinate
//   vx_quarantine(id, x, y, z, version, data, reason, at)  records that failed verification
// Coarse levels of detail, created by the first commit that writes one (worlds made before
// levels exist open unchanged; missing tables read as empty):
//   vx_lod_chunks(level, x, y, z, version, data)   one coarse chunk record (level-seeded checksum)
//   vx_lod_dirty(level, x, y, z)                   coarse chunks made stale by a level-0 edit
//   vx_lod_quarantine(id, level, x, y, z, version, data, reason, at)
// Coarse chunks are derived data: their upserts are last-writer-wins (no versions compared, no
// edit replay), sent in the same pipelined transaction as the chunks, and notified on vx_chunks
// with payloads "lod;level,x,y,z;..." (poll_lod_changes).
//
// Writes: save() queues records in memory (read back at once, as in every ChunkStore); a commit
// sends every queued record as one transaction of versioned upserts in coordinate order, in one
// round trip (pipelined up to one sync point: an implicit transaction the server commits there),
// so a batch lands whole or not at all and a killed writer leaves no torn record (PostgreSQL's
// WAL; synchronous_commit on, so a flush() that succeeded survives a server crash too). Each
// upsert states the version this process last saw; when another process wrote the chunk since,
// that upsert fails, the transaction is rolled back, one query finds every chunk that conflicted,
// the newer records are fetched, this process's own edits (ChunkWrite::edits) are re-applied to
// them, and the batch is retried: no acknowledged edit of either process is lost. A commit also
// sends NOTIFY vx_chunks with the coordinates; a listener thread (its own connection) collects
// other processes' notifications for poll_changes().
// Notifications sent while the listener was not connected (a server restart, a dropped link) are
// lost, so each time it starts listening the next tick() compares every version this store knows
// (chunks it loaded, absent ones included, or wrote) with the table and reports the chunks that
// moved on through poll_changes() as well. Once versions were forgotten (max_known_versions), a
// chunk the caller still holds may have no version to compare: then the catch-up makes
// poll_changes() ask for a resync (the caller re-checks every chunk it holds) instead.
//
// Connection loss (or a server that stops answering for query_timeout): queued edits stay in
// memory; tick() reconnects with exponential back-off (0.25 s doubling to 8 s), flush() and
// load() report the error; health() says so. A commit on a connection that died unnoticed (a
// server restart) reconnects at once and tries again (not after a timeout: one wait is enough).
// Destruction commits queued edits only over a live connection (one that is down was reported by
// the last flush; no further connect timeout is spent) and logs any edits it could not save.
//
// Thread affinity: as every ChunkStore, one thread (the engine's I/O lane) calls everything but
// poll_changes() and health(), which are thread-safe.

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "world/store/chunk_record.h"
#include "world/store/pg_listener.h"
#include "world/store/chunk_store.h"
#include "world/store/pending_writes.h"
#include "world/store/record_batch_encoder.h"

struct pg_conn;

namespace vx::world {

struct PgStoreCreateInfo {
    // libpq connection URI or key=value string. A URI may also carry vx's own parameters, taken
    // out before libpq reads it (pg_uri_params.h), so a world opened by its URI alone (open_store,
    // the engine's WorldSource, the vx CLI) can set them; they win over the fields here:
    //   vx_query_timeout_ms=N   query_timeout, N milliseconds from 1 to 3,600,000
    // e.g. postgresql://host/world?vx_query_timeout_ms=2000. A bad value fails open() naming it.
    std::string uri;
    bool read_only = false;                          // Refuse writes (readers still get notified).
    bool create = true;                              // Create the tables in an empty database.
    bool listen = true;                              // Run the change listener (poll_changes).
    // Changed coordinates kept until poll_changes() takes them (about 40 B each); past this they
    // are forgotten and poll_changes() asks the caller to re-check everything it holds.
    size_t max_pending_changes = size_t(1) << 16;
    std::chrono::milliseconds max_pending_age{1000}; // tick() commits edits older than this.
    size_t max_pending_bytes = size_t(32) << 20;     // save() commits when the queue holds more.
    int zstd_level = 1;                              // 1..3.
    // Threads encoding the chunks of a save() batch that come without records (the caller
    // included; 0: the machine's hardware threads, at most 8; 1: the caller alone).
    unsigned encode_threads = 0;
    int connect_timeout_s = 3;                       // Per connection attempt (the URI's own wins).
    // lock_timeout of the store's session, unless the URI sets one: a row or table lock another
    // session holds fails a commit (edits kept, retried later) or a load after this long instead
    // of blocking the I/O lane for ever. 0: wait for ever.
    std::chrono::milliseconds lock_timeout{5000};
    // The longest one round trip may wait for the server's answer (a statement, or a commit's
    // whole pipelined transaction), in milliseconds. A server process that is alive but stopped
    // answering (frozen, a stuck disk) passes keepalives, so without this the I/O lane, flush()
    // and shutdown would wait for ever. Past it the call returns an error naming query_timeout,
    // the connection is dropped (not cancelled: a cancel request to a frozen server blocks too),
    // queued edits are kept, and a later call reconnects. A commit that landed anyway is met by
    // the retry as a conflict and its edits re-applied. Longer than lock_timeout, so a lock wait
    // reports as such. 0: wait for ever. The URI's vx_query_timeout_ms wins.
    std::chrono::milliseconds query_timeout{15000};
    // Chunk versions remembered (about 60 B each). Past this, versions of chunks with no queued
    // edit are forgotten down to half: a later commit of such a chunk costs one conflict round
    // trip (reload, re-apply edits) but stays correct, so a long session's memory stays bounded.
    size_t max_known_versions = size_t(1) << 18;
};

// True for strings libpq reads as a connection URI ("postgresql://", "postgres://").
bool is_pg_uri(std::string_view s);
// The URI with any password replaced by "***", for messages and logs.
std::string redact_pg_uri(std::string_view uri);

class PgStore final : public ChunkStore {
public:
    // Connects, checks (or creates) the schema. Errors, one line naming the database: a bad vx
    // parameter in the URI (nothing is opened), cannot connect (server down, no such database,
    // authentication), a database holding something else, an unsupported format version.
    static Result<std::unique_ptr<PgStore>> open(const PgStoreCreateInfo& given);
    // Commits queued edits if connected (else logs how many are lost), stops the listener,
    // closes the connections.
    ~PgStore() override;
    PgStore(const PgStore&) = delete;
    PgStore& operator=(const PgStore&) = delete;

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
    bool poll_changes(std::vector<ChunkCoord>& out) override;
    void poll_lod_changes(std::vector<LodCoord>& out) override;
    using ChunkStore::save_lod;
    bool supports_lod() const override { return true; }
    Result<ChunkLoad> load_lod(LodCoord c) override;
    Status save_lod(std::span<const LodWrite> batch) override;
    Status mark_lod_dirty(std::span<const LodCoord> coords) override;
    Result<std::vector<LodCoord>> list_lod_dirty() override;
    Result<std::vector<LodCoord>> list_lod_coords() override;
    StoreHealth health() const override;

    // Commits queued edits now (a synchronous commit: durable when it returns success).
    Status commit();
    size_t pending_edits() const override { return m_queue.edits(); }
    // The version of chunk `c` this store last read or wrote (0: absent or never seen).
    uint64_t known_version(ChunkCoord c) const;

private:
    struct Pending {
        std::optional<std::vector<uint8_t>> record; // Nullopt: erase.
        std::vector<BlockEdit> edits;               // Since `base`.
        bool whole = false;                         // A write without edits: replaces the chunk.
        // The stored version this write replaces (the commit checks the row still is it): the
        // first queued write's (base_of), or the version a conflict merged onto.
        uint64_t base = 0;
        std::optional<uint64_t> caller_base; // The latest write's ChunkWrite::base_version.
        bool merged = false; // Another process's blocks were merged in: no caller's copy has them.
        bool if_absent = false; // ChunkWrite::if_absent: `base` is 0 or a tombstone's version.
    };
    // What this process's own commits made of a caller's copy: a copy loaded as `caller_base`
    // (plus edits) was written as `latest`, with nothing of another process merged in. A later
    // save of that copy (the caller never learns `latest`) replaces `latest`.
    struct Lineage {
        uint64_t caller_base = 0;
        uint64_t latest = 0;
    };

    explicit PgStore(PgStoreCreateInfo info);
    Status connect();
    Status ensure_connected(bool now); // now: try at once, else only when the back-off elapsed.
    Status init_schema();
    Status prepare();
    // Prepares the coarse-level statements once their tables exist; `create`: creates the tables
    // first. False when they do not exist (and `create` is false). Needs a connection.
    Result<bool> lod_tables(bool create);
    Result<std::vector<LodCoord>> list_lod(const char* statement, const char* what);
    void lost(const std::string& what);
    // The deadline of a round trip on m_conn starting now (query_timeout; max: none). A round trip
    // past it sets m_timed_out (pg_wire.h), and error() then drops the connection.
    Clock::time_point deadline() const;
    // load() and load_lod() (level 0: vx_chunks, with versions and tombstones).
    Result<ChunkLoad> load_level(LodCoord c);
    Status quarantine(LodCoord c, uint64_t version, const std::string& reason);
    // After a save: publishes the queue length; commits when the queue passed its byte bound.
    Status queued();
    Status commit_attempts(); // commit() on one connection: rounds of try_commit + conflicts.
    Result<bool> try_commit(std::vector<ChunkCoord>& conflicts);
    // try_commit's steps. CommitOrder: the queue sorted as sent, and the notification payloads.
    struct CommitOrder;
    CommitOrder commit_order() const;
    // Pipeline the commit's statements (chunk upserts; coarse chunks and dirty marks; metadata and
    // notifications); false when one could not be sent.
    bool send_chunk_writes(const CommitOrder& order);
    bool send_lod_writes(const CommitOrder& order);
    bool send_meta_and_notify(const CommitOrder& order);
    // Drops queued metadata entry `index` (in the queue's order) when the server refused it for good
    // (SQLSTATE `state`, message `why`), for refused_meta() to report; false: not such a refusal.
    bool drop_refused_meta(size_t index, const std::string& state, const std::string& why);
    // After a conflict: appends the chunks of `order` whose stored version is not their base; an
    // error when none is.
    Status find_conflicts(const std::vector<ChunkCoord>& order, std::vector<ChunkCoord>& conflicts);
    // After a commit: remembers the versions written (`versions[i]`: `order[i]`'s) and the lineages.
    void note_committed(const std::vector<ChunkCoord>& order, const std::vector<uint64_t>& versions);
    Status catch_up(); // After the listener (re)started: report chunks changed meanwhile.
    // Appends the chunks of `coords` whose stored version is not `expected`'s (0: absent).
    Status changed_since(const std::vector<ChunkCoord>& coords, const std::function<uint64_t(ChunkCoord)>& expected,
                         std::vector<ChunkCoord>& changed);
    // The stored version a write of `w` replaces: its base_version, or this process's own later
    // write of that copy (Lineage); without one, the known version.
    uint64_t base_of(const ChunkWrite& w) const;
    Status resolve_conflict(ChunkCoord c);
    // An error naming the world; `why`: the cause ("": the connection's last message).
    Error error(const std::string& what, const std::string& why = {});
    // After a commit: the metadata the server refused for good and try_commit dropped, as one
    // error (none: success).
    Status refused_meta();
    void note_version(ChunkCoord c, uint64_t version); // Remembers, then trim_versions().
    void trim_versions();

    PgStoreCreateInfo m_info;
    std::string m_name; // Redacted URI for messages.
    pg_conn* m_conn = nullptr;
    bool m_timed_out = false; // A round trip on m_conn passed query_timeout; cleared by connect().
    bool m_schema_ready = false;
    bool m_lod_ready = false; // The coarse-level tables exist and their statements are prepared.
    RecordCodec m_codec;
    RecordBatchEncoder m_encoder;
    std::unordered_map<ChunkCoord, uint64_t, ChunkCoordHash> m_versions; // Last version seen.
    std::unordered_map<ChunkCoord, Lineage, ChunkCoordHash> m_lineage;   // Trimmed with m_versions.
    StoreQueue<Pending> m_queue; // Edits not yet committed.
    Clock::time_point m_next_retry{};
    std::chrono::milliseconds m_backoff{250};
    std::unique_ptr<pg::ChangeListener> m_listener;
    uint64_t m_caught_up_epoch = 0; // The listener's listen_epoch() the last catch_up() served.
    // trim_versions() forgot a version: the caller may hold chunks catch_up() cannot check, so a
    // catch-up asks for a resync instead. Stays set (such a chunk may be held for ever).
    bool m_forgot_versions = false;
    std::vector<std::string> m_refused_meta; // Dropped by try_commit; reported by refused_meta().
    pg::ChangeSet<ChunkCoord, ChunkCoordHash> m_local_changes; // Merged, caught up; m_health_mutex.

    mutable std::mutex m_health_mutex; // Guards m_health and m_local_changes.
    StoreHealth m_health;
};

} // namespace vx::world
