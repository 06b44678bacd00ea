#pragma once
// RecordBatchEncoder: encodes a batch of chunk records (chunk_record.h) on several threads, so a
// store's save() of chunks its caller did not encode (vx world gen's writers, tools, benchmarks;
// the engine encodes on its own workers and passes ChunkWrite::record) is not bound by one core's
// zstd while the commit that follows waits on the disk. A durable commit of 64 chunks waits
// 3.9 ms for PostgreSQL's WAL flush on this machine, and encoding them on one thread took another
// 3.5–4 ms (docs/benchmarks.md, "PostgreSQL store").
//
// Threads: `threads - 1` helpers, started on the first batch large enough to share and parked on
// a condition variable between batches; the calling thread encodes too, then waits for every
// helper to have left the batch (a late waker costs its wake-up latency, tens of µs). Every record is exactly
// what RecordCodec::encode writes on one thread (each thread has its own codec of the same level).
// Thread affinity: one owner thread calls encode() (a store's I/O lane); the helpers touch only
// the jobs of the batch in flight, which encode() waits for before it returns.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <unordered_map>
#include <vector>

#include "world/store/chunk_record.h"

namespace vx::world {

class RecordBatchEncoder {
public:
    // One record to write: `*out` = the record of `*chunk` at chunk coordinates `coord` of
    // level `level` (0: the blocks; coarse levels as world/lod/lod_coords.h).
    struct Job {
        ChunkCoord coord{0};
        const Chunk* chunk = nullptr;
        std::vector<uint8_t>* out = nullptr;
        int level = 0;
    };

    // zstd_level: as RecordCodec. threads: total threads encoding a batch, the caller included
    // (0: the machine's hardware threads, at most kMaxThreads; 1: the caller alone).
    RecordBatchEncoder(int zstd_level, unsigned threads);
    ~RecordBatchEncoder(); // Joins the helpers.
    RecordBatchEncoder(const RecordBatchEncoder&) = delete;
    RecordBatchEncoder& operator=(const RecordBatchEncoder&) = delete;

    // Encodes every job and returns when all are written; the caller's share goes through
    // `codec` (the store's own, of the same level). Each job's `out` must be distinct and its
    // chunk unchanged until the call returns. Batches smaller than kMinShared run on the caller
    // alone (waking helpers costs more than a few records).
    void encode(std::span<const Job> jobs, RecordCodec& codec);

    // Total threads a batch is shared among (the caller included).
    unsigned threads() const { return m_threads; }

    // The jobs of one save() batch, gathered in order: a coordinate's last write wins (an erase or
    // a pre-encoded record written after it drops its job). Caller's thread only.
    class Batch {
    public:
        // Called for every write of `c`, before add() when the write is to be encoded.
        void supersede(ChunkCoord c) { supersede(LodCoord{0, c}); }
        void add(ChunkCoord c, const Chunk& chunk, std::vector<uint8_t>& out) { add(LodCoord{0, c}, chunk, out); }
        // The same for chunks of any level (a batch may mix levels).
        void supersede(LodCoord c);
        void add(LodCoord c, const Chunk& chunk, std::vector<uint8_t>& out);
        // The jobs still wanted, in first-write order.
        std::span<const Job> jobs();

    private:
        std::vector<Job> m_jobs;
        std::unordered_map<LodCoord, size_t, LodCoordHash> m_index;
    };

    static constexpr unsigned kMaxThreads = 8;
    static constexpr size_t kMinShared = 8;

private:
    void start_helpers();
    void helper_main(unsigned index);
    // Takes jobs off the shared counter until none of `jobs` are left.
    void run_jobs(RecordCodec& codec, std::span<const Job> jobs);

    int m_level;
    unsigned m_threads;
    std::vector<std::thread> m_helpers;
    std::vector<std::unique_ptr<RecordCodec>> m_helper_codecs;

    std::mutex m_mutex;
    std::condition_variable m_wake; // Helpers wait for a new batch (or stop).
    std::condition_variable m_done; // The caller waits for helpers to leave the batch.
    uint64_t m_generation = 0;      // Batches handed out; m_mutex.
    size_t m_finished = 0;          // Helpers done with the current batch; m_mutex.
    bool m_stop = false;            // m_mutex.
    std::span<const Job> m_jobs;    // The batch in flight; written under m_mutex before a wake.
    std::atomic<size_t> m_next{0};  // Next job index to take.
};

} // namespace vx::world
