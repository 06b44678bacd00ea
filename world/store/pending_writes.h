#pragma once
// The edits a store queues between commits (chunk_store.h's write model), shared by SqliteStore
// and PgStore for level 0 and the coarse levels: PendingWrites, one record write per coordinate
// (ChunkCoord or LodCoord) with the bytes the queue holds, and StoreQueue, everything one store
// queues. A save batch queues its writes (an erase, a record the caller encoded, or a chunk to
// encode), then encodes the chunks together on RecordBatchEncoder's threads.
// Thread affinity: not thread-safe; the owning store's I/O lane thread only.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "world/store/chunk_store.h"
#include "world/store/record_batch_encoder.h"

namespace vx::world {

// The record of one queued write; nullopt: an erase.
struct PendingRecord {
    std::optional<std::vector<uint8_t>> record;
};

// A coordinate of any level as the codec takes it (level 0: the blocks).
inline LodCoord lod_key(ChunkCoord c) { return LodCoord{0, c}; }
inline LodCoord lod_key(LodCoord c) { return c; }

// How messages name the record of `c`: "chunk x,y,z" (level 0) or "level L chunk x,y,z".
inline std::string record_name(LodCoord c) {
    std::string xyz = std::to_string(c.chunk.x) + "," + std::to_string(c.chunk.y) + "," + std::to_string(c.chunk.z);
    return c.level == 0 ? "chunk " + xyz : "level " + std::to_string(c.level) + " chunk " + xyz;
}

// load() of a queued write of `c`: Present, or Absent for an erase. A queued record is the
// store's own encoder's output, so decoding it cannot fail short of a bug.
inline ChunkLoad load_queued(const std::optional<std::vector<uint8_t>>& record, LodCoord c, RecordCodec& codec) {
    ChunkLoad out;
    if (!record)
        return out; // Erase queued.
    Result<Chunk> chunk = codec.decode_lod(*record, c);
    VX_ASSERT_MSG(chunk.ok(), "a queued record failed to decode");
    out.state = LoadState::Present;
    out.chunk = std::move(*chunk);
    return out;
}

// load() of stored bytes `record` of `c`: Present, or Corrupt with the problem (the caller moves
// the record aside).
inline ChunkLoad load_stored(std::span<const uint8_t> record, LodCoord c, RecordCodec& codec) {
    ChunkLoad out;
    Result<Chunk> chunk = codec.decode_lod(record, c);
    if (chunk) {
        out.state = LoadState::Present;
        out.chunk = std::move(*chunk);
        return out;
    }
    out.state = LoadState::Corrupt;
    out.problem = chunk.error();
    return out;
}

// An error when `c` is not of a coarse level (1..kMaxLodLevel).
inline Status check_coarse(LodCoord c) {
    if (valid_lod_level(c.level) && c.level > 0)
        return {};
    return Error{"coarse level " + std::to_string(c.level) + " out of range 1.." + std::to_string(kMaxLodLevel)};
}
// The same for every coordinate of a batch, checked before anything is queued (a batch is taken
// whole or not at all).
inline Status check_coarse(std::span<const LodWrite> batch) {
    for (const LodWrite& w : batch)
        if (Status s = check_coarse(w.coord); !s)
            return s;
    return {};
}
inline Status check_coarse(std::span<const LodCoord> coords) {
    for (LodCoord c : coords)
        if (Status s = check_coarse(c); !s)
            return s;
    return {};
}

// Entry: PendingRecord, or a type with the same `record` member (PgStore adds block edits).
template <class Coord, class Hash, class Entry = PendingRecord>
class PendingWrites {
public:
    using Map = std::unordered_map<Coord, Entry, Hash>;

    // Queues a write of `c` (a later write of `c` wins): an erase when `chunk` is null, else
    // `record` as is when not empty, else `*chunk`, added to `encodes` (call encode() after the
    // batch). Returns the entry (valid until clear()) for the caller's own fields.
    Entry& write(Coord c, const Chunk* chunk, std::span<const uint8_t> record, RecordBatchEncoder::Batch& encodes) {
        Entry& e = m_map[c];
        if (e.record)
            m_bytes -= e.record->size();
        encodes.supersede(c);
        if (!chunk) {
            e.record.reset();
            return e;
        }
        if (!e.record)
            e.record.emplace();
        if (record.empty()) {
            e.record->clear();
            encodes.add(c, *chunk, *e.record);
        } else {
            e.record->assign(record.begin(), record.end());
            m_bytes += e.record->size();
        }
        return e;
    }

    // Encodes the chunks `encodes` gathered (the caller's share through `codec`) and counts them.
    void encode(RecordBatchEncoder::Batch& encodes, RecordBatchEncoder& encoder, RecordCodec& codec) {
        const std::span<const RecordBatchEncoder::Job> jobs = encodes.jobs();
        encoder.encode(jobs, codec);
        for (const RecordBatchEncoder::Job& j : jobs)
            m_bytes += j.out->size();
    }

    // Replaces the record of `e`, the queued write of `c` (not an erase), by that of `chunk`.
    void reencode(Coord c, Entry& e, const Chunk& chunk, RecordCodec& codec) {
        m_bytes -= e.record->size();
        codec.encode_lod(lod_key(c), chunk, *e.record);
        m_bytes += e.record->size();
    }

    // The queued record of `c`: null when nothing is queued there (nullopt: an erase).
    const std::optional<std::vector<uint8_t>>* find(Coord c) const {
        const auto it = m_map.find(c);
        return it == m_map.end() ? nullptr : &it->second.record;
    }
    Entry& operator[](Coord c) { return m_map[c]; }
    bool contains(Coord c) const { return m_map.count(c) != 0; }
    // Drops the queued write of `c` (if any).
    void erase(Coord c) {
        if (const auto it = m_map.find(c); it != m_map.end()) {
            if (it->second.record)
                m_bytes -= it->second.record->size();
            m_map.erase(it);
        }
    }
    typename Map::const_iterator begin() const { return m_map.begin(); }
    typename Map::const_iterator end() const { return m_map.end(); }
    size_t size() const { return m_map.size(); }
    bool empty() const { return m_map.empty(); }
    size_t bytes() const { return m_bytes; } // Record bytes queued.
    void clear() {
        m_map.clear();
        m_bytes = 0;
    }

private:
    Map m_map;
    size_t m_bytes = 0;
};

// Why `key` cannot name metadata ("" if it can): keys are text in every store (PostgreSQL's
// vx_meta.key is UTF-8 text, which refuses NUL and invalid UTF-8 only when a commit sends it, and
// then refuses the whole commit), so both stores refuse such keys when they are set.
inline std::string meta_key_problem(std::string_view key) {
    if (key.empty())
        return "empty";
    // UTF-8 as PostgreSQL checks it (RFC 3629): no overlong forms, no surrogates, at most U+10FFFF.
    for (size_t i = 0; i < key.size();) {
        const auto b = uint8_t(key[i]);
        if (b == 0)
            return "it holds a NUL byte";
        const size_t n = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
        bool valid = n != 0 && i + n <= key.size() && !(n == 2 && b < 0xC2);
        for (size_t k = 1; valid && k < n; ++k)
            valid = (uint8_t(key[i + k]) & 0xC0) == 0x80;
        if (valid && n >= 3) {
            const auto b1 = uint8_t(key[i + 1]);
            valid = n == 3 ? !(b == 0xE0 && b1 < 0xA0) && !(b == 0xED && b1 >= 0xA0)
                           : !(b == 0xF0 && b1 < 0x90) && !(b == 0xF4 && b1 >= 0x90) && b <= 0xF4;
        }
        if (!valid)
            return "not valid UTF-8 at byte " + std::to_string(i);
        i += n;
    }
    return {};
}

// Everything one store queues between commits. ChunkEntry: as PendingWrites' Entry.
template <class ChunkEntry = PendingRecord>
struct StoreQueue {
    PendingWrites<ChunkCoord, ChunkCoordHash, ChunkEntry> chunks;
    PendingWrites<LodCoord, LodCoordHash> lods;
    std::unordered_map<LodCoord, bool, LodCoordHash> dirty; // true: mark, false: clear.
    std::map<std::string, std::string, std::less<>> meta;
    std::optional<ChunkStore::Clock::time_point> since; // Time of the oldest queued edit.

    // Queued edits (chunks, coarse chunks, dirty marks and metadata).
    size_t edits() const { return chunks.size() + meta.size() + lods.size() + dirty.size(); }
    size_t bytes() const { return chunks.bytes() + lods.bytes(); }
    // Call before queuing `n` edits: the first edit of an empty queue starts its age.
    void start(size_t n) {
        if (edits() == 0 && n > 0)
            since = ChunkStore::Clock::now();
    }
    // save_lod(): queues and encodes the batch (a saved coarse chunk is no longer stale), or queues
    // nothing when a coordinate is not of a coarse level.
    Status save_lods(std::span<const LodWrite> batch, RecordBatchEncoder& encoder, RecordCodec& codec) {
        if (Status s = check_coarse(batch); !s)
            return s;
        start(batch.size());
        RecordBatchEncoder::Batch encodes;
        for (const LodWrite& w : batch) {
            dirty.insert_or_assign(w.coord, false);
            lods.write(w.coord, w.chunk, w.record, encodes);
        }
        lods.encode(encodes, encoder, codec);
        return {};
    }
    // mark_lod_dirty(), or nothing when a coordinate is not of a coarse level.
    Status mark_dirty(std::span<const LodCoord> coords) {
        if (Status s = check_coarse(coords); !s)
            return s;
        start(coords.size());
        for (LodCoord c : coords)
            dirty.insert_or_assign(c, true);
        return {};
    }
    // set_meta(): queues the value (opaque bytes), or nothing when the key is not valid text.
    Status set_meta(std::string_view key, std::string_view value) {
        if (const std::string why = meta_key_problem(key); !why.empty())
            return Error{"metadata key refused: " + why};
        start(1);
        meta.insert_or_assign(std::string(key), std::string(value));
        return {};
    }
    void clear() {
        chunks.clear();
        lods.clear();
        dirty.clear();
        meta.clear();
        since.reset();
    }
};

} // namespace vx::world
