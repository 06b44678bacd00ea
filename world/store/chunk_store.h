#pragma once
// ChunkStore: persistent storage of chunk records (world/store/chunk_record.h) plus a few metadata
// strings (seed, block registry names). Implementations: SqliteStore (one file, one writing
// process, batched, crash-safe), PgStore (a PostgreSQL database shared by several processes:
// versioned writes, change notifications), VdbStore (world/vdb, read-only: save, erase and
// set_meta return an error, tick and flush succeed with nothing to do) and VdbOverlayStore
// (world/vdb: a store's edits layered over a VdbStore).
//
// Thread affinity of every implementation: not thread-safe. The engine calls a store from its one
// serial I/O lane thread only (one call at a time, all on that thread); main-thread code never
// touches it directly.
//
// Write model: save/erase/set_meta queue edits in memory (read back at once by load/contains/
// get_meta on the same store); they reach the disk in one transaction when tick() finds the oldest
// queued edit older than the store's bound, when the queue grows too big, or on flush(). Only
// flush() promises durability: when it returns success, every edit queued before it survives a
// crash of the process.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "world/base/result.h"
#include "world/chunk.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

namespace vx::world {

enum class LoadState : uint8_t {
    Present, // The chunk was stored and decoded.
    Absent,  // Nothing stored at this coordinate (generate it).
    Corrupt, // A record was there but failed verification; it was moved aside where the store
             // can (SqliteStore: the quarantine table), so regenerating and saving loses nothing.
};

struct ChunkLoad {
    LoadState state = LoadState::Absent;
    std::optional<Chunk> chunk; // Set when state == Present.
    std::string problem;        // When state == Corrupt: what was wrong, one line.
    // The stored version `chunk` is, in a store shared between processes (PgStore's row
    // version); 0: absent, or a store with one writer. Hand it back as ChunkWrite::base_version
    // when saving this copy.
    uint64_t version = 0;
};

// One block changed by this process: chunk-local position and its new id.
struct BlockEdit {
    LocalPos pos{0};
    BlockId id = kAir;
};

// One edit of a save batch. `chunk` == nullptr erases the stored chunk.
struct ChunkWrite {
    ChunkCoord coord{0};
    const Chunk* chunk = nullptr; // Read during save() only (encoded at once).
    // The blocks this process changed since it loaded (or last saved) the chunk, oldest first.
    // A shared store (PgStore) that finds the chunk changed by another process meanwhile
    // re-applies these to the newer version instead of overwriting it. Empty: `chunk` replaces
    // whatever is stored (a freshly generated chunk, or a store with one writer). Read during
    // save() only.
    std::span<const BlockEdit> edits{};
    // The chunk's record already encoded (encode_chunk_record / RecordCodec, e.g. on a worker
    // thread so the store's thread only writes): stored as is, `chunk` is then not read. The
    // caller vouches that it encodes `chunk` at `coord` (`chunk` stays non-null: null erases).
    std::span<const uint8_t> record{};
    // The ChunkLoad::version the caller's copy was loaded as, `edits` made on top (0: it was
    // absent). A shared store writes only if no other process wrote the chunk since then, else it
    // merges (above): a copy made from an older version than one the store read later, for a
    // load whose result the caller had not applied, stays older. Nullopt: the version this store
    // last read or wrote (right only when the caller applies every load). Single-writer stores
    // ignore it.
    std::optional<uint64_t> base_version{};
    // Write only where no chunk is stored (a generated chunk: pregeneration checks contains()
    // first). A shared store that finds one another process stored meanwhile drops this write
    // and keeps theirs; single-writer stores ignore it (nobody writes between the check and the
    // save). A later plain write of the coordinate in the same queue makes it unconditional.
    bool if_absent = false;
};

// One coarse chunk of a save_lod batch (levels of detail, world/lod/lod_coords.h). `chunk` ==
// nullptr erases the stored coarse chunk. Coarse chunks are derived data (the downsampling of
// the level below), so there are no block edits to replay: the last write wins.
struct LodWrite {
    LodCoord coord{};             // Level 1..kMaxLodLevel.
    const Chunk* chunk = nullptr; // Read during save_lod() only (encoded at once).
    // As ChunkWrite::record: the record already encoded at `coord` (RecordCodec::encode_lod).
    std::span<const uint8_t> record{};
};

// How a store's connection to its backing storage is doing (shared stores; files are always up).
struct StoreHealth {
    bool connected = true;         // False while the server cannot be reached; edits are kept.
    uint64_t reconnects = 0;       // Connections re-established after a loss.
    uint64_t conflicts = 0;        // Writes that found a newer version and re-applied their edits.
    uint64_t connect_attempts = 0; // Connections tried (the first included), failed or not.
    uint64_t caught_up = 0;        // Changes found by a catch-up after missed notifications.
    uint64_t resyncs = 0;          // Catch-ups that could not name the changes: re-check everything.
    size_t pending_edits = 0;      // Edits queued in memory, not yet committed.
    std::string last_error;        // The last connection or write error, one line ("" if none).
    // A shared world's change listener is down (its server away, its LISTEN refused): other
    // processes' changes reach this one only once it is back and has caught up. False otherwise.
    bool listener_down = false;
};

class ChunkStore {
public:
    using Clock = std::chrono::steady_clock;

    virtual ~ChunkStore() = default;

    // Loads chunk `c`. An error result means the store itself failed (I/O error, database
    // damaged beyond one record): the caller must not overwrite that chunk in the meantime.
    virtual Result<ChunkLoad> load(ChunkCoord c) = 0;

    // Queues a batch of edits (encoded during the call; later edits of a coordinate win).
    virtual Status save(std::span<const ChunkWrite> batch) = 0;
    Status save(ChunkCoord c, const Chunk& chunk) {
        const ChunkWrite w{c, &chunk};
        return save(std::span<const ChunkWrite>(&w, 1));
    }
    Status erase(ChunkCoord c) {
        const ChunkWrite w{c, nullptr};
        return save(std::span<const ChunkWrite>(&w, 1));
    }

    // Commits queued edits if the oldest is older than the store's bound. `now` is the caller's
    // steady-clock time (call it every frame or so from the I/O lane).
    virtual Status tick(Clock::time_point now) = 0;
    // Commits every queued edit and makes it durable before returning success.
    virtual Status flush() = 0;

    // Whether chunk `c` is stored (queued edits included; a corrupt record counts as stored).
    virtual Result<bool> contains(ChunkCoord c) = 0;
    // Stored chunks. May commit queued edits first.
    virtual Result<uint64_t> count() = 0;
    // Calls `fn` for every stored chunk coordinate, in no particular order, until it returns false.
    // May commit queued edits first. `fn` must not call back into the store.
    virtual Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) = 0;
    Result<std::vector<ChunkCoord>> list_coords() {
        std::vector<ChunkCoord> out;
        Status s = for_each_coord([&](ChunkCoord c) {
            out.push_back(c);
            return true;
        });
        if (!s)
            return Error{s.error()};
        return out;
    }

    // Metadata strings (e.g. "seed", "registry"): values are opaque bytes. Queued like chunks.
    virtual Result<std::optional<std::string>> get_meta(std::string_view key) = 0;
    virtual Status set_meta(std::string_view key, std::string_view value) = 0;

    // Coarse levels (levels 1..kMaxLodLevel; level 0 is load/save above). A store that keeps them
    // (supports_lod()) queues them like chunks, in the same transactions. The defaults are a store
    // that keeps none: load_lod finds every coarse chunk absent (the caller derives it from the
    // levels below or the generator), save_lod fails (the data would be lost), mark_lod_dirty
    // succeeds with nothing to do (nothing stored can be stale) and list_lod_dirty is empty.
    virtual bool supports_lod() const { return false; }
    // Loads coarse chunk `c`; as load() (a record of another level or place reads as Corrupt).
    virtual Result<ChunkLoad> load_lod(LodCoord c) {
        (void)c;
        return ChunkLoad{};
    }
    // Queues a batch of coarse chunks (encoded during the call; later writes of a coordinate win).
    // Saving a coarse chunk also clears its dirty mark, in the same transaction.
    virtual Status save_lod(std::span<const LodWrite> batch) {
        (void)batch;
        return Error{"this store keeps no coarse levels"};
    }
    Status save_lod(LodCoord c, const Chunk& chunk) {
        const LodWrite w{c, &chunk};
        return save_lod(std::span<const LodWrite>(&w, 1));
    }
    // Queues durable dirty marks on coarse chunks made stale by level-0 edits. Pass them with (just
    // before or after) the save() of those edits: queued edits commit in one transaction, so after
    // a crash a reopened world finds either neither or both, and re-derives the marked chunks.
    virtual Status mark_lod_dirty(std::span<const LodCoord> coords) {
        (void)coords;
        return {};
    }
    // Coarse chunks marked dirty and not saved since (queued marks and saves included). May
    // commit queued edits first.
    virtual Result<std::vector<LodCoord>> list_lod_dirty() { return std::vector<LodCoord>{}; }
    // Stored coarse chunks, in no particular order. May commit queued edits first.
    virtual Result<std::vector<LodCoord>> list_lod_coords() { return std::vector<LodCoord>{}; }

    virtual bool read_only() const = 0;
    // Queued edits (chunks and metadata) not yet committed. Same thread as the calls above.
    virtual size_t pending_edits() const { return 0; }

    // Chunks that other processes changed since the last call (shared stores: the engine reloads
    // and remeshes those it holds), appended to `out`. True when changes may have been missed
    // beyond `out` (more piled up than the store keeps, or notifications were lost and the store
    // cannot tell which chunks moved on): the caller re-checks every chunk it holds. Thread-safe,
    // cheap, never blocks: callable from any thread.
    virtual bool poll_changes(std::vector<ChunkCoord>& out) {
        (void)out;
        return false;
    }
    // The same for coarse chunks other processes saved (PgStore; a hint only: coarse chunks are
    // derived, and the level-0 changes above are what a process re-derives them from). Thread-safe.
    virtual void poll_lod_changes(std::vector<LodCoord>& out) { (void)out; }
    // Connection state and counters. Thread-safe.
    virtual StoreHealth health() const { return {}; }
};

} // namespace vx::world
