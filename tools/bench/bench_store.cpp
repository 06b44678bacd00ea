// Benchmarks of the chunk store: records (encode/decode) and SqliteStore (save with a commit per
// batch and the checkpoint; loads warm and cold from a file ten times the page cache),
// on terrain-like chunks. Registered with BENCHMARK(); the `vx bench store` command links this.
//
// Data: a 16 x 8 x 16 block of chunks (2048 chunks, 512 x 256 x 512 blocks) around a rolling
// heightmap (y 10..94): stone with ore specks and gravel pockets, 3 layers of dirt, grass or sand
// on top, water up to sea level, spherical caves. Chunks above the terrain are uniform air (the
// uniform_share counter reports how many); the rest hold 2-8 ids. 2048 chunks are enough that
// the load order defeats the page cache's locality, and small enough to set up in seconds.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

#include <benchmark/benchmark.h>

#include "world/store/chunk_record.h"
#include "world/store/sqlite_store.h"
#include "scratch_dir.h"

namespace vx::world {
namespace {

constexpr BlockId kStone = 1, kDirt = 2, kGrass = 3, kSand = 4, kWater = 5;
constexpr BlockId kGravel = 12, kOre = 13; // Not in the default registry: storage does not care.
constexpr int kSeaLevel = 40; // World y of the water surface.

// Smooth deterministic value noise in 2D (bilinear between hashed lattice values).
float lattice(int x, int z, uint32_t seed) {
    uint32_t h = uint32_t(x) * 374761393u + uint32_t(z) * 668265263u + seed * 2246822519u;
    h = (h ^ (h >> 13)) * 1274126177u;
    return float((h ^ (h >> 16)) & 0xFFFF) / 65535.f;
}
float value_noise(float x, float z, uint32_t seed) {
    const int x0 = int(std::floor(x)), z0 = int(std::floor(z));
    const float fx = x - float(x0), fz = z - float(z0);
    const float sx = fx * fx * (3 - 2 * fx), sz = fz * fz * (3 - 2 * fz);
    const float a = lattice(x0, z0, seed), b = lattice(x0 + 1, z0, seed);
    const float c = lattice(x0, z0 + 1, seed), d = lattice(x0 + 1, z0 + 1, seed);
    return (a + (b - a) * sx) + ((c + (d - c) * sx) - (a + (b - a) * sx)) * sz;
}

int height_at(int64_t x, int64_t z) {
    const float fx = float(x), fz = float(z);
    const float h = 64 * value_noise(fx / 128, fz / 128, 1) + 16 * value_noise(fx / 32, fz / 32, 2) +
                    4 * value_noise(fx / 8, fz / 8, 3);
    return 10 + int(h); // 10..94
}

struct Cave {
    float x, y, z, r;
};

// Caves: spheres of radius 4-12 below the surface, a few per 128-block column.
std::vector<Cave> make_caves(int chunks_x, int chunks_z) {
    std::mt19937 rng(7);
    std::vector<Cave> caves;
    const int n = chunks_x * chunks_z / 2;
    for (int i = 0; i < n; ++i) {
        const float x = float(rng() % uint32_t(chunks_x * kChunkSize));
        const float z = float(rng() % uint32_t(chunks_z * kChunkSize));
        const float y = float(height_at(int64_t(x), int64_t(z)) - 8 - int(rng() % 40));
        caves.push_back({x, y, z, 4 + float(rng() % 9)});
    }
    return caves;
}

Chunk terrain_chunk(ChunkCoord c, const std::vector<Cave>& caves) {
    std::vector<BlockId> ids(kChunkVolume, kAir);
    const BlockPos o = chunk_origin(c);
    for (int z = 0; z < kChunkSize; ++z)
        for (int x = 0; x < kChunkSize; ++x) {
            const int h = height_at(o.x + x, o.z + z);
            for (int y = 0; y < kChunkSize; ++y) {
                const int64_t wy = o.y + y;
                BlockId b = kAir;
                if (wy < h - 3)
                    b = kStone;
                else if (wy < h)
                    b = kDirt;
                else if (wy == h)
                    b = h <= kSeaLevel + 1 ? kSand : kGrass;
                else if (wy <= kSeaLevel)
                    b = kWater;
                const int wx = int(o.x + x), wz = int(o.z + z);
                if (b == kStone && lattice(wx * 31 + y, wz, uint32_t(c.y) + 9) < 0.004f)
                    b = kOre; // Ore specks: deep stone chunks are rarely all one id.
                if (b == kStone && wy < h - 20 && lattice(wx >> 2, wz >> 2, uint32_t(wy >> 2) + 99) < 0.03f)
                    b = kGravel; // 4x4x4 gravel pockets.

                ids[local_index(x, y, z)] = b;
            }
        }
    for (const Cave& cv : caves) {
        for (int z = 0; z < kChunkSize; ++z)
            for (int y = 0; y < kChunkSize; ++y)
                for (int x = 0; x < kChunkSize; ++x) {
                    const float dx = float(o.x + x) - cv.x, dy = float(o.y + y) - cv.y, dz = float(o.z + z) - cv.z;
                    if (dx * dx + dy * dy + dz * dz < cv.r * cv.r && ids[local_index(x, y, z)] != kWater)
                        ids[local_index(x, y, z)] = kAir;
                }
    }
    return Chunk::from_dense(ids);
}

struct Dataset {
    std::vector<ChunkCoord> coords;
    std::vector<Chunk> chunks;
    size_t uniform = 0;
};

// 16 x 8 x 16 chunks, y from -3 to 4 (world y -96..159). Built once.
const Dataset& dataset() {
    static const Dataset d = [] {
        Dataset out;
        const std::vector<Cave> caves = make_caves(16, 16);
        std::vector<Cave> near;
        for (int cz = 0; cz < 16; ++cz)
            for (int cy = -3; cy < 5; ++cy)
                for (int cx = 0; cx < 16; ++cx) {
                    const ChunkCoord c(cx, cy, cz);
                    near.clear(); // Only caves that touch this chunk.
                    const BlockPos o = chunk_origin(c);
                    for (const Cave& cv : caves)
                        if (cv.x + cv.r >= float(o.x) && cv.x - cv.r <= float(o.x + kChunkSize) &&
                            cv.y + cv.r >= float(o.y) && cv.y - cv.r <= float(o.y + kChunkSize) &&
                            cv.z + cv.r >= float(o.z) && cv.z - cv.r <= float(o.z + kChunkSize))
                            near.push_back(cv);
                    out.coords.push_back(c);
                    out.chunks.push_back(terrain_chunk(c, near));
                    out.uniform += out.chunks.back().is_uniform();
                }
        return out;
    }();
    return d;
}

// The folder for the store files (tools/bench/scratch_dir.h: made on first use, removed whole at
// exit), or null after marking the benchmark failed with the reason ($TMPDIR unusable).
const std::string* scratch_dir(benchmark::State& state) {
    static const Result<tools::ScratchDir> dir = tools::ScratchDir::make("vx_bench_store");
    if (!dir) {
        state.SkipWithError(dir.error().c_str());
        return nullptr;
    }
    return &dir->path();
}

std::unique_ptr<SqliteStore> open_or_die(const std::string& path, benchmark::State& state) {
    SqliteStoreCreateInfo info;
    info.path = path;
    Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
    if (!s) {
        state.SkipWithError(s.error().c_str());
        return nullptr;
    }
    return std::move(*s);
}

void BM_RecordEncode(benchmark::State& state) {
    const Dataset& d = dataset();
    RecordCodec codec(int(state.range(0)));
    std::vector<uint8_t> rec;
    size_t bytes = 0, n = 0;
    for (auto _ : state) {
        for (size_t i = 0; i < d.chunks.size(); ++i) {
            codec.encode(d.coords[i], d.chunks[i], rec);
            bytes += rec.size();
            benchmark::DoNotOptimize(rec.data());
        }
        n += d.chunks.size();
    }
    state.SetItemsProcessed(int64_t(n));
    state.counters["bytes_per_chunk"] = double(bytes) / double(n);
    state.counters["uniform_share"] = double(d.uniform) / double(d.chunks.size());
}
BENCHMARK(BM_RecordEncode)->Name("store/record_encode_zstd_level")->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond);

void BM_RecordDecode(benchmark::State& state) {
    const Dataset& d = dataset();
    RecordCodec codec;
    std::vector<std::vector<uint8_t>> recs(d.chunks.size());
    for (size_t i = 0; i < d.chunks.size(); ++i)
        codec.encode(d.coords[i], d.chunks[i], recs[i]);
    for (auto _ : state)
        for (size_t i = 0; i < recs.size(); ++i) {
            Result<Chunk> c = codec.decode(recs[i], d.coords[i]);
            if (!c)
                state.SkipWithError(c.error().c_str());
            benchmark::DoNotOptimize(c);
        }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(recs.size()));
}
BENCHMARK(BM_RecordDecode)->Name("store/record_decode")->Unit(benchmark::kMillisecond);

// Save every chunk into a fresh store one save() at a time (as the streamer's save jobs do), with
// a durable commit (flush: one transaction, one fsync of the WAL) after every `range(0)` chunks,
// then close the store, which checkpoints the WAL into the main file: all of it timed. The
// streamer commits about once a second (its store_tick_s, the store's max_pending_age), so the
// chunks per commit are the chunks saved per second: 64 for a player editing and unloading, 2048
// (one commit for the whole set) as the bound a bulk writer reaches.
void BM_StoreSave(benchmark::State& state) {
    const std::string* dir = scratch_dir(state);
    if (!dir)
        return;
    const Dataset& d = dataset();
    const size_t per_commit = size_t(state.range(0));
    const std::string path = *dir + "/save.db";
    double file_bytes = 0;
    for (auto _ : state) {
        state.PauseTiming();
        std::error_code ec; // Absent on the first iteration.
        for (const char* suffix : {"", "-wal", "-shm"})
            std::filesystem::remove(path + suffix, ec);
        std::unique_ptr<SqliteStore> store = open_or_die(path, state);
        if (!store)
            return;
        state.ResumeTiming();
        for (size_t i = 0; i < d.chunks.size(); ++i) {
            if (!store->save(d.coords[i], d.chunks[i]))
                state.SkipWithError("save failed");
            if ((i + 1) % per_commit == 0 || i + 1 == d.chunks.size())
                if (!store->flush())
                    state.SkipWithError("flush failed");
        }
        store.reset(); // Checkpoints the WAL into the main file (timed: the writer pays it too).
        state.PauseTiming();
        file_bytes = double(std::filesystem::file_size(path, ec));
        state.ResumeTiming();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(d.chunks.size()));
    state.counters["file_bytes_per_chunk"] = file_bytes / double(d.chunks.size());
    state.counters["commits"] = double((d.chunks.size() + per_commit - 1) / per_commit);
}
BENCHMARK(BM_StoreSave)->Name("store/sqlite_save_chunks_per_commit")->Arg(64)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// Writes `copies` copies of the dataset (shifted 16 chunks apart along x) into a store at `path`,
// once, and closes it (checkpointed).
bool write_store(const std::string& path, int copies, benchmark::State& state) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec))
        return true;
    const Dataset& d = dataset();
    std::unique_ptr<SqliteStore> w = open_or_die(path, state);
    if (!w)
        return false;
    for (int k = 0; k < copies; ++k) {
        for (size_t i = 0; i < d.chunks.size(); ++i)
            (void)w->save(d.coords[i] + ChunkCoord(16 * k, 0, 0), d.chunks[i]);
        if (!w->flush()) {
            state.SkipWithError("flush failed");
            return false;
        }
    }
    return true;
}

// Load every chunk of a store written once, in a shuffled order (streaming order is not key
// order), through one connection kept open: after the first pass the 1.5 MB file sits in
// SQLite's page cache (2 MB by default), so this is the warm figure.
void BM_StoreLoad(benchmark::State& state) {
    const std::string* dir = scratch_dir(state);
    if (!dir)
        return;
    const Dataset& d = dataset();
    const std::string path = *dir + "/load.db";
    if (!write_store(path, 1, state))
        return;
    std::unique_ptr<SqliteStore> store = open_or_die(path, state);
    if (!store)
        return;
    std::vector<size_t> order(d.chunks.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::shuffle(order.begin(), order.end(), std::mt19937(3));
    for (auto _ : state)
        for (size_t i : order) {
            Result<ChunkLoad> r = store->load(d.coords[i]);
            if (!r || r->state != LoadState::Present)
                state.SkipWithError("load failed");
            benchmark::DoNotOptimize(r);
        }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(d.chunks.size()));
}
BENCHMARK(BM_StoreLoad)->Name("store/sqlite_load_warm")->Unit(benchmark::kMillisecond)->UseRealTime();

// Cold loads: 16 copies of the dataset (32,768 chunks, about 23 MB, ten times SQLite's default
// 2 MB page cache); each iteration reopens the store (an empty page cache) after asking the OS
// to drop the file's pages (posix_fadvise DONTNEED: clean pages leave the kernel's cache, so the
// reads go to the disk), then loads 4,096 chunks spread over the whole file in shuffled order.
void BM_StoreLoadCold(benchmark::State& state) {
    const std::string* dir = scratch_dir(state);
    if (!dir)
        return;
    const Dataset& d = dataset();
    constexpr int kCopies = 16;
    const std::string path = *dir + "/load_cold.db";
    if (!write_store(path, kCopies, state))
        return;
    std::mt19937 rng(5);
    std::vector<ChunkCoord> picks(4096);
    for (ChunkCoord& c : picks)
        c = d.coords[rng() % d.coords.size()] + ChunkCoord(16 * int(rng() % kCopies), 0, 0);
    for (auto _ : state) {
        state.PauseTiming();
        const int fd = open(path.c_str(), O_RDONLY);
        if (fd >= 0) {
            (void)posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
            close(fd);
        }
        std::unique_ptr<SqliteStore> store = open_or_die(path, state);
        if (!store)
            return;
        state.ResumeTiming();
        for (const ChunkCoord& c : picks) {
            Result<ChunkLoad> r = store->load(c);
            if (!r || r->state != LoadState::Present)
                state.SkipWithError("load failed");
            benchmark::DoNotOptimize(r);
        }
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(picks.size()));
    std::error_code ec;
    state.counters["file_MB"] = double(std::filesystem::file_size(path, ec)) / 1e6;
}
BENCHMARK(BM_StoreLoadCold)->Name("store/sqlite_load_cold")->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
} // namespace vx::world
