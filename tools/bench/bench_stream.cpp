// Streaming benchmarks (`vx bench stream`): how fast the engine fills a view from nothing
// (terrain generation or store loads, + meshing on all cores), and a real-time fly-through at 100 blocks/s with
// a 12-chunk view radius: holes in the view after the initial fill, and main-thread time per
// frame (p50/p99). Wall-clock by nature: run them on a quiet machine.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <unistd.h>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/chunk_streamer.h"
#include "engine/engine_sink.h"
#include "render/renderer.h"
#include "world/gen/terrain.h"

#include "world/store/sqlite_store.h"
#include "scratch_dir.h"

namespace vx::tools {
namespace {

using namespace vx::engine;
using namespace vx::world;
using Clock = std::chrono::steady_clock;

struct NullSink : MeshSink {
    size_t quads = 0;
    void on_mesh(ChunkCoord, const ChunkMesh& m, std::span<const int>) override { quads += m.quad_count(); }
    void on_unload(ChunkCoord) override {}
};

// Remembers which chunks were handed a mesh, so the fill counts only those with blocks: an air
// chunk gets an empty mesh without a mesh job and costs nothing worth counting.
struct FillSink : MeshSink {
    std::vector<ChunkCoord> meshed;
    void on_mesh(ChunkCoord c, const ChunkMesh&, std::span<const int>) override { meshed.push_back(c); }
    void on_unload(ChunkCoord) override {}
};

constexpr int kFillRadius = 8, kFillRadiusVertical = 3;

// A store holding every chunk the fill of `gen` at its surface near (0, 0) can ask for (the view
// plus the meshing apron and a margin), written once per process into a scratch folder
// (scratch_dir.h: removed at exit). Empty when it could not be written.
const std::string& fill_store_path(const TerrainGenerator& gen, const glm::dvec3& pos) {
    static const Result<tools::ScratchDir> dir = tools::ScratchDir::make("vx_bench_fill");
    static const std::string path = [&] {
        if (!dir)
            return std::string();
        const std::string p = dir->path() + "/fill.db";
        Result<std::unique_ptr<SqliteStore>> store = SqliteStore::open({p});
        if (!store)
            return std::string();
        const ChunkCoord centre = world::chunk_of(BlockPos(glm::floor(pos)));
        const int r = kFillRadius + 2, rv = kFillRadiusVertical + 2;
        for (int y = -rv; y <= rv; ++y)
            for (int z = -r; z <= r; ++z)
                for (int x = -r; x <= r; ++x) {
                    const ChunkCoord c = centre + ChunkCoord(x, y, z);
                    if (!(*store)->save(c, gen.generate(c)))
                        return std::string();
                }
        if (!(*store)->flush())
            return std::string();
        return p;
    }();
    return path;
}

// From an empty world to a fully meshed view of radius 8 (3 vertically) at a terrain surface,
// generating every chunk (range(0) == 0) or loading it from a store written beforehand (1; the
// store is reopened each iteration: SQLite's page cache starts empty, the OS's is warm).
void bench_fill(benchmark::State& state) {
    const bool from_store = state.range(0) != 0;
    const TerrainGenerator gen(1234);
    const glm::dvec3 pos(0.5, gen.surface_height(0, 0) + 2.0, 0.5);
    const std::string path = from_store ? fill_store_path(gen, pos) : std::string();
    if (from_store && path.empty()) {
        state.SkipWithError("cannot write the fill's store");
        return;
    }
    size_t loaded = 0, meshed = 0;
    double seconds = 0;
    for (auto _ : state) {
        std::unique_ptr<SqliteStore> store;
        if (from_store) {
            Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open({path});
            if (!s) {
                state.SkipWithError(s.error().c_str());
                return;
            }
            store = std::move(*s);
        }
        FillSink sink;
        StreamingSettings st;
        st.view_radius = kFillRadius;
        st.view_radius_vertical = kFillRadiusVertical;
        st.frame_budget = std::chrono::milliseconds(4);
        const auto t0 = Clock::now();
        double t = 0;
        {
            ChunkStreamer s(gen, store.get(), sink, st);
            do {
                s.update(pos, glm::dvec3(1, 0, 0), Clock::now());
                std::this_thread::sleep_for(std::chrono::microseconds(500));
            } while (!s.settled());
            t = std::chrono::duration<double>(Clock::now() - t0).count();
            loaded += s.metrics().loaded;
            for (const ChunkCoord& c : sink.meshed) {
                const Chunk* chunk = s.world().find_chunk(c);
                meshed += chunk && !chunk->is_empty();
            }
        }
        state.SetIterationTime(t);
        seconds += t;
    }
    state.counters["loaded_per_s"] = double(loaded) / seconds; // Generated, or read from the store.
    state.counters["meshed_per_s"] = double(meshed) / seconds; // Chunks with blocks (a mesh job each).
    state.counters["meshed"] = double(meshed) / double(state.iterations());
}

double percentile(std::vector<double> v, double p) {
    if (v.empty())
        return 0;
    std::sort(v.begin(), v.end());
    return v[size_t(p * double(v.size() - 1))];
}

// 100 blocks/s along +x at 60 frames/s, view radius 12 (4 vertically), for 10 s after the fill.
// With `use_store`: over an empty SQLite store in a temporary folder, so every chunk is a load
// miss that falls back to generation (the I/O lane's path) instead of generating directly.
void run_flythrough(benchmark::State& state, bool use_store) {
    const TerrainGenerator gen(77);
    for (auto _ : state) {
        Result<tools::ScratchDir> dir = tools::ScratchDir(); // Removed after the store closes.
        std::unique_ptr<SqliteStore> store;
        if (use_store) {
            dir = tools::ScratchDir::make("vx_bench_stream_store");
            if (!dir) {
                state.SkipWithError(dir.error().c_str());
                return;
            }
            auto opened = SqliteStore::open({dir->path() + "/world.db"});
            if (!opened) {
                state.SkipWithError(opened.error().c_str());
                return;
            }
            store = std::move(*opened);
        }
        NullSink sink;
        StreamingSettings st;
        st.view_radius = 12;
        st.view_radius_vertical = 4;
        ChunkStreamer s(gen, store.get(), sink, st);
        glm::dvec3 pos(0.5, 40.0, 0.5);
        while (!s.settled()) {
            s.update(pos, glm::dvec3(1, 0, 0), Clock::now());
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        std::vector<double> update_ms, update_cpu_ms;
        size_t max_missing = 0, missing_frames = 0, frames = 0, over_budget = 0;
        const auto frame = std::chrono::microseconds(16667);
        auto next = Clock::now();
        const auto t0 = next;
        while (next - t0 < std::chrono::seconds(10)) {
            pos.x += 100.0 / 60.0;
            s.update(pos, glm::dvec3(1, 0, 0), next);
            const StreamingMetrics m = s.metrics();
            update_ms.push_back(std::chrono::duration<double, std::milli>(m.last_update_time).count());
            update_cpu_ms.push_back(std::chrono::duration<double, std::milli>(m.last_update_cpu).count());
            over_budget += m.last_update_cpu > st.frame_budget;
            const size_t missing = m.wanted_meshes - m.meshed;
            max_missing = std::max(max_missing, missing);
            missing_frames += missing > 0;
            ++frames;
            next += frame;
            std::this_thread::sleep_until(next);
        }
        const StreamingMetrics m = s.metrics();
        size_t uniform = 0, other = 0, other_bytes = 0, uniform_bytes = 0;
        s.world().for_each_chunk([&](ChunkCoord, const Chunk& c) {
            (c.is_uniform() ? uniform : other) += 1;
            (c.is_uniform() ? uniform_bytes : other_bytes) += c.memory_bytes();
        });
        state.counters["bytes_per_uniform_chunk"] = double(uniform_bytes) / double(std::max<size_t>(1, uniform));
        state.counters["bytes_per_other_chunk"] = double(other_bytes) / double(std::max<size_t>(1, other));
        state.counters["uniform_share"] = double(uniform) / double(std::max<size_t>(1, uniform + other));
        state.counters["max_missing_in_view"] = double(max_missing);
        state.counters["frames_with_missing"] = double(missing_frames);
        state.counters["frames"] = double(frames);
        state.counters["update_p50_ms"] = percentile(update_ms, 0.5);
        state.counters["update_p99_ms"] = percentile(update_ms, 0.99);
        state.counters["update_max_ms"] = percentile(update_ms, 1.0);
        state.counters["update_cpu_p50_ms"] = percentile(update_cpu_ms, 0.5);
        state.counters["update_cpu_p90_ms"] = percentile(update_cpu_ms, 0.9);
        state.counters["update_cpu_p99_ms"] = percentile(update_cpu_ms, 0.99);
        state.counters["update_cpu_max_ms"] = percentile(update_cpu_ms, 1.0);
        state.counters["frames_cpu_over_budget"] = double(over_budget); // Main-thread CPU > frame_budget.
        state.counters["loaded"] = double(m.loaded);
        state.counters["bytes_per_loaded_chunk"] = double(m.block_bytes) / double(std::max<size_t>(1, m.loaded));
        state.counters["wasted_ms"] = std::chrono::duration<double, std::milli>(m.jobs.wasted_work).count();
        state.counters["cancelled"] = double(m.jobs.cancelled);
    }
}

// A renderer on $VX_BENCH_DEVICE (auto, cpu, gpu, N), or null when unset or not made: the
// streaming benchmarks then measure without the GPU side of set_chunk.
std::unique_ptr<render::Renderer> bench_renderer() {
    const char* dev = std::getenv("VX_BENCH_DEVICE");
    if (!dev)
        return nullptr;
    render::RendererCreateInfo ci;
    if (auto choice = render::parse_device_choice(dev))
        ci.device = *choice;
    auto made = render::Renderer::create(ci);
    return made ? std::move(*made) : nullptr;
}

// Counts the chunks handed on (meshes, empty ones included) on the way to the real sink.
struct CountingSink : MeshSink {
    explicit CountingSink(MeshSink& to) : next(to) {}
    void on_mesh(ChunkCoord c, const ChunkMesh& m, std::span<const int> slices) override {
        ++meshes;
        next.on_mesh(c, m, slices);
    }
    void on_unload(ChunkCoord c) override { next.on_unload(c); }
    MeshSink& next;
    size_t meshes = 0;
};

// Applying finished chunks inside update()'s budget (issue 16: radius 32 at full detail flown at
// 100 blocks/s needs >= 5,000 chunks/s within 2 ms per update). A view of radius range(0)
// (4 vertically) fills from nothing at 60 updates/s of wall time with the default 2 ms budget,
// generation and meshing on every core, the meshes going to the engine's sink and, when
// $VX_BENCH_DEVICE names a device that can be made (auto, cpu, gpu, N; unset: none), on to a
// real Renderer's set_chunk (no frames are drawn: the GPU side runs in frames, not in update()).
// Counters: applied_per_update_s, chunks applied (loaded + meshed) per second of main-thread
// update() time, the rate the budget sustains (x 0.002 per update); fill_s, the wall time to a
// settled view; update_cpu_p99_ms.
void bench_apply(benchmark::State& state) {
    const int radius = int(state.range(0));
    const TerrainGenerator gen(77);
    std::unique_ptr<render::Renderer> renderer = bench_renderer();
    for (auto _ : state) {
        if (renderer)
            renderer->clear_chunks();
        EngineSink engine_sink(renderer.get(), false);
        CountingSink sink(engine_sink);
        StreamingSettings st;
        st.view_radius = radius;
        st.view_radius_vertical = 4;
        std::vector<double> update_cpu_ms;
        double cpu_s = 0;
        size_t applied = 0;
        const glm::dvec3 pos(0.5, gen.surface_height(0, 0) + 2.0, 0.5);
        const auto t0 = Clock::now();
        {
            ChunkStreamer s(gen, nullptr, sink, st);
            auto next = t0;
            do {
                const size_t before = sink.meshes + s.metrics().loaded;
                s.update(pos, glm::dvec3(1, 0, 0), next);
                const StreamingMetrics m = s.metrics();
                const double ms = std::chrono::duration<double, std::milli>(m.last_update_cpu).count();
                update_cpu_ms.push_back(ms);
                cpu_s += ms / 1e3;
                applied += sink.meshes + m.loaded - before;
                next += std::chrono::microseconds(16667);
                std::this_thread::sleep_until(next);
            } while (!s.settled() && Clock::now() - t0 < std::chrono::seconds(120));
        }
        const double fill_s = std::chrono::duration<double>(Clock::now() - t0).count();
        state.SetIterationTime(fill_s);
        state.counters["applied"] = double(applied);
        state.counters["applied_per_update_s"] = double(applied) / cpu_s;
        state.counters["applied_per_s"] = double(applied) / fill_s;
        state.counters["fill_s"] = fill_s;
        state.counters["update_cpu_p50_ms"] = percentile(update_cpu_ms, 0.5);
        state.counters["update_cpu_p99_ms"] = percentile(update_cpu_ms, 0.99);
        state.counters["renderer"] = renderer ? 1 : 0;
    }
}

// Counts chunk loads on the way to the engine's sink (which observes them too).
struct CountingObserver : StreamObserver {
    explicit CountingObserver(StreamObserver& to) : next(to) {}
    void on_chunk_loaded(ChunkCoord c) override {
        ++loads;
        next.on_chunk_loaded(c);
    }
    void on_chunk_unloaded(ChunkCoord c) override { next.on_chunk_unloaded(c); }
    StreamObserver& next;
    size_t loads = 0;
};

// Applying finished chunks while flying (issue 16: radius 32 at full detail flown at 100
// blocks/s needs >= 5,000 chunks/s inside update()'s 2 ms). A view of radius range(0) (4
// vertically) is filled at the terrain surface, then flown along +x at 100 blocks/s for 10 s of
// wall time at 60 updates/s, generation and meshing on every core, meshes through the engine's
// sink (and a Renderer's set_chunk with $VX_BENCH_DEVICE, as stream/apply). Counters, over the
// flight only: applied (chunk loads + meshes handed on), applied_per_update_ms (per ms of
// main-thread update() CPU: x 2 is what one budget-limited update applies), update_cpu_p50/p99_ms,
// meshed_share_min/end (meshed / wanted in the view radius; 1: no holes). On a machine whose
// workers cannot keep up (few cores) the share falls and fewer chunks are applied per update,
// but the applied-per-ms figure still compares builds.
void bench_apply_flight(benchmark::State& state) {
    const int radius = int(state.range(0));
    const TerrainGenerator gen(77);
    std::unique_ptr<render::Renderer> renderer = bench_renderer();
    for (auto _ : state) {
        if (renderer)
            renderer->clear_chunks();
        EngineSink engine_sink(renderer.get(), false);
        CountingSink sink(engine_sink);
        CountingObserver observer(engine_sink);
        StreamingSettings st;
        st.view_radius = radius;
        st.view_radius_vertical = 4;
        ChunkStreamer s(gen, nullptr, sink, st);
        s.set_observer(&observer);
        glm::dvec3 pos(0.5, gen.surface_height(0, 0) + 2.0, 0.5);
        const auto fill0 = Clock::now();
        auto next = fill0;
        do {
            s.update(pos, glm::dvec3(1, 0, 0), next);
            next += std::chrono::microseconds(16667);
            std::this_thread::sleep_until(next);
        } while (!s.settled() && Clock::now() - fill0 < std::chrono::seconds(300));
        const double fill_s = std::chrono::duration<double>(Clock::now() - fill0).count();
        std::vector<double> update_cpu_ms;
        double cpu_ms = 0, share_min = 1;
        const size_t applied0 = sink.meshes + observer.loads;
        next = Clock::now();
        const auto t0 = next;
        while (next - t0 < std::chrono::seconds(10)) {
            pos.x += 100.0 / 60.0;
            s.update(pos, glm::dvec3(1, 0, 0), glm::dvec3(100, 0, 0), next);
            const StreamingMetrics m = s.metrics();
            const double ms = std::chrono::duration<double, std::milli>(m.last_update_cpu).count();
            update_cpu_ms.push_back(ms);
            cpu_ms += ms;
            share_min = std::min(share_min, double(m.meshed) / double(std::max<size_t>(1, m.wanted_meshes)));
            next += std::chrono::microseconds(16667);
            std::this_thread::sleep_until(next);
        }
        const StreamingMetrics m = s.metrics();
        const size_t applied = sink.meshes + observer.loads - applied0;
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
        state.counters["fill_s"] = fill_s;
        state.counters["applied"] = double(applied);
        state.counters["applied_per_update_ms"] = double(applied) / cpu_ms;
        state.counters["update_cpu_p50_ms"] = percentile(update_cpu_ms, 0.5);
        state.counters["update_cpu_p99_ms"] = percentile(update_cpu_ms, 0.99);
        state.counters["meshed_share_min"] = share_min;
        state.counters["meshed_share_end"] = double(m.meshed) / double(std::max<size_t>(1, m.wanted_meshes));
        state.counters["loaded_end"] = double(m.loaded);
        state.counters["renderer"] = renderer ? 1 : 0;
    }
}

// update()'s main-thread CPU time against the number of loaded chunks (issue 16: it must not
// grow with it): a settled view of radius range(0) (4 vertically), then 120 updates at 60/s with
// the viewer still (update_still_ms: mean; the work left is the bookkeeping of a frame), then 120
// flying at 100 blocks/s along +x (update_moving_ms: mean; work proportional to the chunks
// entering and leaving, so about the same at every radius until the budget caps it).
void bench_update_cost(benchmark::State& state) {
    const int radius = int(state.range(0));
    const TerrainGenerator gen(77);
    for (auto _ : state) {
        NullSink sink;
        StreamingSettings st;
        st.view_radius = radius;
        st.view_radius_vertical = 4;
        ChunkStreamer s(gen, nullptr, sink, st);
        glm::dvec3 pos(0.5, gen.surface_height(0, 0) + 2.0, 0.5);
        auto now = Clock::now();
        while (!s.settled()) {
            s.update(pos, glm::dvec3(1, 0, 0), now = Clock::now());
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        auto run = [&](double speed) {
            double ms = 0;
            for (int i = 0; i < 120; ++i) {
                pos.x += speed / 60.0;
                now += std::chrono::microseconds(16667);
                s.update(pos, glm::dvec3(1, 0, 0), now);
                ms += std::chrono::duration<double, std::milli>(s.metrics().last_update_cpu).count();
                std::this_thread::sleep_until(now);
            }
            return ms / 120;
        };
        state.counters["loaded"] = double(s.metrics().loaded);
        state.counters["update_still_ms"] = run(0.0);
        state.counters["update_moving_ms"] = run(100.0);
    }
}

void bench_flythrough(benchmark::State& state) { run_flythrough(state, false); }
void bench_flythrough_store(benchmark::State& state) { run_flythrough(state, true); }

BENCHMARK(bench_fill)->Name("stream/fill_radius8_generated")->Arg(0)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(bench_fill)->Name("stream/fill_radius8_from_store")->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(bench_update_cost)->Name("stream/update_cost")->Arg(8)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(bench_apply)->Name("stream/apply")->Arg(12)->Arg(32)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(bench_apply_flight)->Name("stream/apply_flight")->Arg(32)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(bench_flythrough)->Name("stream/flythrough_100bps_r12")->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(bench_flythrough_store)
    ->Name("stream/flythrough_store_100bps_r12")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

} // namespace
} // namespace vx::tools
