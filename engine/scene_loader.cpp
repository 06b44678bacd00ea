#include "engine/scene_loader.h"

#include <algorithm>
#include <functional>
#include <vector>

#include "engine/job_batch.h"
#include "world/gen/seed_scene.h"
#include "world/gen/terrain.h"
#include "world/store/store_open.h"

namespace vx::engine {
namespace {

using namespace vx::world;

// A stored world larger than this is loaded only around the camera.
constexpr uint64_t kMaxWorldChunks = 20000;

using ChunkSource = std::function<Chunk(ChunkCoord)>;

// Pool: makes one chunk with a pure function of its coordinate (terrain, the seed scene).
class MakeChunkJob final : public Job {
public:
    MakeChunkJob(ChunkCoord c, const ChunkSource& source, World& world)
        : Job({c, JobKind::Generate}), m_source(source), m_world(world) {}
    void run(JobContext& ctx) override {
        if (!ctx.is_cancelled())
            m_chunk = m_source(key().chunk);
    }
    void complete() override { m_world.put_chunk(key().chunk, std::move(m_chunk)); }

private:
    const ChunkSource& m_source;
    World& m_world;
    Chunk m_chunk;
};

// I/O lane: reads one stored chunk (the store is used from that thread only).
class ReadChunkJob final : public Job {
public:
    ReadChunkJob(ChunkCoord c, ChunkStore& store, World& world, uint64_t& corrupt, std::string& failure)
        : Job({c, JobKind::Load}), m_store(store), m_world(world), m_corrupt(corrupt), m_failure(failure) {}
    void run(JobContext& ctx) override {
        if (!ctx.is_cancelled())
            m_load = m_store.load(key().chunk);
    }
    void complete() override {
        if (!m_load) {
            if (m_failure.empty())
                m_failure = m_load.error();
        } else if (m_load->state == LoadState::Present) {
            m_world.put_chunk(key().chunk, std::move(*m_load->chunk));
        } else {
            ++m_corrupt;
        }
    }

private:
    ChunkStore& m_store;
    World& m_world;
    uint64_t& m_corrupt;
    std::string& m_failure;
    Result<ChunkLoad> m_load{Error{"not run"}};
};

double ms(double seconds) { return seconds * 1e3; }

void make_chunks(JobSystem& jobs, World& world, const ChunkSource& source, const std::vector<ChunkCoord>& coords) {
    std::vector<std::unique_ptr<Job>> batch;
    batch.reserve(coords.size());
    for (ChunkCoord c : coords)
        batch.push_back(std::make_unique<MakeChunkJob>(c, source, world));
    run_batch(jobs, std::move(batch));
}

void mesh_scene(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& info, const std::vector<ChunkCoord>& coords) {
    RegionMesher mesher(jobs, {scene.isolated ? ApronMode::Air : ApronMode::Neighbours, info.mesh_fn});
    scene.mesh_ms = ms(mesher.mesh(*scene.world, coords, scene.meshes).seconds);
}

bool near(ChunkCoord c, ChunkCoord centre, int radius, int vradius) {
    const ChunkCoord d = glm::abs(c - centre);
    return d.x <= radius && d.z <= radius && d.y <= vradius;
}

Status load_terrain(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    const TerrainGenerator gen(a.seed);
    if (!a.eye) {
        // Default: above the surface at the origin, looking across the terrain.
        const int h = std::max(gen.surface_height(0, 0), gen.params().sea_level);
        const int ht = std::max(gen.surface_height(160, 160), gen.params().sea_level);
        scene.default_eye = world_pos_at({0.5, h + 40.5, 0.5});
        scene.default_target = world_pos_at({160.5, ht + 0.5, 160.5});
    }
    const ChunkCoord centre = chunk_of(a.eye ? a.eye->block : scene.default_eye->block);
    const int r = a.radius < 0 ? 8 : a.radius;
    std::vector<ChunkCoord> all, inner;
    // One ring more than is meshed, so the meshed chunks' aprons hold real neighbours.
    for (int z = -r - 1; z <= r + 1; ++z)
        for (int y = -a.vradius - 1; y <= a.vradius + 1; ++y)
            for (int x = -r - 1; x <= r + 1; ++x) {
                const ChunkCoord c = centre + ChunkCoord(x, y, z);
                all.push_back(c);
                if (near(c, centre, r, a.vradius))
                    inner.push_back(c);
            }
    const ChunkSource source = [&gen](ChunkCoord c) { return gen.generate(c); };
    const auto t0 = std::chrono::steady_clock::now();
    make_chunks(jobs, *scene.world, source, all);
    scene.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mesh_scene(jobs, scene, a, inner);
    scene.description = "terrain seed " + std::to_string(a.seed) + ": " + std::to_string(inner.size()) +
                        " chunks within " + std::to_string(r) + " (vertical " + std::to_string(a.vradius) +
                        ") of the camera's chunk, generated with a ring of neighbours for the aprons";
    return {};
}

Status load_world(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    auto store = open_store({.name = a.world_path, .read_only = true, .create = false, .listen = false});
    if (!store)
        return Error{store.error()};
    auto coords = (*store)->list_coords();
    if (!coords)
        return Error{coords.error()};
    const bool all = a.radius < 0 && coords->size() <= kMaxWorldChunks;
    const int r = a.radius < 0 ? 8 : a.radius;
    if (!all) {
        const ChunkCoord centre = a.eye ? chunk_of(a.eye->block) : ChunkCoord(0);
        std::erase_if(*coords, [&](ChunkCoord c) { return !near(c, centre, r, a.vradius); });
    }
    uint64_t corrupt = 0;
    std::string failure;
    std::vector<std::unique_ptr<Job>> batch;
    for (ChunkCoord c : *coords)
        batch.push_back(std::make_unique<ReadChunkJob>(c, **store, *scene.world, corrupt, failure));
    scene.load_ms = ms(run_batch(jobs, std::move(batch)).seconds);
    if (!failure.empty())
        return Error{failure};
    const std::vector<ChunkCoord> loaded = chunk_coords(*scene.world);
    mesh_scene(jobs, scene, a, loaded);
    scene.description = "world " + a.world_path + ": " +
                        (all ? std::string("every stored chunk (") + std::to_string(loaded.size()) + ")"
                             : std::to_string(loaded.size()) + " stored chunks within " + std::to_string(r) +
                                   " (vertical " + std::to_string(a.vradius) + ") of the camera's chunk") +
                        (corrupt ? ", " + std::to_string(corrupt) + " corrupt skipped" : "") +
                        ", meshed with neighbours' aprons";
    return {};
}

Status load_seed_scene(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    const auto block = scene.world->registry().find(a.seed_block);
    if (!block)
        return Error{"unknown block '" + a.seed_block + "'"};
    scene.isolated = true; // The thesis meshes each chunk padded with air.
    std::vector<ChunkCoord> coords;
    for (int z = 0; z < kSeedSceneSide; ++z)
        for (int x = 0; x < kSeedSceneSide; ++x)
            coords.push_back(ChunkCoord(x, 0, z));
    const ChunkSource source = [id = *block](ChunkCoord c) { return seed_scene_chunk(c, kSeedSceneSeed, id); };
    const auto t0 = std::chrono::steady_clock::now();
    make_chunks(jobs, *scene.world, source, coords);
    scene.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mesh_scene(jobs, scene, a, coords);
    scene.description = "thesis seed scene (" + a.seed_block + "): " + std::to_string(coords.size()) +
                        " chunks, 10% random, chunks isolated as in the thesis";
    return {};
}

Status load_raw(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = load_raw_volume(a.raw_path, a.raw, *scene.world);
    if (!r)
        return Error{r.error()};
    scene.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::vector<ChunkCoord> coords = chunk_coords(*scene.world);
    mesh_scene(jobs, scene, a, coords);
    scene.description = "raw volume " + a.raw_path + ": " + std::to_string(coords.size()) + " chunks";
    scene.volume_box = std::pair{a.raw.origin, a.raw.origin + a.raw.dims}; // The default view frames the volume.
    return {};
}

void finish(LoadedScene& scene) {
    bool first = true;
    for (const auto& [c, mc] : scene.meshes) {
        scene.quads += mc.mesh.quad_count();
        const glm::i64vec3 lo = chunk_origin(c), hi = lo + glm::i64vec3(kChunkSize);
        scene.box_min = first ? lo : glm::min(scene.box_min, lo);
        scene.box_max = first ? hi : glm::max(scene.box_max, hi);
        first = false;
    }
    scene.triangles = 2 * scene.quads;
    if (scene.volume_box) {
        scene.box_min = scene.volume_box->first;
        scene.box_max = scene.volume_box->second;
    }
}

} // namespace

WorldPos world_pos_at(glm::dvec3 p) {
    const glm::dvec3 f = glm::floor(p);
    return {glm::i64vec3(f), p - f};
}

Result<LoadedScene> load_scene(JobSystem& jobs, const SceneLoadInfo& info) {
    if (info.radius > 64 || info.vradius < 0 || info.vradius > 64)
        return Error{"--radius and --vradius must be 0..64 chunks"};
    LoadedScene scene;
    scene.world = std::make_unique<World>();
    Status s;
    switch (info.kind) {
    case SceneKind::StoredWorld: s = load_world(jobs, scene, info); break;
    case SceneKind::Terrain: s = load_terrain(jobs, scene, info); break;
    case SceneKind::SeedScene: s = load_seed_scene(jobs, scene, info); break;
    case SceneKind::RawVolume: s = load_raw(jobs, scene, info); break;
    }
    if (!s)
        return Error{s.error()};
    finish(scene);
    return scene;
}

void remesh_chunk(LoadedScene& scene, ChunkCoord c, const ChunkMeshFn& mesh_fn) {
    if (!scene.world->find_chunk(c))
        return;
    thread_local GreedyMesher scratch; // Reused across edits; main thread.
    mesh_chunk(*scene.world, c, {scene.isolated ? ApronMode::Air : ApronMode::Neighbours, mesh_fn}, scratch,
               scene.meshes[c]);
}

} // namespace vx::engine
