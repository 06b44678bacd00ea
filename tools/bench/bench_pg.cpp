// Benchmarks of the PostgreSQL chunk store (`vx bench pg`): chunk writes per second with one
// connection and with several, point reads per second, each beside a plain-SQL baseline of the
// same records, and commit-to-visible latency between two stores (each with its own connections,
// as two processes would have).
//
// Needs a server: VX_BENCH_PG_URI names an empty database or a vx world to use (its vx_chunks are
// overwritten under x >= 1,000,000; the plain baselines use a schema vx_bench of their own, dropped
// after each run); `bash scripts/pg_cluster.sh start DIR` starts a throwaway one and prints the
// URI. Without it the suite reports an error and runs nothing.
//
// Data: 256 non-uniform terrain chunks of seed 1 (the surface band: about 1.5 KB per record).
// Writers update the same 64 chunks per thread every batch (the streamer's common case: saving
// chunks that exist), so a rerun on the same database meets no version conflicts.

#include <algorithm>
#include <atomic>
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

std::unique_ptr<PgStore> open_bench_store(benchmark::State& state, bool listen = false, unsigned encode_threads = 0) {
    const char* uri = std::getenv("VX_BENCH_PG_URI");
    if (!uri || !*uri) {
        state.SkipWithError("set VX_BENCH_PG_URI (bash scripts/pg_cluster.sh start DIR prints one)");
        return nullptr;
    }
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = listen;
    info.encode_threads = encode_threads;
    info.max_pending_age = std::chrono::hours(1); // Commits only when the benchmark flushes.
    auto store = PgStore::open(info);
    if (!store) {
        state.SkipWithError(store.error().c_str());
        return nullptr;
    }
    return std::move(*store);
}

// Each writing thread updates the same 64 chunks every iteration (the streamer's common case:
// saving chunks that exist), with contents rotating through 4 variants so every write changes
// the row. A first, untimed batch creates the rows (or, on a database that already ran the
// suite, takes their versions).
constexpr int kVariants = 4;

ChunkCoord write_coord(int bench, int thread, int k) { return {kBaseX + 10 * bench + thread, 0, k}; }

const Chunk& write_chunk(int variant, int k) {
    const std::vector<Chunk>& chunks = sample_chunks();
    return chunks[size_t(k + kBatch * variant) % chunks.size()];
}

// Records of every (variant, k) for one thread's coordinates, encoded before timing.
std::vector<std::vector<uint8_t>> write_records(int bench, int thread) {
    RecordCodec codec;
    std::vector<std::vector<uint8_t>> out(size_t(kVariants * kBatch));
    for (int v = 0; v < kVariants; ++v)
        for (int k = 0; k < kBatch; ++k)
            codec.encode(write_coord(bench, thread, k), write_chunk(v, k), out[size_t(v * kBatch + k)]);
    return out;
}

// Writes batches of 64 chunks, one durable commit each, the chunks encoded (zstd) in save() on
// `encode_threads` threads (0: all cores; 1: the calling thread alone, as before
// RecordBatchEncoder); `encoded`: records encoded beforehand (ChunkWrite::record), the store's own
// path to the server (the engine encodes on its workers). One connection per benchmark thread.
void write_batches(benchmark::State& state, bool encoded, unsigned encode_threads = 0) {
    auto store = open_bench_store(state, false, encode_threads);
    if (!store)
        return;
    const int bench = encoded ? 1 : encode_threads == 1 ? 3 : 2, thread = state.thread_index();
    const std::vector<std::vector<uint8_t>> records = write_records(bench, thread);
    std::vector<ChunkWrite> batch(kBatch);
    auto fill = [&](int v) {
        for (int k = 0; k < kBatch; ++k) {
            batch[size_t(k)] = {write_coord(bench, thread, k), &write_chunk(v, k)};
            if (encoded)
                batch[size_t(k)].record = records[size_t(v * kBatch + k)];
        }
    };
    fill(kVariants - 1);
    if (!store->save(batch) || !store->flush()) {
        state.SkipWithError("setup write failed");
        return;
    }
    int v = 0;
    for (auto _ : state) {
        fill(v);
        v = (v + 1) % kVariants;
        if (!store->save(batch) || !store->flush()) {
            state.SkipWithError("write failed");
            return;
        }
    }
    state.SetItemsProcessed(state.iterations() * kBatch);
    state.counters["record_bytes"] = benchmark::Counter(double(records[0].size()), benchmark::Counter::kAvgThreads);
}

void bench_write(benchmark::State& state) { write_batches(state, false); }
void bench_write_one_encoder(benchmark::State& state) { write_batches(state, false, 1); }
void bench_write_encoded(benchmark::State& state) { write_batches(state, true); }

// The baselines live in a schema of their own (vx_bench), created and dropped around each run:
// a PgStore refuses a database whose schema holds tables other than a vx world's, so the whole
// suite runs on one empty database.
PGconn* open_baseline(benchmark::State& state, const char* table) {
    const char* uri = std::getenv("VX_BENCH_PG_URI");
    if (!uri || !*uri) {
        state.SkipWithError("set VX_BENCH_PG_URI (bash scripts/pg_cluster.sh start DIR prints one)");
        return nullptr;
    }
    PGconn* conn = PQconnectdb(uri);
    PQsetNoticeProcessor(conn, [](void*, const char*) {}, nullptr); // "already exists, skipping"
    // Benchmark threads start together: the advisory lock orders their CREATE ... IF NOT EXISTS.
    const std::string sql = std::string("BEGIN; SELECT pg_advisory_xact_lock(7942519737); "
                                        "CREATE SCHEMA IF NOT EXISTS vx_bench; CREATE TABLE IF NOT EXISTS vx_bench.") +
                            table + "(x int4, y int4, z int4, data bytea, PRIMARY KEY (x, y, z)); COMMIT";
    PGresult* r = PQexec(conn, sql.c_str());
    const bool ok = PQstatus(conn) == CONNECTION_OK && PQresultStatus(r) == PGRES_COMMAND_OK;
    PQclear(r);
    if (!ok) {
        state.SkipWithError(PQerrorMessage(conn));
        PQfinish(conn);
        return nullptr;
    }
    return conn;
}

// After the timed loop (every thread has left it): the first thread drops the baseline schema.
void close_baseline(benchmark::State& state, PGconn* conn) {
    if (state.thread_index() == 0)
        PQclear(PQexec(conn, "DROP SCHEMA IF EXISTS vx_bench CASCADE"));
    PQfinish(conn);
}

bool prepare_plain(PGconn* conn, const char* name, const char* sql) {
    PGresult* r = PQprepare(conn, name, sql, 0, nullptr);
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
    PQclear(r);
    return ok;
}

// One upsert round trip of a pre-encoded record ("plain_put", text coordinates as a plain client
// would send them).
void plain_put(PGconn* conn, ChunkCoord c, const std::vector<uint8_t>& rec) {
    const std::string xs = std::to_string(c.x), ys = std::to_string(c.y), zs = std::to_string(c.z);
    const char* values[] = {xs.c_str(), ys.c_str(), zs.c_str(), reinterpret_cast<const char*>(rec.data())};
    const int lengths[] = {0, 0, 0, int(rec.size())}, formats[] = {0, 0, 0, 1};
    PQclear(PQexecPrepared(conn, "plain_put", 4, values, lengths, formats, 0));
}

// One transaction: BEGIN, `n` upserts (coordinate and record of index i from `at`), COMMIT.
template <class At> bool plain_transaction(PGconn* conn, int n, At at) {
    PQclear(PQexec(conn, "BEGIN"));
    for (int i = 0; i < n; ++i) {
        const auto [c, rec] = at(i);
        plain_put(conn, c, *rec);
    }
    PGresult* r = PQexec(conn, "COMMIT");
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
    PQclear(r);
    return ok;
}

// The write baseline, side by side: plain 64-row transactions (BEGIN, one INSERT ... ON CONFLICT
// round trip per row, COMMIT) of the same encoded records at the same kind of coordinates (the
// same 64 rows updated per thread) into a table of the same shape, as a straightforward client
// would write them.
void bench_write_plain(benchmark::State& state) {
    PGconn* conn = open_baseline(state, "plain_write");
    if (!conn)
        return;
    if (!prepare_plain(conn, "plain_put",
                       "INSERT INTO vx_bench.plain_write VALUES ($1::int4, $2::int4, $3::int4, $4) "
                       "ON CONFLICT (x, y, z) DO UPDATE SET data = EXCLUDED.data")) {
        state.SkipWithError(PQerrorMessage(conn));
        close_baseline(state, conn);
        return;
    }
    const int bench = 0, thread = state.thread_index();
    const std::vector<std::vector<uint8_t>> records = write_records(bench, thread);
    int v = kVariants - 1;
    auto at = [&](int k) { return std::pair(write_coord(bench, thread, k), &records[size_t(v * kBatch + k)]); };
    bool ok = plain_transaction(conn, kBatch, at); // Creates the rows, as the stores' first batch.
    for (auto _ : state) {
        v = (v + 1) % kVariants;
        if (!ok || !(ok = plain_transaction(conn, kBatch, at))) {
            state.SkipWithError("commit failed");
            break;
        }
    }
    state.SetItemsProcessed(state.iterations() * kBatch);
    close_baseline(state, conn);
}

// The read baseline: point SELECTs of the same records by primary key, prepared, binary results,
// nothing decoded (what the database and libpq cost alone).
void bench_read_plain(benchmark::State& state) {
    PGconn* conn = open_baseline(state, "plain_read");
    if (!conn)
        return;
    const bool prepared =
        prepare_plain(conn, "plain_put",
                      "INSERT INTO vx_bench.plain_read VALUES ($1::int4, $2::int4, $3::int4, $4) "
                      "ON CONFLICT (x, y, z) DO UPDATE SET data = EXCLUDED.data") &&
        prepare_plain(conn, "plain_get", "SELECT data FROM vx_bench.plain_read WHERE x = $1 AND y = $2 AND z = $3");
    // The records bench_read stores (what they are does not matter to the database).
    const int32_t y = state.thread_index();
    const std::vector<std::vector<uint8_t>> records = write_records(0, state.thread_index());
    bool stored = prepared;
    for (int32_t z0 = 0; stored && z0 < 2048; z0 += kBatch)
        stored = plain_transaction(conn, kBatch, [&](int i) {
            return std::pair(ChunkCoord(0, y, z0 + i), &records[size_t(z0 + i) % records.size()]);
        });
    if (!stored) {
        state.SkipWithError("setup failed");
        close_baseline(state, conn);
        return;
    }
    uint32_t h = 12345u + uint32_t(state.thread_index());
    uint32_t be[3] = {0, __builtin_bswap32(uint32_t(y)), 0};
    const char* values[] = {reinterpret_cast<const char*>(&be[0]), reinterpret_cast<const char*>(&be[1]),
                            reinterpret_cast<const char*>(&be[2])};
    const int lengths[] = {4, 4, 4}, formats[] = {1, 1, 1};
    for (auto _ : state) {
        h = h * 1664525u + 1013904223u;
        be[2] = __builtin_bswap32(h >> 21);
        PGresult* r = PQexecPrepared(conn, "plain_get", 3, values, lengths, formats, 1);
        const bool ok = PQresultStatus(r) == PGRES_TUPLES_OK && PQntuples(r) == 1;
        benchmark::DoNotOptimize(PQgetvalue(r, 0, 0));
        PQclear(r);
        if (!ok) {
            state.SkipWithError("read failed");
            break;
        }
    }
    state.SetItemsProcessed(state.iterations());
    close_baseline(state, conn);
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
    // One chunk, rewritten each iteration (a first, untimed write takes its version).
    const ChunkCoord c(kBaseX + 100, 0, 0);
    if (!writer->save(c, sample_chunks()[0]) || !writer->flush()) {
        state.SkipWithError("setup write failed");
        return;
    }
    std::vector<ChunkCoord> seen;
    int variant = 0;
    for (auto _ : state) {
        const Chunk& chunk = sample_chunks()[size_t(++variant % 2)];
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
BENCHMARK(bench_write_one_encoder)->Name("pg/write_one_encoder_thread")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_write)->Name("pg/write")->ThreadRange(1, 4)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_read_plain)->Name("pg/read_plain_baseline")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_read)->Name("pg/read")->ThreadRange(1, 2)->UseRealTime()->MinTime(2.0);
BENCHMARK(bench_visibility)->Name("pg/commit_to_visible")->UseManualTime()->Iterations(200)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace vx::world
