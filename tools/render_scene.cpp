#include "render_scene.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <thread>
#include <vector>

#include "cli_common.h"
#include "parallel_mesh.h"
#include "world/io/raw_volume.h"
#include "world/gen/seed_scene.h"
#include "world/store/sqlite_store.h"
#include "world/gen/terrain.h"

namespace vx::tools {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// A stored world larger than this is loaded only around the camera.
constexpr uint64_t kMaxWorldChunks = 20000;

// "-12.375" -> block -13, frac 0.625. Integer part by strtoll (exact), fraction by strtod.
std::optional<std::pair<int64_t, double>> parse_coord(const std::string& t) {
    if (t.empty() || t.find_first_of("eExXpP") != std::string::npos)
        return std::nullopt;
    const bool neg = t[0] == '-';
    const size_t dot = t.find('.');
    const std::string ip = t.substr(0, dot), fp = dot == std::string::npos ? "" : t.substr(dot + 1);
    if (fp.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    errno = 0;
    char* end = nullptr;
    const bool int_empty = ip.empty() || ip == "-" || ip == "+";
    const long long i = int_empty ? 0 : std::strtoll(ip.c_str(), &end, 10);
    if (errno != 0 || (!int_empty && *end != '\0') || (int_empty && fp.empty()))
        return std::nullopt;
    const double f = fp.empty() ? 0.0 : std::strtod(("0." + fp).c_str(), nullptr);
    if (f == 0.0)
        return std::pair<int64_t, double>{i, 0.0};
    // Negative: -12.375 = -13 + 0.625.
    return neg ? std::pair<int64_t, double>{i - 1, 1.0 - f} : std::pair<int64_t, double>{i, f};
}


// Fills `scene.meshes` for `coords` and meshes them in parallel.
void mesh_all(RenderScene& scene, const std::vector<ChunkCoord>& coords, unsigned threads) {
    std::vector<MeshJob> jobs;
    for (ChunkCoord c : coords)
        scene.meshes[c];
    for (ChunkCoord c : coords) {
        MeshedChunk& mc = scene.meshes[c];
        mc.apron = scene.isolated ? Apron::air() : make_apron(*scene.world, c);
        jobs.push_back({c, scene.world->find_chunk(c), &mc});
    }
    scene.mesh_ms = mesh_parallel(jobs, scene.world->registry(), MeshMode::Greedy, threads) * 1e3;
}

// Generates the chunks of `coords` on all cores (terrain generation is pure).
void generate(World& world, const TerrainGenerator& gen, const std::vector<ChunkCoord>& coords, unsigned threads) {
    std::vector<Chunk> out(coords.size());
    parallel_for(coords.size(), threads, [&](size_t i) { out[i] = gen.generate(coords[i]); });
    for (size_t i = 0; i < coords.size(); ++i)
        world.put_chunk(coords[i], std::move(out[i]));
}

bool near(ChunkCoord c, ChunkCoord centre, int radius, int vradius) {
    const ChunkCoord d = glm::abs(c - centre);
    return d.x <= radius && d.z <= radius && d.y <= vradius;
}

Status load_terrain(RenderScene& scene, const RenderSceneArgs& a) {
    const TerrainGenerator gen(*a.seed);
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
    const auto t0 = Clock::now();
    generate(*scene.world, gen, all, a.threads);
    scene.load_ms = ms_since(t0);
    mesh_all(scene, inner, a.threads);
    scene.description = "terrain seed " + std::to_string(*a.seed) + ": " + std::to_string(inner.size()) +
                        " chunks within " + std::to_string(r) + " (vertical " + std::to_string(a.vradius) +
                        ") of the camera's chunk, generated with a ring of neighbours for the aprons";
    return {};
}

Status load_world(RenderScene& scene, const RenderSceneArgs& a) {
    auto store = SqliteStore::open({.path = a.world_path, .read_only = true, .create = false});
    if (!store)
        return Error{store.error()};
    auto coords = (*store)->list_coords();
    if (!coords)
        return Error{coords.error()};
    const bool all = a.radius < 0 && coords->size() <= kMaxWorldChunks;
    const int r = a.radius < 0 ? 8 : a.radius;
    if (!all) {
        ChunkCoord centre{0};
        if (a.eye)
            centre = chunk_of(a.eye->block);
        std::erase_if(*coords, [&](ChunkCoord c) { return !near(c, centre, r, a.vradius); });
    }
    const auto t0 = Clock::now();
    uint64_t corrupt = 0;
    for (ChunkCoord c : *coords) {
        auto load = (*store)->load(c);
        if (!load)
            return Error{load.error()};
        if (load->state == LoadState::Present)
            scene.world->put_chunk(c, std::move(*load->chunk));
        else
            ++corrupt;
    }
    scene.load_ms = ms_since(t0);
    std::vector<ChunkCoord> loaded;
    scene.world->for_each_chunk([&](ChunkCoord c, const Chunk&) { loaded.push_back(c); });
    mesh_all(scene, loaded, a.threads);
    scene.description = "world " + a.world_path + ": " +
                        (all ? std::string("every stored chunk (") + std::to_string(loaded.size()) + ")"
                             : std::to_string(loaded.size()) + " stored chunks within " + std::to_string(r) +
                                   " (vertical " + std::to_string(a.vradius) + ") of the camera's chunk") +
                        (corrupt ? ", " + std::to_string(corrupt) + " corrupt skipped" : "") +
                        ", meshed with neighbours' aprons";
    return {};
}

Status load_seed_scene(RenderScene& scene, const RenderSceneArgs& a) {
    const auto block = scene.world->registry().find(a.scene_block);
    if (!block)
        return Error{"unknown block '" + a.scene_block + "'"};
    scene.isolated = true; // The thesis meshes each chunk padded with air.
    const auto t0 = Clock::now();
    std::vector<ChunkCoord> coords;
    for (int z = 0; z < kSeedSceneSide; ++z)
        for (int x = 0; x < kSeedSceneSide; ++x) {
            coords.push_back(ChunkCoord(x, 0, z));
            scene.world->put_chunk(coords.back(), seed_scene_chunk(coords.back(), kSeedSceneSeed, *block));
        }
    scene.load_ms = ms_since(t0);
    mesh_all(scene, coords, a.threads);
    scene.description = "thesis seed scene (" + a.scene_block + "): " + std::to_string(coords.size()) +
                        " chunks, 10% random, chunks isolated as in the thesis";
    return {};
}

Status load_raw(RenderScene& scene, const RenderSceneArgs& a) {
    const auto dims = parse_i64vec3(a.dims);
    if (!dims)
        return Error{"--dims must be X,Y,Z (integers), got '" + a.dims + "'"};
    const auto origin = parse_i64vec3(a.origin);
    if (!origin)
        return Error{"--origin must be X,Y,Z (integers), got '" + a.origin + "'"};
    const auto t0 = Clock::now();
    auto r = load_raw_volume(a.raw, {*dims, a.type == "u16" ? RawType::U16 : RawType::U8, *origin}, *scene.world);
    if (!r)
        return Error{r.error()};
    scene.load_ms = ms_since(t0);
    std::vector<ChunkCoord> coords;
    scene.world->for_each_chunk([&](ChunkCoord c, const Chunk&) { coords.push_back(c); });
    mesh_all(scene, coords, a.threads);
    scene.description = "raw volume " + a.raw + ": " + std::to_string(coords.size()) + " chunks";
    scene.volume_box = std::pair{*origin, *origin + *dims}; // The default view frames the volume.
    return {};
}

void finish(RenderScene& scene) {
    bool first = true;
    for (const auto& [c, mc] : scene.meshes) {
        scene.triangles += 2 * uint64_t(mc.mesh.quad_count());
        const glm::i64vec3 lo = chunk_origin(c), hi = lo + glm::i64vec3(kChunkSize);
        scene.box_min = first ? lo : glm::min(scene.box_min, lo);
        scene.box_max = first ? hi : glm::max(scene.box_max, hi);
        first = false;
    }
    if (scene.volume_box) {
        scene.box_min = scene.volume_box->first;
        scene.box_max = scene.volume_box->second;
    }
}

} // namespace

std::optional<WorldPos> parse_world_pos(const std::string& s) {
    const auto parts = split_commas(s);
    if (parts.size() != 3)
        return std::nullopt;
    WorldPos p;
    for (int i = 0; i < 3; ++i) {
        const auto c = parse_coord(parts[i]);
        if (!c || !in_world(c->first))
            return std::nullopt;
        p.block[i] = c->first;
        p.frac[i] = c->second;
    }
    return p;
}

glm::dvec3 world_delta(const WorldPos& a, const WorldPos& b) {
    return glm::dvec3(a.block - b.block) + (a.frac - b.frac);
}

WorldPos world_pos_at(glm::dvec3 p) {
    const glm::dvec3 f = glm::floor(p);
    return {glm::i64vec3(f), p - f};
}

Result<RenderScene> build_render_scene(const RenderSceneArgs& a) {
    const int sources = int(!a.world_path.empty()) + int(a.seed.has_value()) + int(!a.scene.empty()) + int(!a.raw.empty());
    if (sources != 1)
        return Error{"name exactly one scene: --world PATH, --seed N, --scene seed or --raw FILE --dims X,Y,Z"};
    if (!a.scene.empty() && a.scene != "seed")
        return Error{"unknown scene '" + a.scene + "' (known: seed)"};
    if (!a.raw.empty() && a.dims.empty())
        return Error{"--raw needs --dims X,Y,Z"};
    if (a.radius > 64 || a.vradius < 0 || a.vradius > 64)
        return Error{"--radius and --vradius must be 0..64 chunks"};
    RenderScene scene;
    scene.world = std::make_unique<World>();
    Status s = !a.world_path.empty() ? load_world(scene, a)
               : a.seed              ? load_terrain(scene, a)
               : !a.scene.empty()    ? load_seed_scene(scene, a)
                                     : load_raw(scene, a);
    if (!s)
        return Error{s.error()};
    finish(scene);
    return scene;
}

void remesh_chunk(RenderScene& scene, ChunkCoord c) {
    MeshedChunk& mc = scene.meshes[c];
    mc.apron = scene.isolated ? Apron::air() : make_apron(*scene.world, c);
    std::vector<MeshJob> one{{c, scene.world->find_chunk(c), &mc}};
    mesh_parallel(one, scene.world->registry(), MeshMode::Greedy, 1);
}

} // namespace vx::tools
