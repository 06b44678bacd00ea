// Terrain generation throughput. The region is 16 x 16 chunk columns (512 x 512 blocks: lowlands,
// hills and sea with the default parameters) and chunk y from -6 to 4 (world y -192..159): from
// below the cave band (uniform stone) to above the highest possible peak (uniform air), the
// vertical range a streaming viewer loads. Single-threaded; one chunk per iteration.
//
// Levels of detail (issue 16): level-k chunks over the same world y range (-192..159) and 4 x 4
// level-k chunk columns around the origin, made three ways: generate_coarse() (direct, from
// the height samples), downsample_generated() (what the engine does for a generator without
// generate_coarse(): 8^k generate() calls and the downsampling), and downsample() alone on 8
// ready level-(k-1) children (the cost of re-downsampling a parent after an edit).

#include <algorithm>
#include <array>
#include <ctime>
#include <vector>

#include <benchmark/benchmark.h>

#include "world/base/assert.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"

namespace vx::world {
namespace {

constexpr uint64_t kSeed = 1234;

struct Region {
    std::vector<ChunkCoord> all, uniform, mixed;
};

// Classifies the region once (cached across benchmarks).
const Region& region() {
    static const Region r = [] {
        Region out;
        const TerrainGenerator gen(kSeed);
        for (int z = -8; z < 8; ++z)
            for (int x = -8; x < 8; ++x)
                for (int y = -6; y <= 4; ++y) {
                    const ChunkCoord c(x, y, z);
                    out.all.push_back(c);
                    (gen.generate(c).is_uniform() ? out.uniform : out.mixed).push_back(c);
                }
        return out;
    }();
    return r;
}

// The level-k chunks of the LOD region (all of them, uniform ones included).
const std::vector<LodCoord>& lod_region(int level) {
    static std::vector<LodCoord> cache[kMaxLodLevel + 1];
    std::vector<LodCoord>& r = cache[level];
    if (r.empty()) {
        const int shift = kChunkBits + level;
        for (int z = -2; z < 2; ++z)
            for (int x = -2; x < 2; ++x)
                for (int y = -192 >> shift; y <= 159 >> shift; ++y)
                    r.push_back({level, ChunkCoord(x, y, z)});
    }
    return r;
}

// CPU time of this thread, microseconds: per-chunk figures stay meaningful on a loaded machine.
double thread_cpu_us() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e6 + double(t.tv_nsec) * 1e-3;
}

// Generates the chunks of `list` in turn; reports chunks/s, and per chunk the best thread CPU
// time over the passes through the list (robust to other load on the machine): its median and
// 90th percentile over the chunks.
template <class T, class Make> void run_with(benchmark::State& state, const std::vector<T>& list, Make&& make) {
    std::vector<double> us(list.size(), 0.0); // Best time per chunk, 0 until generated.
    size_t i = 0;
    for (auto _ : state) {
        const double t0 = thread_cpu_us();
        Chunk c = make(list[i]);
        benchmark::DoNotOptimize(c);
        const double t = thread_cpu_us() - t0;
        us[i] = us[i] == 0.0 ? t : std::min(us[i], t);
        i = i + 1 == list.size() ? 0 : i + 1;
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    std::vector<double> seen;
    for (double v : us)
        if (v > 0.0)
            seen.push_back(v);
    if (!seen.empty()) {
        std::sort(seen.begin(), seen.end());
        state.counters["median_us"] = seen[seen.size() / 2];
        state.counters["p90_us"] = seen[seen.size() * 9 / 10];
    }
    state.counters["chunks_in_set"] = double(list.size());
}

void run(benchmark::State& state, const std::vector<ChunkCoord>& list) {
    const TerrainGenerator gen(kSeed);
    run_with(state, list, [&](ChunkCoord c) { return gen.generate(c); });
}

void BM_TerrainAll(benchmark::State& state) { run(state, region().all); }
void BM_TerrainNonUniform(benchmark::State& state) { run(state, region().mixed); }
void BM_TerrainUniform(benchmark::State& state) { run(state, region().uniform); }

BENCHMARK(BM_TerrainAll)->Name("terrain/all_chunks")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TerrainNonUniform)->Name("terrain/non_uniform")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TerrainUniform)->Name("terrain/uniform")->Unit(benchmark::kMicrosecond);

// Direct coarse chunks, level state.range(0).
void BM_CoarseDirect(benchmark::State& state) {
    const TerrainGenerator gen(kSeed);
    run_with(state, lod_region(int(state.range(0))), [&](LodCoord c) {
        Chunk out;
        VX_ASSERT(gen.generate_coarse(c, out));
        return out;
    });
    state.counters["level0_chunks_each"] = double(int64_t(1) << (3 * state.range(0)));
}

// The same chunks from generated blocks: 8^k generate() calls and the downsampling.
void BM_CoarseFromBlocks(benchmark::State& state) {
    const TerrainGenerator gen(kSeed);
    run_with(state, lod_region(int(state.range(0))), [&](LodCoord c) { return *downsample_generated(gen, c); });
    state.counters["level0_chunks_each"] = double(int64_t(1) << (3 * state.range(0)));
}

// downsample() alone: the level-k chunk from its 8 ready children (direct level-(k-1) chunks,
// made once before timing; level 1 takes generated level-0 chunks).
void BM_DownsampleOnly(benchmark::State& state) {
    const TerrainGenerator gen(kSeed);
    const int level = int(state.range(0));
    const std::vector<LodCoord>& list = lod_region(level);
    std::vector<std::array<Chunk, kLodChildren>> kids(list.size());
    for (size_t i = 0; i < list.size(); ++i)
        for (int k = 0; k < kLodChildren; ++k) {
            const LodCoord child = lod_child(list[i], k);
            if (level == 1)
                kids[i][size_t(k)] = gen.generate(child.chunk);
            else
                VX_ASSERT(gen.generate_coarse(child, kids[i][size_t(k)]));
        }
    std::vector<size_t> index(list.size());
    for (size_t i = 0; i < index.size(); ++i)
        index[i] = i;
    run_with(state, index, [&](size_t i) {
        std::array<const Chunk*, kLodChildren> p;
        for (int k = 0; k < kLodChildren; ++k)
            p[size_t(k)] = &kids[i][size_t(k)];
        return downsample(p);
    });
}

BENCHMARK(BM_CoarseDirect)->Name("terrain/coarse_direct")->ArgName("level")->DenseRange(1, 5)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseFromBlocks)->Name("terrain/coarse_from_blocks")->ArgName("level")->DenseRange(1, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DownsampleOnly)->Name("terrain/downsample_only")->ArgName("level")->DenseRange(1, 3)->Unit(benchmark::kMicrosecond);

} // namespace
} // namespace vx::world
