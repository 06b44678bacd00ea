// `vx bench render` geometry section: see bench_render_geometry.h.
#include "bench_render_geometry.h"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numeric>
#include <optional>
#include <random>
#include <tuple>
#include <vector>

#include "bench_render_frames.h"
#include "cli_common.h"
#include "world/base/median.h"
#include "world/mesh/apron.h"
#include "world/mesh/edit_mesher.h"
#include "world/mesh/reference_meshers.h"

namespace vx::tools {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

bool coord_less(ChunkCoord a, ChunkCoord b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); }

// The scene's chunks meshed by one mesher, in coordinate order (empty meshes dropped).
struct MeshedScene {
    std::vector<std::pair<ChunkCoord, ChunkMesh>> chunks;
    uint64_t quads = 0;
    std::vector<double> chunk_us; // CPU time of each mesh call giving quads (aprons made beforehand).
    double total_ms = 0;          // Of every chunk's mesh call, empty or not.
};

MeshedScene mesh_scene(const engine::LoadedScene& scene, MesherKind kind) {
    GreedyMesher greedy;
    const BlockRegistry& registry = scene.world->registry();
    MeshedScene out;
    for (const auto& entry : scene.meshes) {
        const ChunkCoord c = entry.first;
        const Chunk* chunk = scene.world->find_chunk(c);
        if (!chunk)
            continue;
        // The apron the loader meshed with: air for isolated scenes (the seed scene).
        const Apron apron = scene.isolated ? Apron::air() : make_apron(*scene.world, c);
        const MesherInput in{*chunk, apron, registry};
        ChunkMesh mesh;
        const auto t0 = Clock::now();
        if (kind == MesherKind::Greedy)
            greedy.mesh(in, mesh);
        else if (kind == MesherKind::Culled)
            mesh_culled(in, mesh);
        else
            mesh_naive(in, mesh);
        const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        out.total_ms += us * 1e-3;
        if (!mesh.empty()) // Uniform chunks (air, or solid in culled and greedy) would be the median.
            out.chunk_us.push_back(us);
        out.quads += mesh.quad_count();
        if (!mesh.empty())
            out.chunks.emplace_back(c, std::move(mesh));
    }
    std::sort(out.chunks.begin(), out.chunks.end(), [](const auto& a, const auto& b) { return coord_less(a.first, b.first); });
    return out;
}

// Medians over `repeat` frames (after one warm-up) of the GPU trace (or raster pass) time:
// time_frames() without a warm-up window, as these rows were always timed.
double trace_ms(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam, uint32_t repeat,
                render::RenderImage* image = nullptr) {
    render::RenderImage last;
    const double ms = time_frames(r, s, cam, repeat, &last).trace;
    if (image)
        *image = std::move(last);
    return ms;
}

struct TraceRows {
    render::RenderSettings flat, full, raster;
};

TraceRows trace_rows(const GeometryBenchInfo& info) {
    TraceRows t{info.base, info.base, info.base};
    t.flat.mode = render::ShadingMode::Flat;
    t.full.mode = render::ShadingMode::Full;
    t.full.shadow_samples = 4;
    t.full.max_bounces = info.reflections;
    t.full.denoise = false;
    t.full.accumulate = 1;
    t.raster.mode = render::ShadingMode::Flat;
    t.raster.pipeline = render::PipelineKind::Raster;
    return t;
}

struct MesherRow {
    const char* name = "";
    uint64_t triangles = 0;
    double mesh_median_us = 0, mesh_total_ms = 0;
    double build_ms = -1, build_wall_ms = 0;
    uint64_t blas_bytes = 0, chunk_bytes = 0;
    double flat_ms = -1, full_ms = -1, raster_ms = -1;
    int flat_diff_bytes = 0; // Against the greedy mesh's flat image.
};

MesherRow measure_mesher(render::Renderer& r, const engine::LoadedScene& scene, MesherKind kind,
                         const GeometryBenchInfo& info, render::RenderImage* flat_image) {
    MesherRow row;
    row.name = mesher_name(kind);
    const MeshedScene ms = mesh_scene(scene, kind);
    row.triangles = 2 * ms.quads;
    row.mesh_median_us = median(ms.chunk_us);
    row.mesh_total_ms = ms.total_ms;
    r.clear_chunks();
    for (const auto& [c, mesh] : ms.chunks)
        r.set_chunk(c, mesh);
    const TraceRows t = trace_rows(info);
    // Frame 1 uploads and builds every BLAS (cold: exact size, FAST_TRACE); frame 3 compacts.
    const auto t0 = Clock::now();
    bench_frame(r, t.flat, info.camera);
    row.build_wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    row.build_ms = r.last_stats().gpu_blas_ms;
    bench_frame(r, t.flat, info.camera);
    bench_frame(r, t.flat, info.camera);
    const render::GpuMemoryStats& m = r.last_stats().memory;
    row.blas_bytes = m.blas;
    row.chunk_bytes = m.blas + m.vertices + m.quads;
    row.flat_ms = trace_ms(r, t.flat, info.camera, info.repeat, flat_image);
    row.full_ms = trace_ms(r, t.full, info.camera, info.repeat);
    row.raster_ms = trace_ms(r, t.raster, info.camera, info.repeat);
    return row;
}

// One renderer's run of the edit sequence: BLAS phase per burst and trace times after k bursts.
struct EditRun {
    std::vector<double> burst_ms; // GPU BLAS phase (slice uploads + refits/builds) per burst.
    uint64_t refits = 0, builds = 0;
    double cold_flat = -1, cold_full = -1; // Before any edit (cold, compacted BLASes).
    std::vector<std::tuple<uint32_t, double, double>> trace; // k, flat ms, full ms.
};

constexpr uint32_t kEditSteps[] = {0, 1, 10, 100};

// Every step toggles one random block inside each chunk of `coords` (planes 1..31 only, so the
// chunk's six remeshed slices never read a neighbour: isolated scenes stay isolated) and
// restores the previous step's block; step 0 turns the cold chunks hot (a rebuild for both).
EditRun run_edits(engine::LoadedScene& scene, const std::vector<ChunkCoord>& coords, const GeometryBenchInfo& info,
                  uint32_t max_refits) {
    EditRun run;
    auto created = render::Renderer::create(
        {.device = info.device, .allow_refit = true, .hot_frames = 1u << 30, .max_refits = max_refits});
    if (!created) {
        std::printf("  geometry: cannot create a renderer: %s\n", created.error().c_str());
        return run;
    }
    render::Renderer& r = **created;
    r.set_registry(scene.world->registry());
    for (ChunkCoord c : coords)
        r.set_chunk(c, scene.meshes[c].mesh);
    const TraceRows t = trace_rows(info);
    for (int i = 0; i < 3; ++i)
        bench_frame(r, t.flat, info.camera); // Built, then compacted in frame 3.
    run.cold_flat = trace_ms(r, t.flat, info.camera, info.repeat);
    run.cold_full = trace_ms(r, t.full, info.camera, info.repeat);

    const BlockId stone = scene.world->registry().find("stone").value_or(BlockId(1));
    EditMesher em(scene.isolated);
    std::mt19937 rng(12345); // Same sequence for every run.
    std::uniform_int_distribution<int> inner(1, kChunkSize - 2);
    std::vector<std::optional<BlockPos>> previous(coords.size());
    auto toggle = [&](BlockPos p) {
        const BlockId id = scene.world->get_block(p) == kAir ? stone : kAir;
        const EditResult e = em.apply(*scene.world, p, id, scene.meshes);
        for (const SliceUpdate& u : e.updates)
            r.set_chunk(u.chunk, scene.meshes[u.chunk].mesh,
                        u.full ? std::span<const int>{} : std::span<const int>(u.slices.data(), size_t(u.count)));
    };
    uint32_t step = 0;
    for (uint32_t k : kEditSteps) {
        for (; step <= k; ++step) {
            for (size_t i = 0; i < coords.size(); ++i) {
                if (previous[i])
                    toggle(*previous[i]);
                previous[i] = chunk_origin(coords[i]) + BlockPos(inner(rng), inner(rng), inner(rng));
                toggle(*previous[i]);
            }
            bench_frame(r, t.flat, info.camera);
            const render::RenderStats& st = r.last_stats();
            if (step > 0) { // Step 0 rebuilds every chunk hot in both runs.
                run.burst_ms.push_back(st.gpu_blas_ms);
                run.refits += st.blas_refits;
                run.builds += st.blas_builds;
            }
        }
        run.trace.emplace_back(k, trace_ms(r, t.flat, info.camera, info.repeat),
                               trace_ms(r, t.full, info.camera, info.repeat));
    }
    for (const std::optional<BlockPos>& p : previous)
        if (p)
            toggle(*p); // The world and meshes as loaded again.
    return run;
}

std::string fmt(const char* f, auto... args) {
    char line[2048];
    std::snprintf(line, sizeof line, f, args...);
    return line;
}

std::string mesher_section(engine::LoadedScene& scene, const GeometryBenchInfo& info, std::ofstream& csv) {
    std::string md = "### Meshers\n\nThe scene's chunks meshed three ways (same aprons as loaded), each drawn by "
                     "a fresh set of cold BLASes (exact size, compacted). Mesh: CPU time of the mesher call, median "
                     "over the chunks it gave quads, and summed over all chunks; one thread, wall clock (the machine "
                     "may be shared). Build: frame 1's GPU BLAS phase "
                     "(timestamps: staging copy + every BLAS build in one call); wall: that frame's render() call. "
                     "BLAS memory after compaction (frame 3); per-chunk memory adds the quad records (and vertices "
                     "of hot chunks). Trace: GPU medians; RT full is 4 shadow samples + " +
                     std::to_string(info.reflections) + " reflection bounces; raster is Flat. Last column: bytes of the "
                     "RT flat image that differ from the greedy mesh's (same surfaces: edges and ties only).\n\n"
                     "| mesher | triangles | mesh µs/chunk | mesh ms total | build ms (GPU) | build ms (wall) | "
                     "BLAS MB | per-chunk MB | RT flat ms | RT full ms | raster ms | flat bytes ≠ greedy |\n"
                     "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto created = render::Renderer::create({.device = info.device});
    if (!created)
        return md + "(cannot create a renderer: " + created.error() + ")\n";
    render::Renderer& r = **created;
    r.set_registry(scene.world->registry());
    render::RenderImage greedy_flat;
    for (MesherKind kind : {MesherKind::Greedy, MesherKind::Culled, MesherKind::Naive}) {
        render::RenderImage flat;
        MesherRow row = measure_mesher(r, scene, kind, info, &flat);
        if (kind == MesherKind::Greedy)
            greedy_flat = flat;
        row.flat_diff_bytes = greedy_flat.rgba.size() == flat.rgba.size()
                                  ? int(std::inner_product(flat.rgba.begin(), flat.rgba.end(), greedy_flat.rgba.begin(),
                                                           0, std::plus<>(), std::not_equal_to<>()))
                                  : -1;
        const std::string line =
            fmt("| %s | %" PRIu64 " | %.1f | %.1f | %.3f | %.1f | %.2f | %.2f | %.3f | %.3f | %.3f | %d |\n", row.name,
                row.triangles, row.mesh_median_us, row.mesh_total_ms, row.build_ms, row.build_wall_ms,
                double(row.blas_bytes) / 1e6, double(row.chunk_bytes) / 1e6, row.flat_ms, row.full_ms, row.raster_ms,
                row.flat_diff_bytes);
        md += line;
        std::printf("  geometry %s", line.c_str());
        csv << "mesher," << row.name << ',' << row.triangles << ',' << row.mesh_median_us << ',' << row.mesh_total_ms
            << ',' << row.build_ms << ',' << row.build_wall_ms << ',' << row.blas_bytes << ',' << row.chunk_bytes << ','
            << row.flat_ms << ',' << row.full_ms << ',' << row.raster_ms << '\n';
    }
    return md;
}

std::string edit_section(engine::LoadedScene& scene, const GeometryBenchInfo& info, std::ofstream& csv) {
    std::vector<ChunkCoord> coords;
    for (const auto& [c, mc] : scene.meshes)
        if (!mc.mesh.empty() && scene.world->find_chunk(c))
            coords.push_back(c);
    std::sort(coords.begin(), coords.end(), coord_less);
    const EditRun refit = run_edits(scene, coords, info, 1u << 30);
    const EditRun rebuild = run_edits(scene, coords, info, 0);
    std::string md = fmt(
        "\n### Refit against rebuild\n\nGreedy meshes; a burst toggles one random block inside each of the %zu "
        "non-empty chunks and restores the previous burst's block, remeshed through world::EditMesher (six slices "
        "each), sent as set_chunk(changed slices). Burst 0 turns the cold chunks hot (a rebuild in both runs). "
        "Refit run: every later burst refits (max_refits unlimited) unless a slice outgrows its spare slots; "
        "rebuild run: max_refits = 0, every burst rebuilds the hot BLASes (same layout and flags). Burst cost: GPU "
        "BLAS phase (timestamps: slice uploads + refits or builds), median over %zu bursts; trace times after k "
        "bursts, medians of %u frames.\n\n",
        coords.size(), refit.burst_ms.size(), info.repeat);
    md += fmt("| run | burst ms (GPU) | per chunk µs | refits | builds |\n|---|---|---|---|---|\n");
    for (const EditRun* run : {&refit, &rebuild}) {
        const char* name = run == &refit ? "refit" : "rebuild";
        const double ms = median(run->burst_ms);
        md += fmt("| %s | %.3f | %.1f | %" PRIu64 " | %" PRIu64 " |\n", name, ms,
                  coords.empty() ? 0.0 : ms * 1e3 / double(coords.size()), run->refits, run->builds);
        csv << "burst," << name << ',' << ms << ',' << run->refits << ',' << run->builds << '\n';
    }
    md += fmt("\nTrace after k bursts (before any edit, cold: RT flat %.3f ms, RT full %.3f ms in the refit run).\n\n"
              "| k | refit: RT flat ms | rebuild: RT flat ms | flat refit/rebuild | refit: RT full ms | rebuild: "
              "RT full ms | full refit/rebuild |\n|---|---|---|---|---|---|---|\n",
              refit.cold_flat, refit.cold_full);
    for (size_t i = 0; i < refit.trace.size() && i < rebuild.trace.size(); ++i) {
        const auto [k, ff, fu] = refit.trace[i];
        const auto [k2, bf, bu] = rebuild.trace[i];
        (void)k2;
        md += fmt("| %u | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", k, ff, bf, bf > 0 ? ff / bf : 0.0, fu, bu,
                  bu > 0 ? fu / bu : 0.0);
        csv << "trace," << k << ',' << ff << ',' << bf << ',' << fu << ',' << bu << '\n';
    }
    std::printf("%s", md.c_str());
    return md;
}

} // namespace

std::string run_geometry_bench(engine::LoadedScene& scene, const GeometryBenchInfo& info) {
    ReportFile csv(info.out + "/geometry.csv");
    csv << "# mesher,name,triangles,mesh_us_median,mesh_ms_total,build_ms_gpu,build_ms_wall,blas_bytes,chunk_bytes,"
           "flat_ms,full_ms,raster_ms\n# burst,run,median_ms,refits,builds\n"
           "# trace,k,refit_flat_ms,rebuild_flat_ms,refit_full_ms,rebuild_full_ms\n";
    std::string md = "\n## Geometry\n\n";
    md += mesher_section(scene, info, csv);
    md += edit_section(scene, info, csv);
    return md;
}

} // namespace vx::tools
