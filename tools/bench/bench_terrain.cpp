// Terrain generation throughput. The region is 16 x 16 chunk columns (512 x 512 blocks: lowlands,
// hills and sea with the default parameters) and chunk y from -6 to 4 (world y -192..159): from
// below the cave band (uniform stone) to above the highest possible peak (uniform air), the
// vertical range a streaming viewer loads. Single-threaded; one chunk per iteration.

#include <algorithm>
#include <ctime>
#include <vector>

#include <benchmark/benchmark.h>

#include "world/gen/terrain.h"

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

// CPU time of this thread, microseconds: per-chunk figures stay meaningful on a loaded machine.
double thread_cpu_us() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e6 + double(t.tv_nsec) * 1e-3;
}

// Generates the chunks of `list` in turn; reports chunks/s, and per chunk the best thread CPU
// time over the passes through the list (robust to other load on the machine): its median and
// 90th percentile over the chunks.
void run(benchmark::State& state, const std::vector<ChunkCoord>& list) {
    const TerrainGenerator gen(kSeed);
    std::vector<double> us(list.size(), 0.0); // Best time per chunk, 0 until generated.
    size_t i = 0;
    for (auto _ : state) {
        const double t0 = thread_cpu_us();
        Chunk c = gen.generate(list[i]);
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

void BM_TerrainAll(benchmark::State& state) { run(state, region().all); }
void BM_TerrainNonUniform(benchmark::State& state) { run(state, region().mixed); }
void BM_TerrainUniform(benchmark::State& state) { run(state, region().uniform); }

BENCHMARK(BM_TerrainAll)->Name("terrain/all_chunks")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TerrainNonUniform)->Name("terrain/non_uniform")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TerrainUniform)->Name("terrain/uniform")->Unit(benchmark::kMicrosecond);

} // namespace
} // namespace vx::world
