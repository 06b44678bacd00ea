// Renderer benchmarks (Google Benchmark): batched BLAS builds and refits of a terrain of
// K x K chunks, and tracing primary + shadow rays. Device: $VX_BENCH_DEVICE (auto, cpu, gpu, N).
// Sizes: 8 x 8 chunks is a small view distance (256 blocks across), 16 x 16 a typical one;
// 256 x 256 keeps lavapipe runs short, 1920 x 1080 is the real target.
// Timings are wall clock from submit to fence (what a frame waits for).
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include <benchmark/benchmark.h>

#include "render/renderer.h"
#include "world/mesh/edit_mesher.h"
#include "world/world.h"

namespace vx::render {
namespace {

Renderer& renderer() {
    static std::unique_ptr<Renderer> r = [] {
        const char* env = std::getenv("VX_BENCH_DEVICE");
        RendererCreateInfo ci;
        ci.device = *parse_device_choice(env ? env : "auto");
        auto created = Renderer::create(ci);
        if (!created) {
            std::fprintf(stderr, "no renderer: %s\n", created.error().c_str());
            std::exit(1);
        }
        std::fprintf(stderr, "device: %s (%s)\n", (*created)->device().name.c_str(),
                     device_type_name((*created)->device().type));
        return std::move(*created);
    }();
    return *r;
}

// Rolling terrain, 4..27 blocks high, over k x k chunks (one chunk layer), greedy meshed.
const world::MeshMap& terrain(int k) {
    static std::map<int, world::MeshMap> cache;
    if (auto it = cache.find(k); it != cache.end())
        return it->second;
    world::World w;
    const int64_t n = int64_t(k) * world::kChunkSize;
    for (int64_t z = 0; z < n; ++z)
        for (int64_t x = 0; x < n; ++x) {
            const double h = 15 + 6 * std::sin(double(x) * 0.07) * std::cos(double(z) * 0.05) +
                             5 * std::sin(double(x + 2 * z) * 0.13);
            for (int64_t y = 0; y < int64_t(h); ++y)
                w.set_block({x, y, z}, world::BlockId(y + 1 >= int64_t(h) ? 3 : (y > 8 ? 2 : 1)));
        }
    world::EditMesher em;
    world::MeshMap meshes;
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) { em.mesh_chunk(w, c, meshes); });
    return cache[k] = std::move(meshes);
}

RenderSettings tiny() {
    RenderSettings s;
    s.width = s.height = 8;
    s.mode = ShadingMode::Flat;
    return s;
}

Camera overview(int k) {
    const double n = k * 32.0;
    return Camera::look_at({n * 0.5 + 0.3, 60.2, -10.7}, {n * 0.5, 10.0, n * 0.6});
}

void BM_BuildAllBlas(benchmark::State& state) {
    const int k = int(state.range(0));
    const world::MeshMap& meshes = terrain(k);
    Renderer& r = renderer();
    uint64_t tris = 0;
    for (auto _ : state) {
        r.clear_chunks();
        for (const auto& [c, mc] : meshes)
            r.set_chunk(c, mc.mesh);
        r.render(tiny(), overview(k));
        tris = r.last_stats().triangles;
    }
    state.counters["blas"] = double(meshes.size());
    state.counters["triangles"] = double(tris);
    state.counters["tri/s"] = benchmark::Counter(double(tris), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_RefitAllBlas(benchmark::State& state) {
    const int k = int(state.range(0));
    const world::MeshMap& meshes = terrain(k);
    Renderer& r = renderer();
    r.clear_chunks();
    for (const auto& [c, mc] : meshes)
        r.set_chunk(c, mc.mesh);
    r.render(tiny(), overview(k));
    std::vector<int> all(world::kSliceCount); // Every slice named as changed: a whole-chunk edit.
    for (int s = 0; s < world::kSliceCount; ++s)
        all[size_t(s)] = s;
    // The same quads with another block id: same slots, so every iteration refits every chunk
    // (set_chunk ignores a mesh sent again unchanged).
    std::vector<std::pair<world::ChunkCoord, std::array<world::ChunkMesh, 2>>> variants;
    for (const auto& [c, mc] : meshes) {
        world::ChunkMesh other;
        other.begin(mc.mesh.quad_count());
        for (int s = 0; s < world::kSliceCount; ++s) {
            other.begin_slice(s);
            for (world::Quad q : mc.mesh.slice(s)) {
                q.block = world::BlockId(q.block == 1 ? 2 : 1);
                other.push(q);
            }
        }
        other.end();
        variants.push_back({c, {mc.mesh, std::move(other)}});
    }
    // The first edit turns the loaded (cold) chunks hot, a rebuild each; after that every chunk
    // refits with all its slots uploaded.
    for (const auto& [c, pair] : variants)
        r.set_chunk(c, pair[1], all);
    r.render(tiny(), overview(k));
    size_t iteration = 1;
    for (auto _ : state) {
        ++iteration;
        for (const auto& [c, pair] : variants)
            r.set_chunk(c, pair[iteration % 2], all);
        r.render(tiny(), overview(k));
        if (r.last_stats().blas_refits != meshes.size())
            state.SkipWithError("expected refits only");
    }
    state.counters["blas"] = double(meshes.size());
}

void BM_Trace(benchmark::State& state) {
    const int k = 8;
    const world::MeshMap& meshes = terrain(k);
    Renderer& r = renderer();
    r.clear_chunks();
    for (const auto& [c, mc] : meshes)
        r.set_chunk(c, mc.mesh);
    RenderSettings s;
    s.width = uint32_t(state.range(0));
    s.height = uint32_t(state.range(1));
    s.mode = ShadingMode::Full;
    s.shadow_samples = uint32_t(state.range(2));
    s.max_bounces = 0;
    s.light.block = {-50, 120, -50};
    r.render(s, overview(k)); // Builds the BLASes outside the timed loop.
    double gpu_ms = 0;
    for (auto _ : state) {
        r.render(s, overview(k));
        gpu_ms += r.last_stats().gpu_ms;
    }
    const double rays = double(s.width) * s.height * (1 + s.shadow_samples); // Upper bound.
    state.counters["rays"] = rays;
    state.counters["Mrays/s"] = rays * double(state.iterations()) / (gpu_ms * 1e3);
    state.counters["gpu_ms"] = gpu_ms / double(state.iterations());
}

// The CPU cost of a frame against the number of resident chunks (issue 16: it must not grow
// with it). N chunks of one block each (6 quads) on a square grid one chunk layer thick, a
// 64 x 36 flat frame looking down on a corner of it; built once, then each iteration records a
// frame with range(1) chunks removed and as many added (0: a still world; 16: streaming at about
// 100 blocks/s). Counters: record_ms is the CPU time recording the frame (RenderStats::cpu_ms),
// wait_ms the submit-to-fence wait (on lavapipe that includes the TLAS build, done on the CPU).
// Sizes: 1k chunks is a radius-8 view, 16k radius 32, 64k the full-detail radius 48 of the issue.
void BM_FrameCpu(benchmark::State& state) {
    const int n = int(state.range(0)), churn = int(state.range(1));
    static const world::ChunkMesh block = [] {
        world::World w;
        w.set_block({5, 5, 5}, world::BlockId(1));
        world::EditMesher em;
        world::MeshMap meshes;
        em.mesh_chunk(w, world::ChunkCoord(0, 0, 0), meshes);
        return meshes.at(world::ChunkCoord(0, 0, 0)).mesh;
    }();
    const int side = int(std::ceil(std::sqrt(double(n))));
    auto coord = [&](int i) { return world::ChunkCoord(i % side, 0, i / side); };
    Renderer& r = renderer();
    r.clear_chunks();
    for (int i = 0; i < n; ++i)
        r.set_chunk(coord(i), block);
    RenderSettings s;
    s.width = 64;
    s.height = 36;
    s.mode = ShadingMode::Flat;
    const Camera cam = Camera::look_at({-20.3, 90.6, -20.2}, {40.0, 0.0, 40.0});
    int next = n; // Chunks [next - n, next) are resident.
    auto frame = [&] {
        for (int i = 0; i < churn; ++i, ++next) {
            r.remove_chunk(coord(next - n));
            r.set_chunk(coord(next), block);
        }
        r.render(s, cam);
    };
    // Outside the timed loop: every BLAS built, compacted (kFramesInFlight frames later) and the
    // originals freed (kFramesInFlight frames after that), so the loop sees the steady state.
    for (int i = 0; i < 8; ++i)
        frame();
    double record_ms = 0, wait_ms = 0;
    for (auto _ : state) {
        frame();
        record_ms += r.last_stats().cpu_ms;
        wait_ms += r.last_stats().gpu_ms;
    }
    r.clear_chunks();
    const double it = double(state.iterations());
    state.counters["chunks"] = n;
    state.counters["instances"] = r.last_stats().instances;
    state.counters["record_ms"] = record_ms / it;
    state.counters["wait_ms"] = wait_ms / it;
}

BENCHMARK(BM_BuildAllBlas)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RefitAllBlas)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FrameCpu)
    ->ArgsProduct({{1024, 4096, 16384, 65536}, {0, 16}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Trace)->Args({256, 256, 1})->Args({256, 256, 4})->Args({1920, 1080, 1})->Args({1920, 1080, 4})->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
} // namespace vx::render

BENCHMARK_MAIN();
