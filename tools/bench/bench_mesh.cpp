// Mesher benchmarks (`vx bench mesh`). Scenes follow issue 2: 10% random (the thesis's
// `rand() % 10 == 0`), a terrain-like heightmap with a few block types, 50% noise with 3 types,
// a 3D checkerboard (the worst case), solid and empty; each isolated (air around, as in the
// thesis) and embedded (opaque neighbours). 32³ chunks: the engine's chunk size.
// Each benchmark cycles through 16 chunks, distinct wherever the scene allows (solid: 9 ids;
// empty: air is air), so caches and branch predictors see realistic variety.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/job_batch.h"
#include "engine/region_mesher.h"
#include "render/touching_faces.h"
#include "render/touching_pairs.h"
#include "world/mesh/mesher.h"
#include "world/mesh/reference_meshers.h"
#include "world/gen/seed_scene.h"

namespace vx::tools {
namespace {

using namespace vx::world;

constexpr int kPool = 16;

Chunk terrain_chunk(uint64_t seed) {
    // Rolling hills 8..26 blocks high: stone, 3 dirt, grass on top, sand in hollows, ~1% ore.
    std::vector<BlockId> ids(kChunkVolume, kAir);
    std::mt19937_64 rng(seed);
    const double px = double(rng() % 1000), pz = double(rng() % 1000);
    for (int z = 0; z < kChunkSize; ++z)
        for (int x = 0; x < kChunkSize; ++x) {
            const double fx = (x + px) * 0.11, fz = (z + pz) * 0.09;
            const int h = 17 + int(std::lround(5 * std::sin(fx) * std::cos(fz) + 2.5 * std::sin(fx * 2.3 + fz * 1.7)));
            for (int y = 0; y <= h && y < kChunkSize; ++y) {
                BlockId b = y < h - 3 ? 1 : y < h ? 2 : (h < 13 ? 4 : 3);
                if (b == 1 && rng() % 100 == 0)
                    b = 10; // Ore-like speckles.
                ids[local_index(x, y, z)] = b;
            }
        }
    return Chunk::from_dense(ids);
}

// `percent` of the cells hold one of `types` ids from `first`, at random.
Chunk noise_chunk(uint64_t seed, int percent, int types, BlockId first = 1) {
    std::vector<BlockId> ids(kChunkVolume);
    std::mt19937_64 rng(seed);
    for (BlockId& b : ids)
        b = int(rng() % 100) < percent ? BlockId(first + rng() % types) : kAir;
    return Chunk::from_dense(ids);
}

// The default registry's opaque ids (water 5 and glass 6 are not).
constexpr BlockId kOpaqueIds[] = {1, 2, 3, 4, 7, 8, 9, 10, 11};
constexpr int kOpaqueCount = int(sizeof kOpaqueIds / sizeof kOpaqueIds[0]);

// Chunk i: either parity of the 3D checkerboard, with one of 8 opaque ids (16 distinct chunks).
Chunk checker_chunk(uint64_t i) {
    std::vector<BlockId> ids(kChunkVolume);
    const BlockId block = kOpaqueIds[(i >> 1) % 8];
    for (int k = 0; k < kChunkVolume; ++k)
        ids[k] = (((k & 31) + ((k >> 5) & 31) + (k >> 10) + int(i)) & 1) ? block : kAir;
    return Chunk::from_dense(ids);
}

struct Scene {
    const char* name;
    std::function<Chunk(uint64_t)> make;
};

const std::vector<Scene>& scenes() {
    static const std::vector<Scene> s = {
        {"random10", [](uint64_t i) { return random_fill_chunk(i * 7919 + 1, 10, 1); }},
        {"terrain", [](uint64_t i) { return terrain_chunk(i + 11); }},
        {"noise50x3", [](uint64_t i) { return noise_chunk(i + 101, 50, 3); }},
        // 10% water and glass at random (ids 5 and 6: see-through): render::mark_touching_faces'
        // worst case, many touching pairs inside and transparent faces on every border.
        {"see_through10", [](uint64_t i) { return noise_chunk(i + 211, 10, 2, 5); }},
        {"checker3d", [](uint64_t i) { return checker_chunk(i); }},
        // A uniform chunk differs from another only by its id: the 9 opaque ids in turn.
        {"solid", [](uint64_t i) { return Chunk(kOpaqueIds[i % kOpaqueCount]); }},
        {"empty", [](uint64_t) { return Chunk(); }}, // All air chunks are alike.
    };
    return s;
}

using MeshFn = void (*)(GreedyMesher&, const MesherInput&, ChunkMesh&);

void bench_mesher(benchmark::State& state, const Scene& scene, bool embedded, MeshFn fn) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    std::vector<Chunk> pool;
    for (int i = 0; i < kPool; ++i)
        pool.push_back(scene.make(uint64_t(i)));
    const Apron apron = embedded ? Apron::filled(1, reg) : Apron::air();
    GreedyMesher mesher;
    ChunkMesh mesh;
    uint64_t quads = 0, n = 0;
    for (const Chunk& c : pool) {
        fn(mesher, {c, apron, reg}, mesh);
        quads += mesh.quad_count();
    }
    for (auto _ : state) {
        const Chunk& c = pool[n++ % kPool];
        fn(mesher, {c, apron, reg}, mesh);
        benchmark::DoNotOptimize(mesh.quad_count());
    }
    state.counters["quads"] = double(quads) / kPool; // Mean over the pool, exact.
}

// The renderer's marks for the coincident-face probe (render/touching_faces.h) on the greedy
// meshes of `scene` (isolated), per chunk: what Renderer::set_chunk adds to each chunk it is sent.
void bench_touching_faces(benchmark::State& state, const Scene& scene) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    GreedyMesher mesher;
    std::vector<ChunkMesh> meshes(kPool);
    std::vector<std::vector<BlockId>> ids(kPool);
    uint64_t quads = 0, marked = 0;
    ChunkMesh out;
    for (int i = 0; i < kPool; ++i) {
        mesher.mesh({scene.make(uint64_t(i)), Apron::air(), reg}, meshes[i]);
        ids[i] = meshes[i].block_ids();
        quads += meshes[i].quad_count();
        if (render::mark_touching_faces(meshes[i], ids[i], reg, out).marked)
            out.for_each_quad([&](const Quad& q) { marked += q.reserved != 0; });
    }
    uint64_t n = 0;
    for (auto _ : state) {
        const size_t i = n++ % kPool;
        benchmark::DoNotOptimize(render::mark_touching_faces(meshes[i], ids[i], reg, out));
    }
    state.counters["quads"] = double(quads) / kPool;
    state.counters["marked"] = double(marked) / kPool; // Quads probed: border faces and pairs.
}

// Renderer::set_chunk's bookkeeping of touching see-through blocks across chunk borders
// (render/touching_pairs.h) for chunks of `scene` in a 4x4x4 block, each set again in turn: its
// links dropped, then its border faces compared with its six neighbours'. Each iteration copies
// the chunk's border faces (the renderer moves them): up to 12 KB.
void bench_touching_pairs(benchmark::State& state, const Scene& scene) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    constexpr int kSide = 4, kChunks = kSide * kSide * kSide;
    GreedyMesher mesher;
    std::vector<render::TouchingFaces> faces(kChunks);
    ChunkMesh mesh, out;
    for (int i = 0; i < kChunks; ++i) {
        mesher.mesh({scene.make(uint64_t(i)), Apron::air(), reg}, mesh);
        faces[size_t(i)] = render::mark_touching_faces(mesh, mesh.block_ids(), reg, out);
    }
    const auto coord = [](int i) {
        return LodCoord{0, ChunkCoord(i % kSide, (i / kSide) % kSide, i / (kSide * kSide))};
    };
    render::TouchingPairs pairs;
    for (int i = 0; i < kChunks; ++i)
        pairs.set(coord(i), faces[size_t(i)].inside, faces[size_t(i)].border);
    uint64_t n = 0;
    for (auto _ : state) {
        const int i = int(n++ % kChunks);
        pairs.set(coord(i), faces[size_t(i)].inside, faces[size_t(i)].border);
        benchmark::DoNotOptimize(pairs.any());
    }
    state.counters["border_pairs"] = double(pairs.border_pairs());
}

// One edit and its undo per iteration, so the chunk stays the scene it started as (toggling
// blocks forever would turn any chunk into noise). `with_old`: remesh_block is told the block's
// previous id and merges only the plane sides that changed (the edit path); without it, all six
// slices are merged again (same process: the ratio of the two is what skipping saves).
void bench_remesh_edit(benchmark::State& state, const Scene& scene, bool with_old) {
    const BlockRegistry& reg = BlockRegistry::default_registry();
    Chunk chunk = scene.make(3);
    const Apron apron = Apron::air();
    GreedyMesher mesher;
    ChunkMesh mesh;
    mesher.mesh({chunk, apron, reg}, mesh);
    std::mt19937 rng(5);
    for (auto _ : state) {
        const LocalPos p(int(rng() % 32), int(rng() % 32), int(rng() % 32));
        const BlockId old = chunk.get(p);
        const BlockId now = old == kAir ? BlockId(1) : kAir; // Place stone, or dig.
        chunk.set(p, now);
        if (with_old)
            mesher.remesh_block({chunk, apron, reg}, p, old, mesh);
        else
            mesher.remesh_block({chunk, apron, reg}, p, mesh);
        chunk.set(p, old);
        if (with_old)
            mesher.remesh_block({chunk, apron, reg}, p, now, mesh);
        else
            mesher.remesh_block({chunk, apron, reg}, p, mesh);
        benchmark::DoNotOptimize(mesh.quad_count());
    }
    state.counters["per_edit"] = benchmark::Counter(double(state.iterations()) * 2,
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The whole seed scene on the engine's job system, a worker per hardware thread: what `vx mesh
// --scene seed` does. Times the batch (aprons, meshing, results applied on this thread).
void bench_seed_scene(benchmark::State& state) {
    World world;
    for (int z = 0; z < kSeedSceneSide; ++z)
        for (int x = 0; x < kSeedSceneSide; ++x)
            world.put_chunk(ChunkCoord(x, 0, z), seed_scene_chunk(ChunkCoord(x, 0, z)));
    const std::vector<ChunkCoord> coords = engine::chunk_coords(world);
    engine::JobSystem jobs(engine::batch_job_system_info());
    if (!jobs.start_error().empty()) {
        state.SkipWithError(("cannot start the worker threads: " + jobs.start_error()).c_str());
        return;
    }
    engine::RegionMesher mesher(jobs, {engine::ApronMode::Air, {}});
    MeshMap meshes;
    uint64_t tris = 0;
    for (auto _ : state) {
        const engine::RegionMeshStats s = mesher.mesh(world, coords, meshes);
        state.SetIterationTime(s.seconds);
        tris = 2 * s.quads;
    }
    state.counters["triangles"] = double(tris);
    state.counters["thesis_triangles"] = 30917848;
}

const bool registered = [] {
    MeshFn greedy = [](GreedyMesher& m, const MesherInput& in, ChunkMesh& out) { m.mesh(in, out); };
    MeshFn classic = [](GreedyMesher&, const MesherInput& in, ChunkMesh& out) { mesh_classic_greedy(in, out); };
    MeshFn culled = [](GreedyMesher&, const MesherInput& in, ChunkMesh& out) { mesh_culled(in, out); };
    for (const Scene& s : scenes())
        for (int e = 0; e < 2; ++e) {
            const std::string where = e ? "embedded" : "isolated";
            benchmark::RegisterBenchmark(("mesh/greedy/" + std::string(s.name) + "/" + where).c_str(),
                                         [&s, e, greedy](benchmark::State& st) { bench_mesher(st, s, e, greedy); })
                ->Unit(benchmark::kMicrosecond);
            benchmark::RegisterBenchmark(("mesh/classic/" + std::string(s.name) + "/" + where).c_str(),
                                         [&s, e, classic](benchmark::State& st) { bench_mesher(st, s, e, classic); })
                ->Unit(benchmark::kMicrosecond);
            if (e == 0 && std::string(s.name) != "empty" && std::string(s.name) != "solid")
                benchmark::RegisterBenchmark(("mesh/culled/" + std::string(s.name) + "/" + where).c_str(),
                                             [&s, culled](benchmark::State& st) { bench_mesher(st, s, false, culled); })
                    ->Unit(benchmark::kMicrosecond);
        }
    for (const Scene& s : scenes())
        if (std::string(s.name) != "empty" && std::string(s.name) != "solid")
            for (const bool with_old : {true, false})
                benchmark::RegisterBenchmark(
                    ((with_old ? "mesh/remesh_edit/" : "mesh/remesh_all_six/") + std::string(s.name)).c_str(),
                    [&s, with_old](benchmark::State& st) { bench_remesh_edit(st, s, with_old); })
                    ->Unit(benchmark::kMicrosecond);
    for (const Scene& s : scenes())
        if (std::string(s.name) == "see_through10" || std::string(s.name) == "terrain")
            benchmark::RegisterBenchmark(("mesh/touching_faces/" + std::string(s.name)).c_str(),
                                         [&s](benchmark::State& st) { bench_touching_faces(st, s); })
                ->Unit(benchmark::kMicrosecond);
    for (const Scene& s : scenes())
        if (std::string(s.name) == "see_through10" || std::string(s.name) == "terrain")
            benchmark::RegisterBenchmark(("mesh/touching_pairs/" + std::string(s.name)).c_str(),
                                         [&s](benchmark::State& st) { bench_touching_pairs(st, s); })
                ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("mesh/seed_scene_all_cores", bench_seed_scene)->UseManualTime()->Unit(benchmark::kMillisecond);
    return true;
}();

} // namespace
} // namespace vx::tools
