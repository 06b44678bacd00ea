// Benchmarks of the PostgreSQL chunk store (`vx bench pg`): chunk writes per second with one
// connection and with several, point reads per second, and commit-to-visible latency between two
// stores (each with its own connections, as two processes would have).
//
// Needs a server: VX_BENCH_PG_URI names an empty database or a vx world to use (its vx_chunks are
// overwritten under x >= 1,000,000); `bash scripts/pg_cluster.sh start DIR` starts a throwaway one
// and prints the URI. Without it the suite reports an error and runs nothing.
//
// Data: 256 non-uniform terrain chunks of seed 1 (the surface band: about 1.8 KB per record),
// written at ever new coordinates so every write inserts (the streamer's common case is an
// update, which costs the same here: one row lock, one index entry).

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <libpq-fe.h>

#include "world/gen/terrain.h"
#include "world/store/chunk_record.h"
#include "world/store/pg_store.h"

namespace vx::world {
namespace {

constexpr int kBatch = 64; // Chunks per commit, as the streamer's save batches.
constexpr int32_t kBaseX = 1000000;

const std::vector<Chunk>& sample_chunks() {
    static const std::vector<Chunk> chunks = [] {
        const TerrainGenerator gen(1);
        std::vector<Chunk> out;
        for (int32_t x = 0; out.size() < 256; ++x)
            for (int32_t z = 0; z < 16 && out.size() < 256; ++z) {
                const int32_t y = int32_t(gen.surface_height(int64_t(x) * 32 + 16, int64_t(z) * 32 + 16) >> 5);
                Chunk c = gen.generate({x, y, z});
                if (!c.is_uniform())
                    out.push_back(std::move(c));
            }
        return out;
    }();
    return chunks;
}

std::unique_ptr<PgStore> open_bench_store(benchmark::State& state, bool listen = false) {
    const char* uri = std::getenv("VX_BENCH_PG_URI");
    if (!uri || !*uri) {
        state.SkipWithError("set VX_BENCH_PG_URI (bash scripts/pg_cluster.sh start DIR prints one)");
        return nullptr;
    }
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = listen;
    info.max_pending_age = std::chrono::hours(1); // Commits only when the benchmark flushes.
    auto store = PgStore::open(info);
    if (!store) {
        state.SkipWithError(store.error().c_str());
        return nullptr;
    }
    return std::move(*store);
}

// Writes batches of 64 chunks, one durable commit each; one connection per benchmark thread.
void bench_write(benchmark::State& state) {
    auto store = open_bench_store(state);
    if (!store)
        return;
    const std::vector<Chunk>& chunks = sample_chunks();
    // Fresh coordinates per run and thread: x = base + thread, z counts up.
    static std::atomic<int32_t> run{0};
    const int32_t y = 1000 + run.fetch_add(1) * 64 + state.thread_index();
    int32_t z = 0;
    std::vector<ChunkWrite> batch(kBatch);
    for (auto _ : state) {
        for (int i = 0; i < kBatch; ++i, ++z)
            batch[size_t(i)] = {ChunkCoord(kBaseX + state.thread_index(), y, z), &chunks[size_t(z) % chunks.size()]};
        if (!store->save(batch) || !store->flush()) {
            state.SkipWithError("write failed");
            return;
        }
    }
    state.SetItemsProcessed(state.iterations() * kBatch);
    state.counters["record_bytes"] =
        benchmark::Counter(double(encode_chunk_record({0, 0, 0}, chunks[0]).size()), benchmark::Counter::kAvgThreads);
}

const std::vector<std::vector<uint8_t>>& sample_records() {
    static const std::vector<std::vector<uint8_t>> records = [] {
        std::vector<std::vector<uint8_t>> out;
        for (size_t i = 0; i < sample_chunks().size(); ++i)
            out.push_back(encode_chunk_record({kBaseX + 200, 0, int32_t(i)}, sample_chunks()[i]));
        return out;
    }();
    return records;
}

// As bench_write, with records encoded beforehand (ChunkWrite::record): the store's own path to
// the server, without zstd on the calling thread (the engine can encode on its workers).
void bench_write_encoded(benchmark::State& state) {
    auto store = open_bench_store(state);
    if (!store)
        return;
    const std::vector<Chunk>& chunks = sample_chunks();
    const auto& records = sample_records();
    static std::atomic<int32_t> run{0};
    const int32_t y = 5000 + run.fetch_add(1) * 64 + state.thread_index();
    int32_t z = 0;
    std::vector<ChunkWrite> batch(kBatch);
    for (auto _ : state) {
        for (int i = 0; i < kBatch; ++i, ++z) {
            const size_t k = size_t(z) % chunks.size();
            batch[size_t(i)] = {ChunkCoord(kBaseX + 200, y, z), &chunks[k], {}, records[k]};
        }
        if (!store->save(batch) || !store->flush()) {
            state.SkipWithError("write failed");
            return;
        }
    }
    state.SetItemsProcessed(state.iterations() * kBatch);
}

// The baseline, side by side: plain 64-row transactions (BEGIN, one INSERT ... ON CONFLICT round
// trip per row, COMMIT) of the same encoded records into a table of the same shape, as a
// straightforward client would write them.
void bench_write_plain(benchmark::State& state) {
    const char* uri = std::getenv("VX_BENCH_PG_URI");
    if (!uri || !*uri) {
        state.SkipWithError("set VX_BENCH_PG_URI");
        return;
    }
    PGconn* conn = PQconnectdb(uri);
    PQclear(PQexec(conn, "CREATE TABLE IF NOT EXISTS bench_plain(x int4, y int4, z int4, data bytea, "
                         "PRIMARY KEY (x, y, z))"));
    PGresult* prep = PQprepare(conn, "plain_put",
                               "INSERT INTO bench_plain VALUES ($1::int4, $2::int4, $3::int4, $4) "
                               "ON CONFLICT (x, y, z) DO UPDATE SET data = EXCLUDED.data",
                               0, nullptr);
    const bool prepared = PQresultStatus(prep) == PGRES_COMMAND_OK;
    PQclear(prep);
    if (PQstatus(conn) != CONNECTION_OK || !prepared) {
        state.SkipWithError(PQerrorMessage(conn));
        PQfinish(conn);
        return;
    }
    const auto& records = sample_records();
    static std::atomic<int32_t> run{0};
    const std::string x = std::to_string(run.fetch_add(1)), y = std::to_string(state.thread_index());
    int32_t z = 0;
    for (auto _ : state) {
        PQclear(PQexec(conn, "BEGIN"));
        for (int i = 0; i < kBatch; ++i, ++z) {
            const std::string zs = std::to_string(z);
            const auto& rec = records[size_t(z) % records.size()];
            const char* values[] = {x.c_str(), y.c_str(), zs.c_str(), reinterpret_cast<const char*>(rec.data())};
            const int lengths[] = {0, 0, 0, int(rec.size())}, formats[] = {0, 0, 0, 1};
            PQclear(PQexecPrepared(conn, "plain_put", 4, values, lengths, formats, 0));
        }
        PGresult* r = PQexec(conn, "COMMIT");
        const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
        PQclear(r);
        if (!ok) {
            state.SkipWithError("commit failed");
            break;
        }
    }
    state.SetItemsProcessed(state.iterations() * kBatch);
    PQfinish(conn);
}

// Point reads of stored chunks in random order, one connection per thread.
void bench_read(benchmark::State& state) {
    auto store = open_bench_store(state);
    if (!store)
        return;
    const std::vector<Chunk>& chunks = sample_chunks();
    const int32_t y = -1000 - state.thread_index();
    std::vector<ChunkWrite> batch; // Every thread reads its own 2048 chunks.
    for (int32_t z = 0; z < 2048; ++z)
        batch.push_back({ChunkCoord(kBaseX, y, z), &chunks[size_t(z) % chunks.size()]});
    if (!store->save(batch) || !store->flush()) {
        state.SkipWithError("setup failed");
        return;
    }
    uint32_t h = 12345u + uint32_t(state.thread_index());
    for (auto _ : state) {
        h = h * 1664525u + 1013904223u;
        auto r = store->load(ChunkCoord(kBaseX, y, int32_t(h >> 21)));
        if (!r || r->state != LoadState::Present) {
            state.SkipWithError("read failed");
            return;
        }
        benchmark::DoNotOptimize(r);
    }
    state.SetItemsProcessed(state.iterations());
}

// One writer commits a chunk; the time until a second store (its own listener connection) has
// it in poll_changes. Reported as the iteration time.
void bench_visibility(benchmark::State& state) {
    auto writer = open_bench_store(state), reader = open_bench_store(state, true);
    if (!writer || !reader)
        return;
    std::this_thread::sleep_for(std::chrono::milliseconds(300)); // The listener connects.
    const Chunk& chunk = sample_chunks()[0];
    std::vector<ChunkCoord> seen;
    int32_t z = 0;
    for (auto _ : state) {
        const ChunkCoord c(kBaseX + 100, 0, z++);
        const auto start = std::chrono::steady_clock::now();
        if (!writer->save(c, chunk) || !writer->flush()) {
            state.SkipWithError("write failed");
            return;
        }
        for (;;) {
            reader->poll_changes(seen);
            if (std::find(seen.begin(), seen.end(), c) != seen.end())
                break;
            if (std::chrono::steady_clock::now() - start > std::chrono::seconds(5)) {
                state.SkipWithError("no notification within 5 s");
                return;
            }
            std::this_thread::yield();
        }
        seen.clear();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
}

BENCHMARK(bench_write_plain)->Name("pg/write_plain_baseline")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_write_encoded)->Name("pg/write_encoded")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_write)->Name("pg/write")->ThreadRange(1, 4)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_read)->Name("pg/read")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_visibility)->Name("pg/commit_to_visible")->UseManualTime()->Iterations(200)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace vx::world
