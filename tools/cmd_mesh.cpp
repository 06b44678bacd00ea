// `vx mesh`: read a raw volume (or the thesis's seed scene), apply edits through the incremental
// path, mesh, summarise, and optionally export OBJ.
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "commands.h"
#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "world/io/obj_export.h"
#include "world/io/raw_volume.h"
#include "world/mesh/reference_meshers.h"

namespace vx::tools {
namespace {

using namespace vx::world;

struct Edit {
    BlockPos pos;
    BlockId id;
};

// One `x y z id` per line, world coordinates; '#' starts a comment.
Result<std::vector<Edit>> read_edits(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        return Error{"cannot open edits file '" + path + "'"};
    std::vector<Edit> edits;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (const size_t hash = line.find('#'); hash != std::string::npos)
            line.resize(hash);
        std::istringstream ss(line);
        long long x, y, z, id;
        if (!(ss >> x)) {
            if (line.find_first_not_of(" \t\r") == std::string::npos)
                continue;
            return Error{path + ":" + std::to_string(n) + ": expected 'x y z id'"};
        }
        std::string rest;
        if (!(ss >> y >> z >> id) || (ss >> rest))
            return Error{path + ":" + std::to_string(n) + ": expected 'x y z id'"};
        if (id < 0 || id > 0xFFFF)
            return Error{path + ":" + std::to_string(n) + ": block id " + std::to_string(id) + " out of range 0..65535"};
        if (!in_world(BlockPos(x, y, z)))
            return Error{path + ":" + std::to_string(n) + ": position outside the world (|coordinate| < 2^36)"};
        edits.push_back({BlockPos(x, y, z), BlockId(id)});
    }
    if (in.bad() || !in.eof()) // A folder opens, then every read fails: it read as no edits.
        return Error{"cannot read edits file '" + path + "'"};
    return edits;
}

struct MeshArgs {
    std::string raw, dims, type = "u8", origin = "0,0,0", edits, mesher = "greedy", obj, scene;
    unsigned threads = 0;
};

// 30917848 -> "30,917,848".
std::string group(uint64_t v) {
    const std::string digits = std::to_string(v);
    std::string out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0)
            out.push_back(',');
        out.push_back(digits[i]);
    }
    return out;
}

// Which mesher `--mesher` names: empty for the engine's greedy one, else a reference mesher.
engine::ChunkMeshFn mesh_fn_of(const std::string& mesher) {
    if (mesher == "culled")
        return [](GreedyMesher&, const MesherInput& in, ChunkMesh& out) { mesh_culled(in, out); };
    if (mesher == "naive")
        return [](GreedyMesher&, const MesherInput& in, ChunkMesh& out) { mesh_naive(in, out); };
    return {};
}

// The scene `a` names, checked (one-line errors).
Result<engine::SceneLoadInfo> load_info_of(const MeshArgs& a) {
    engine::SceneLoadInfo info;
    info.mesh_fn = mesh_fn_of(a.mesher);
    if (!a.scene.empty()) {
        if (a.scene != "seed")
            return Error{"unknown scene '" + a.scene + "' (known: seed)"};
        if (!a.raw.empty())
            return Error{"--scene and --raw are exclusive"};
        info.kind = engine::SceneKind::SeedScene; // Stone, as the thesis; chunks padded with air.
        return info;
    }
    if (a.raw.empty() || a.dims.empty())
        return Error{"need --raw FILE --dims X,Y,Z (or --scene seed)"};
    const auto dims = parse_i64vec3(a.dims);
    if (!dims)
        return Error{"--dims must be X,Y,Z (integers), got '" + a.dims + "'"};
    const auto origin = parse_i64vec3(a.origin);
    if (!origin)
        return Error{"--origin must be X,Y,Z (integers), got '" + a.origin + "'"};
    info.kind = engine::SceneKind::RawVolume;
    info.raw_path = a.raw;
    info.raw = {*dims, a.type == "u16" ? RawType::U16 : RawType::U8, *origin};
    return info;
}

// Applies the edits: the incremental six-slice path (greedy), or a full remesh of the touched
// chunks with the reference mesher. Returns the slices the incremental path remeshed.
uint64_t apply_edits(engine::LoadedScene& scene, const std::vector<Edit>& edits, const engine::ChunkMeshFn& fn) {
    World& world = *scene.world;
    EditMesher em(scene.isolated);
    GreedyMesher scratch;
    uint64_t slices = 0;
    for (const Edit& e : edits) {
        if (!fn) {
            slices += uint64_t(em.apply(world, e.pos, e.id, scene.meshes).slices_remeshed);
            continue;
        }
        world.set_block(e.pos, e.id);
        const ChunkCoord c = chunk_of(e.pos);
        // An isolated scene's chunks are meshed alone (air aprons), as the greedy edit path does.
        const engine::ApronMode apron = scene.isolated ? engine::ApronMode::Air : engine::ApronMode::Neighbours;
        for (int f = -1; f < (scene.isolated ? 0 : 6); ++f) {
            if (f >= 0 && !has_neighbour(c, Face(f)))
                continue; // The world's edge: nothing beyond it to remesh.
            const ChunkCoord n = f < 0 ? c : c + face_normal(Face(f));
            if (world.find_chunk(n))
                engine::mesh_chunk(world, n, {apron, fn}, scratch, scene.meshes[n]);
        }
    }
    return slices;
}

int run_mesh(const MeshArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!a.obj.empty()) {
        if (const std::string why = output_file_problem(a.obj); !why.empty())
            return bad_input("--obj: " + why);
        for (const std::string& out : {a.obj, mtl_path_for(a.obj)})
            if (const std::string in = output_overwrites(out, {a.raw, a.edits}); !in.empty())
                return bad_input("--obj writes '" + out + "', which is '" + in + "', an input: it would be replaced");
    }
    const auto info = load_info_of(a);
    if (!info)
        return bad_input(info.error());
    std::vector<Edit> edits;
    if (!a.edits.empty()) {
        auto e = read_edits(a.edits);
        if (!e)
            return bad_input(e.error());
        edits = std::move(*e);
    }
    const double edits_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // The process's one job system, a worker per thread asked for (the main thread only waits).
    engine::JobSystem jobs(engine::batch_job_system_info(a.threads));
    if (const std::string why = job_system_problem(jobs.start_error()); !why.empty())
        return failed(why);
    const int threads = jobs.worker_count();
    auto scene = engine::load_scene(jobs, *info);
    if (!scene)
        return bad_input(scene.error());
    const double load_ms = edits_ms + scene->load_ms, mesh_ms = scene->mesh_ms;

    const auto te = std::chrono::steady_clock::now();
    const uint64_t slices = apply_edits(*scene, edits, info->mesh_fn);
    const double edit_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - te).count();

    uint64_t quads = 0;
    for (auto& [c, mc] : scene->meshes)
        quads += mc.mesh.quad_count();
    const size_t chunks = scene->meshes.size();
    std::printf("vx mesh: %zu chunks, %s quads, %s triangles (%s mesher%s)\n", chunks, group(quads).c_str(),
                group(2 * quads).c_str(), a.mesher.c_str(), scene->isolated ? ", chunks isolated as in the thesis" : "");
    if (a.scene == "seed")
        std::printf("  thesis seed scene: 30,917,848 triangles\n");
    std::printf("  load %.1f ms, mesh %.1f ms on %d threads (%.1f us per chunk per thread)\n", load_ms, mesh_ms,
                threads, chunks == 0 ? 0.0 : mesh_ms * 1e3 * threads / double(chunks));
    if (!edits.empty())
        std::printf("  %zu edits in %.2f ms (%.2f us per edit, %" PRIu64 " slices remeshed)\n", edits.size(),
                    edit_s * 1e3, edit_s * 1e6 / double(edits.size()), slices);
    if (!a.obj.empty()) {
        auto r = write_obj(a.obj, scene->meshes, scene->world->registry());
        if (!r)
            return bad_input(r.error());
        std::printf("  wrote %s (%s quads)\n", a.obj.c_str(), group(r->quads).c_str());
    }
    return kExitOk;
}

} // namespace

void add_mesh_command(CLI::App& app, std::function<int()>& action) {
    auto args = std::make_shared<MeshArgs>();
    CLI::App* cmd = app.add_subcommand("mesh", "Mesh a raw block volume (or the thesis seed scene) and summarise");
    cmd->add_option("--raw", args->raw, "Raw volume of block ids: x fastest, then y, then z; y up; little-endian");
    cmd->add_option("--dims", args->dims, "Volume size X,Y,Z in blocks");
    cmd->add_option("--type", args->type, "Block id type")->check(CLI::IsMember({"u8", "u16"}));
    cmd->add_option("--origin", args->origin, "World position X,Y,Z of the volume's first block (64-bit)");
    cmd->add_option("--edits", args->edits, "Text file of edits, one 'x y z id' per line (world coordinates)");
    cmd->add_option("--mesher", args->mesher, "Mesher")->check(CLI::IsMember({"greedy", "culled", "naive"}));
    cmd->add_option("--obj", args->obj, "Write a Wavefront OBJ (+ .mtl) here");
    cmd->add_option("--scene", args->scene, "Built-in scene instead of --raw: 'seed' (thesis: 1024 chunks, 10% random)");
    cmd->add_option("--threads", args->threads, "Meshing threads (0 = all cores; at most 256)")
        ->check(CLI::Range(0u, unsigned(engine::kMaxWorkerThreads)));
    cmd->callback([args, &action] { action = [args] { return run_mesh(*args); }; });
}

} // namespace vx::tools
