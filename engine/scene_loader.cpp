#include "engine/scene_loader.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <unordered_set>
#include <vector>

#include "engine/job_batch.h"
#include "render/renderer.h"
#include "world/base/assert.h"
#include "world/gen/seed_scene.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/lod/lod_cut.h"
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

// Terrain's default camera: above the surface at the origin, looking across the terrain.
void terrain_default_view(const TerrainGenerator& gen, LoadedScene& scene) {
    const int h = std::max(gen.surface_height(0, 0), gen.params().sea_level);
    const int ht = std::max(gen.surface_height(160, 160), gen.params().sea_level);
    scene.default_eye = world_pos_at({0.5, h + 40.5, 0.5});
    scene.default_target = world_pos_at({160.5, ht + 0.5, 160.5});
}

Status load_terrain(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    const TerrainGenerator gen(a.seed);
    if (!a.eye)
        terrain_default_view(gen, scene);
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

// Pool: one coarse chunk of a LOD scene, generated (generate_lod) and meshed with air aprons
// into its output slot, which exists before the batch runs (as RegionMeshJob: nothing copied).
// Keyed by the chunk at one level: a batch holds one level.
class CoarseChunkJob final : public Job {
public:
    CoarseChunkJob(LodCoord c, const ChunkGenerator& gen, const BlockRegistry& registry, const ChunkMeshFn& mesh_fn,
                   ChunkMesh& slot)
        : Job({c.chunk, JobKind::Task}), m_coord(c), m_gen(gen), m_registry(registry), m_mesh_fn(mesh_fn),
          m_slot(slot) {}
    void run(JobContext& ctx) override {
        if (ctx.is_cancelled())
            return;
        const Result<Chunk> chunk = generate_lod(m_gen, m_coord, m_registry);
        VX_ASSERT(bool(chunk)); // The built-in terrain never fails.
        static const Apron kAirApron = Apron::air();
        thread_local GreedyMesher scratch; // One per worker, reused by every job it runs.
        const MesherInput in{*chunk, kAirApron, m_registry};
        if (m_mesh_fn)
            m_mesh_fn(scratch, in, m_slot);
        else
            scratch.mesh(in, m_slot);
    }
    void complete() override {}

private:
    LodCoord m_coord;
    const ChunkGenerator& m_gen;
    const BlockRegistry& m_registry;
    const ChunkMeshFn& m_mesh_fn;
    ChunkMesh& m_slot;
};

// Generates and meshes `coarse` (any levels) into scene.coarse, one batch per level.
void make_coarse(JobSystem& jobs, LoadedScene& scene, const ChunkGenerator& gen, const ChunkMeshFn& mesh_fn,
                 const std::vector<LodCoord>& coarse) {
    for (int level = 1; level <= kMaxLodLevel; ++level) {
        std::vector<std::unique_ptr<Job>> batch;
        for (LodCoord c : coarse)
            if (c.level == level)
                batch.push_back(std::make_unique<CoarseChunkJob>(c, gen, scene.world->registry(), mesh_fn,
                                                                 scene.coarse[c])); // Slots first: stable addresses.
        if (!batch.empty())
            run_batch(jobs, std::move(batch));
    }
}

// The level-0 chunks of a full-detail view: every chunk column within the view distance, rows
// over the terrain's height and the eye's vertical box.
std::vector<ChunkCoord> full_detail_chunks(const LodView& view, ChunkCoord eye, int vradius, int64_t y_lo,
                                           int64_t y_hi) {
    const int lo = std::min(chunk_of(BlockPos(0, y_lo, 0)).y, eye.y - vradius);
    const int hi = std::max(chunk_of(BlockPos(0, y_hi, 0)).y, eye.y + vradius);
    const int h = int(view.settings().view_distance / kChunkSize) + 1;
    std::vector<ChunkCoord> out;
    for (int z = -h; z <= h; ++z)
        for (int x = -h; x <= h; ++x) {
            const ChunkCoord column(eye.x + x, eye.y, eye.z + z);
            if (view.distance({0, column}) > double(view.settings().view_distance))
                continue;
            for (int y = lo; y <= hi; ++y)
                out.push_back(ChunkCoord(column.x, y, column.z));
        }
    return out;
}

// Terrain to a view distance: with LOD, the cut of a LodView; without, full detail (the
// reference). Level-0 chunks are generated with their face neighbours, for real aprons.
Status load_terrain_view(JobSystem& jobs, LoadedScene& scene, const SceneLoadInfo& a) {
    const TerrainGenerator gen(a.seed);
    if (!a.eye)
        terrain_default_view(gen, scene);
    const WorldPos eye = a.eye ? *a.eye : *scene.default_eye;
    const glm::dvec3 viewer = glm::dvec3(eye.block) + eye.frac;
    const int64_t y_lo = std::min<int64_t>(gen.height_min(), gen.params().sea_level);
    const int64_t y_hi = std::max<int64_t>(gen.height_max(), gen.params().sea_level);
    const int r = a.radius < 0 ? 8 : a.radius;
    LodViewSettings vs;
    vs.radius0 = r;
    vs.vradius0 = a.vradius;
    vs.ring = a.lod_ring;
    // Coarse boxes reach the terrain's whole height: from the eye to its lowest and highest block.
    vs.vertical_reach = int64_t(std::ceil(std::max({viewer.y - double(y_lo), double(y_hi + 1) - viewer.y, 0.0})));
    if (a.lod && vs.vertical_reach > kMaxLodVerticalReach)
        return Error{"the eye (y " + std::to_string(eye.block.y) + ") is " + std::to_string(vs.vertical_reach) +
                     " blocks from the far side of the terrain (y " + std::to_string(y_lo) + ".." +
                     std::to_string(y_hi) + "); levels of detail reach at most " +
                     std::to_string(kMaxLodVerticalReach) + " blocks up or down"};
    vs.view_distance = a.view_distance;
    vs.max_level = a.lod ? kMaxLodLevel : 0;
    if (a.lod)
        if (const uint64_t n = lod_box_chunks(vs); n > kMaxLodBoxChunks)
            return Error{"levels of detail would hold " + std::to_string(n) + " coarse chunks around the eye (at most " +
                         std::to_string(kMaxLodBoxChunks) + "): lower --view-distance or --lod-ring, or the eye"};
    const LodView view(viewer, vs);
    std::vector<ChunkCoord> inner;
    std::vector<LodCoord> coarse;
    if (a.lod) {
        std::vector<LodCoord> cut;
        view.cut(cut);
        for (LodCoord c : cut) {
            if (c.level == 0)
                inner.push_back(c.chunk);
            else
                coarse.push_back(c);
        }
        scene.top_level = view.top_level();
    } else {
        inner = full_detail_chunks(view, chunk_of(eye.block), a.vradius, y_lo, y_hi);
    }
    std::unordered_set<ChunkCoord, ChunkCoordHash> all(inner.begin(), inner.end());
    for (ChunkCoord c : inner)
        for (int f = 0; f < 6; ++f)
            all.insert(c + face_normal(Face(f)));
    const ChunkSource source = [&gen](ChunkCoord c) { return gen.generate(c); };
    const auto t0 = std::chrono::steady_clock::now();
    make_chunks(jobs, *scene.world, source, std::vector<ChunkCoord>(all.begin(), all.end()));
    scene.load_ms = ms(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    mesh_scene(jobs, scene, a, inner);
    const auto t1 = std::chrono::steady_clock::now();
    make_coarse(jobs, scene, gen, a.mesh_fn, coarse);
    scene.coarse_ms = ms(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
    const int64_t vd = a.view_distance;
    scene.volume_box = std::pair{glm::i64vec3(eye.block.x - vd, y_lo, eye.block.z - vd),
                                 glm::i64vec3(eye.block.x + vd + 1, y_hi + 1, eye.block.z + vd + 1)};
    std::string d = "terrain seed " + std::to_string(a.seed) + " to " + std::to_string(vd) + " blocks, ";
    if (a.lod)
        d += "LOD (levels 0.." + std::to_string(scene.top_level) + ", ring " + std::to_string(a.lod_ring) + "): " +
             std::to_string(inner.size()) + " level-0 chunks within " + std::to_string(r) + " (vertical " +
             std::to_string(a.vradius) + ") of the camera's chunk, real aprons; " + std::to_string(coarse.size()) +
             " coarse chunks, air aprons";
    else
        d += "full detail: " + std::to_string(inner.size()) + " chunks, every column within the view distance over " +
             "the terrain's height (y " + std::to_string(y_lo) + ".." + std::to_string(y_hi) +
             "), generated with a ring of neighbours for the aprons";
    scene.description = d;
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
    for (const auto& [c, mesh] : scene.coarse) {
        LevelCounts& n = scene.levels[size_t(c.level)];
        ++n.chunks;
        n.meshed += mesh.quad_count() > 0;
        n.quads += mesh.quad_count();
        scene.quads += mesh.quad_count();
    }
    for (const auto& [c, mc] : scene.meshes) {
        ++scene.levels[0].chunks;
        scene.levels[0].meshed += mc.mesh.quad_count() > 0;
        scene.levels[0].quads += mc.mesh.quad_count();
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
    if (info.view_distance != 0) {
        if (info.kind != SceneKind::Terrain)
            return Error{"--view-distance needs generated terrain (--seed)"};
        if (info.view_distance < 1 || info.view_distance > 16384)
            return Error{"--view-distance must be 1..16384 blocks, got " + std::to_string(info.view_distance)};
        if (info.lod_ring < 1 || info.lod_ring > 64)
            return Error{"--lod-ring must be 1..64 chunks, got " + std::to_string(info.lod_ring)};
    }
    // Terrain and stored worlds load a box of chunks around the eye, in 32-bit chunk coordinates
    // (world/coords.h). The seed scene and raw volumes load only their own chunks: their eye (and
    // volume, raw_volume.cpp) may lie anywhere inside the world.
    const bool eye_picks_chunks = info.kind == SceneKind::Terrain || info.kind == SceneKind::StoredWorld;
    if (eye_picks_chunks && info.eye && !inside_edge_margin(info.eye->block))
        return Error{"--eye must stay 2^17 blocks inside the world's edge (|coordinate| < 2^36 - 2^17)"};
    LoadedScene scene;
    scene.world = std::make_unique<World>();
    Status s;
    switch (info.kind) {
    case SceneKind::StoredWorld: s = load_world(jobs, scene, info); break;
    case SceneKind::Terrain:
        s = info.view_distance > 0 ? load_terrain_view(jobs, scene, info) : load_terrain(jobs, scene, info);
        break;
    case SceneKind::SeedScene: s = load_seed_scene(jobs, scene, info); break;
    case SceneKind::RawVolume: s = load_raw(jobs, scene, info); break;
    }
    if (!s)
        return Error{s.error()};
    finish(scene);
    return scene;
}

uint32_t send_scene(const LoadedScene& scene, render::Renderer& renderer) {
    uint32_t sent = 0;
    for (const auto& [c, mc] : scene.meshes)
        if (mc.mesh.quad_count() > 0) {
            renderer.set_chunk(c, mc.mesh);
            ++sent;
        }
    for (const auto& [c, mesh] : scene.coarse)
        if (mesh.quad_count() > 0) {
            renderer.set_chunk(c, mesh);
            ++sent;
        }
    return sent;
}

void remesh_chunk(LoadedScene& scene, ChunkCoord c, const ChunkMeshFn& mesh_fn) {
    if (!scene.world->find_chunk(c))
        return;
    thread_local GreedyMesher scratch; // Reused across edits; main thread.
    mesh_chunk(*scene.world, c, {scene.isolated ? ApronMode::Air : ApronMode::Neighbours, mesh_fn}, scratch,
               scene.meshes[c]);
}

} // namespace vx::engine
