// `vx bench lod`: speed against error of levels of detail (issue 16). Terrain of --seed to
// --view-distance blocks, seen from one pose (the terrain's default view, or --eye/--target), is
// rendered at full detail (every level-0 chunk within the view distance over the terrain's whole
// height: the reference) and with LOD for each level-0 radius of --radii (the LodView cut: level 0
// within the radius, coarse levels beyond), one after the other in one run on one renderer (the
// reference first; each scene replaces the last, is built and compacted, then timed).
// Per scene: image error against full detail (RMSE, PSNR, SSIM) in flat and full shading; the
// pixels full detail hits and LOD leaves as sky (flat shading, from the G-buffer: 0 means no
// holes); GPU frame time (medians of --repeat, timestamps) and wall time; GPU memory; chunks,
// BLASes and triangles, also per level. For scale, full detail against itself with another sample
// seed (every scene uses the same seed, so noise cancels where LOD's geometry matches).
// Writes DIR/lod_report.md, DIR/lod_bench.csv and picture pairs: DIR/full_{flat,full}.png and
// DIR/lod_r<R>_{flat,full}.png.
#include <array>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_render_frames.h"
#include "cli_common.h"
#include "commands.h"
#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "render/image_metrics.h"
#include "render/renderer.h"
#include "scene_args.h"
#include "world/base/assert.h"
#include "world/base/median.h"

namespace vx::tools {
namespace {

constexpr size_t kLevels = world::kMaxLodLevel + 1;

struct BenchLodArgs {
    uint64_t seed = 1;
    int64_t view_distance = 512;
    std::string radii = "4,8,12,16";
    int vradius = 4, ring = 12;
    std::string size = "160x90", out = "lod_bench", device = "auto", eye, target;
    uint32_t repeat = 5;
    unsigned threads = 0;
};

// One scene's figures and pictures.
struct SceneRun {
    std::string name;   // "full detail" or "LOD r=R".
    int radius = -1;    // Level-0 radius, chunks (-1: full detail).
    int top_level = 0;
    uint64_t chunks = 0, triangles = 0;
    uint32_t blas = 0;  // Chunks with triangles sent to the renderer.
    std::array<engine::LevelCounts, kLevels> levels{};
    std::array<uint32_t, kLevels> level_instances{};
    std::array<uint64_t, kLevels> level_bytes{};
    uint64_t gpu_bytes = 0;                    // GpuMemoryStats::total() once built and compacted.
    double load_ms = 0;                        // Generating and meshing, every level.
    double flat_ms = -1, full_ms = -1, full_wall_ms = 0, cpu_ms = 0; // Medians.
    render::RenderImage flat, full;
    std::vector<uint8_t> hit; // Flat shading: 1 where the primary ray hit something.
};

Result<render::Camera> make_camera(const BenchLodArgs& a, const engine::LoadedScene& scene) {
    std::optional<WorldPos> eye = scene.default_eye, target = scene.default_target;
    if (!a.eye.empty() && !(eye = parse_world_pos(a.eye)))
        return Error{"--eye must be X,Y,Z (decimals, inside the world), got '" + a.eye + "'"};
    if (!a.target.empty() && !(target = parse_world_pos(a.target)))
        return Error{"--target must be X,Y,Z (decimals, inside the world), got '" + a.target + "'"};
    VX_ASSERT(eye && target); // The terrain's default view has both; run_bench_lod() checks --eye has --target.
    const glm::dvec3 fwd = world_delta(*target, *eye);
    if (glm::length(fwd) == 0.0 || glm::length(glm::cross(glm::normalize(fwd), glm::dvec3(0, 1, 0))) < 1e-6)
        return Error{"--target must differ from --eye and not lie straight above or below it"};
    render::Camera cam;
    cam.block = eye->block;
    cam.offset = glm::vec3(eye->frac);
    cam.forward = glm::vec3(fwd);
    return cam;
}

// Builds the scene on `r` (replacing the last), then renders and times it.
void run_scene(render::Renderer& r, engine::LoadedScene&& loaded, const render::RenderSettings& base,
               const render::Camera& cam, uint32_t repeat, SceneRun& out) {
    out.top_level = loaded.top_level;
    out.chunks = loaded.meshes.size() + loaded.coarse.size();
    out.triangles = loaded.triangles;
    out.levels = loaded.levels;
    out.load_ms = loaded.load_ms + loaded.mesh_ms + loaded.coarse_ms;
    r.clear_chunks();
    out.blas = engine::send_scene(loaded, r);
    loaded = {}; // The renderer keeps its own copy of every mesh; the world and meshes can go.
    render::RenderSettings flat = base, full = base;
    flat.mode = render::ShadingMode::Flat;
    full.mode = render::ShadingMode::Full;
    for (int i = 0; i < 3; ++i) // Builds, then cold BLASes compacted in frame 3: nothing of it is timed.
        bench_frame(r, flat, cam);
    const render::RenderStats& st = r.last_stats();
    out.gpu_bytes = st.memory.total();
    out.level_instances = st.level_instances;
    out.level_bytes = st.level_gpu_bytes;
    render::GBufferImage g;
    out.flat = bench_frame(r, flat, cam, &g);
    out.hit.resize(g.albedo.size());
    for (size_t i = 0; i < g.albedo.size(); ++i)
        out.hit[i] = g.albedo[i].a > 0.5f;
    std::vector<double> flat_ms, full_ms, wall, cpu;
    for (uint32_t i = 0; i < repeat; ++i) {
        bench_frame(r, flat, cam);
        flat_ms.push_back(r.last_stats().gpu_frame_ms);
    }
    out.full = bench_frame(r, full, cam); // Warm-up of the full-shading pipeline.
    for (uint32_t i = 0; i < repeat; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        out.full = bench_frame(r, full, cam);
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        full_ms.push_back(r.last_stats().gpu_frame_ms);
        cpu.push_back(r.last_stats().cpu_ms);
    }
    out.flat_ms = median(flat_ms);
    out.full_ms = median(full_ms);
    out.full_wall_ms = median(wall);
    out.cpu_ms = median(cpu);
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// Levels drawn by a scene, as "L0 n / L1 n / ..." (chunks with triangles) and their memory.
std::string level_cell(const SceneRun& s, bool memory) {
    std::string out;
    for (size_t k = 0; k < kLevels; ++k) {
        if (s.levels[k].chunks == 0)
            continue;
        out += (out.empty() ? "" : ", ") + std::string("L") + std::to_string(k) + " " +
               (memory ? fmt("%.1f", double(s.level_bytes[k]) / 1e6) : std::to_string(s.levels[k].meshed));
    }
    return out;
}

// --radii: level-0 radii, 0..64 chunks, comma separated; nullopt on anything else.
std::optional<std::vector<int>> parse_radii(const std::string& text) {
    std::vector<int> radii;
    for (const std::string& t : split_commas(text)) {
        char* end = nullptr;
        const long v = std::strtol(t.c_str(), &end, 10);
        if (t.empty() || *end != '\0' || v < 0 || v > 64)
            return std::nullopt;
        radii.push_back(int(v));
    }
    return radii;
}

// The full-detail scene: terrain of --seed to --view-distance, LOD off (the LOD scenes change
// only --lod and --radius).
SceneArgs full_detail_args(const BenchLodArgs& a) {
    SceneArgs sa;
    sa.seed = a.seed;
    sa.vradius = a.vradius;
    sa.threads = a.threads;
    sa.view_distance = a.view_distance;
    sa.lod = "off";
    sa.lod_ring = a.ring;
    return sa;
}

// Full detail, what every scene is compared with: its pictures, and for scale its full shading
// with another sample seed against itself.
struct LodReference {
    render::ImageF flat, full;
    render::RenderSettings other_seed;
    render::ImageError noise;
};

// Renders full detail (on `r`) with another sample seed; `full` is the full-detail run.
LodReference measure_reference(render::Renderer& r, const render::RenderSettings& base, const render::Camera& cam,
                               const SceneRun& full) {
    LodReference ref;
    ref.other_seed = base;
    ref.other_seed.mode = render::ShadingMode::Full;
    ref.other_seed.seed = base.seed + 1;
    ref.flat = render::to_float(full.flat);
    ref.full = render::to_float(full.full);
    ref.noise = render::compare(render::to_float(bench_frame(r, ref.other_seed, cam)), ref.full);
    return ref;
}

// The LOD scene of each radius, loaded with `jobs` and run on `r` after the last (into `runs`).
// The first load's problem (one line), or nullopt.
std::optional<std::string> run_lod_scenes(render::Renderer& r, engine::JobSystem& jobs, SceneArgs sa,
                                          const std::vector<int>& radii, const render::RenderSettings& base,
                                          const render::Camera& cam, uint32_t repeat, std::vector<SceneRun>& runs) {
    for (int radius : radii) {
        sa.lod = "on";
        sa.radius = radius;
        auto info = scene_load_info(sa);
        if (!info)
            return info.error();
        auto scene = engine::load_scene(jobs, *info);
        if (!scene)
            return scene.error();
        runs.push_back({});
        runs.back().name = "LOD r=" + std::to_string(radius);
        runs.back().radius = radius;
        run_scene(r, std::move(*scene), base, cam, repeat, runs.back());
    }
    return std::nullopt;
}

// The report's opening, up to the main table's header. `ground`: pixels full detail hits.
std::string lod_report_intro(const BenchLodArgs& a, const render::RenderSettings& base, const std::string& device,
                             uint64_t ground, const LodReference& ref) {
    return "# LOD speed against error (`vx bench lod`)\n\nTerrain seed " + std::to_string(a.seed) +
           " to " + std::to_string(a.view_distance) + " blocks, " + std::to_string(base.width) + "x" +
           std::to_string(base.height) + ", device " + device + "; level-0 vertical radius " +
           std::to_string(a.vradius) + " chunks, coarse ring " + std::to_string(a.ring) +
           ". Lights: sun and sky (no area light); full shading " + std::to_string(base.shadow_samples) +
           " shadow samples, " + std::to_string(base.max_bounces) +
           " reflections, haze on. Errors are against full detail at the same pose; frame times are "
           "GPU medians of " + std::to_string(a.repeat) +
           " frames (timestamps), wall the full-shading call's. Uncovered: pixels full detail hits "
           "and the scene leaves as sky (flat shading; of " + std::to_string(ground) +
           " ground pixels). For scale, full shading's sampling noise: full detail with sample seed " +
           std::to_string(ref.other_seed.seed) + " against seed " + std::to_string(base.seed) + ": RMSE " +
           fmt("%.4f", ref.noise.rmse) + ", SSIM " + fmt("%.4f", ref.noise.ssim) +
           " (every scene uses seed " + std::to_string(base.seed) +
           ", so where LOD's geometry matches, the noise cancels and its RMSE can be lower).\n\n" +
           "| scene | level-0 reach (blocks) | top level | chunks | BLAS | triangles | GPU MB | flat ms | "
           "full ms | full wall ms | RMSE flat | RMSE full | SSIM full | uncovered px | load ms |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
}

// One scene's row: printed and added to `md`, `levels_md` and `csv`; its pictures written.
// `full`: the full-detail run (its hits).
void report_scene(const SceneRun& s, const SceneRun& full, const LodReference& ref, uint64_t ground,
                  const BenchLodArgs& a, std::string& md, std::string& levels_md, ReportFile& csv) {
    char line[768];
    const bool is_ref = s.radius < 0;
    const render::ImageError ef = render::compare(render::to_float(s.flat), ref.flat);
    const render::ImageError eu = render::compare(render::to_float(s.full), ref.full);
    uint64_t uncovered = 0;
    for (size_t i = 0; i < s.hit.size(); ++i)
        uncovered += full.hit[i] && !s.hit[i];
    const std::string reach = is_ref ? std::to_string(a.view_distance) : std::to_string(s.radius * 32);
    std::snprintf(line, sizeof line,
                  "| %s | %s | %d | %" PRIu64 " | %u | %" PRIu64 " | %.1f | %.3f | %.3f | %.1f | %.4f | %.4f | "
                  "%.4f | %" PRIu64 " | %.0f |\n",
                  s.name.c_str(), reach.c_str(), s.top_level, s.chunks, s.blas, s.triangles,
                  double(s.gpu_bytes) / 1e6, s.flat_ms, s.full_ms, s.full_wall_ms, ef.rmse, eu.rmse, eu.ssim,
                  uncovered, s.load_ms);
    md += line;
    std::printf("  %s", line);
    levels_md += "| " + s.name + " | " + level_cell(s, false) + " | " + level_cell(s, true) + " |\n";
    csv << s.name << ',' << s.radius << ',' << s.top_level << ',' << s.chunks << ',' << s.blas << ','
        << s.triangles << ',' << s.gpu_bytes << ',' << s.flat_ms << ',' << s.full_ms << ',' << s.full_wall_ms << ','
        << s.cpu_ms << ',' << ef.rmse << ',' << eu.rmse << ',' << eu.psnr << ',' << eu.ssim << ',' << uncovered << ','
        << ground << ',' << s.load_ms << '\n';
    const std::string stem = a.out + (is_ref ? "/full" : "/lod_r" + std::to_string(s.radius));
    note_png(stem + "_flat.png", s.flat);
    note_png(stem + "_full.png", s.full);
}

// The report of `runs` (runs[0]: full detail): lod_report.md, lod_bench.csv and the pictures.
int write_lod_report(const BenchLodArgs& a, const render::RenderSettings& base, const std::string& device,
                     const LodReference& ref, const std::vector<SceneRun>& runs) {
    uint64_t ground = 0;
    for (uint8_t h : runs[0].hit)
        ground += h;
    std::string md = lod_report_intro(a, base, device, ground, ref);
    std::string levels_md = "\n## Per level\n\nChunks with triangles (BLASes) and their GPU memory (MB) by level.\n\n"
                            "| scene | BLAS by level | MB by level |\n|---|---|---|\n";
    ReportFile csv(a.out + "/lod_bench.csv");
    csv << "scene,radius,top_level,chunks,blas,triangles,gpu_bytes,flat_ms,full_ms,full_wall_ms,cpu_ms,rmse_flat,"
           "rmse_full,psnr_full,ssim_full,uncovered,ground,load_ms\n";
    for (const SceneRun& s : runs)
        report_scene(s, runs[0], ref, ground, a, md, levels_md, csv);
    md += levels_md;
    md += "\nPictures: full_flat.png and full_full.png (full detail), lod_r<R>_flat.png and lod_r<R>_full.png.\n";
    ReportFile(a.out + "/lod_report.md") << md;
    std::printf("  for scale: full shading, full detail with another sample seed: RMSE %.4f\n", ref.noise.rmse);
    csv.finish();
    std::printf("  wrote %s/lod_report.md, lod_bench.csv and PNG pairs\n", a.out.c_str());
    return report_outputs();
}

// Full detail (`full`, loaded from `sa`), then the LOD scene of each radius, one after the other
// on `r`; then the report.
int measure_lod(render::Renderer& r, engine::JobSystem& jobs, engine::LoadedScene&& full, const SceneArgs& sa,
                const std::vector<int>& radii, const render::RenderSettings& base, const render::Camera& cam,
                const BenchLodArgs& a) {
    std::vector<SceneRun> runs(1);
    runs[0].name = "full detail";
    run_scene(r, std::move(full), base, cam, a.repeat, runs[0]);
    const LodReference ref = measure_reference(r, base, cam, runs[0]);
    if (const std::optional<std::string> err = run_lod_scenes(r, jobs, sa, radii, base, cam, a.repeat, runs))
        return bad_input(*err);
    return write_lod_report(a, base, r.device().name, ref, runs);
}

int run_bench_lod(const BenchLodArgs& a) {
    render::RenderSettings base;
    const std::optional<glm::uvec2> size = parse_image_size(a.size);
    if (!size)
        return bad_input("--size must be WxH (1..16384), got '" + a.size + "'");
    base.width = size->x;
    base.height = size->y;
    const std::optional<std::vector<int>> radii = parse_radii(a.radii);
    if (!radii)
        return bad_input("--radii must be level-0 radii in chunks, 0..64, comma separated; got '" + a.radii + "'");
    if (!a.eye.empty() && a.target.empty())
        return bad_input("--eye needs --target X,Y,Z");
    const auto choice = render::parse_device_choice(a.device);
    if (!choice)
        return bad_input(choice.error());
    base.light.emission = glm::vec3(0.f); // Sun and sky light, as outdoors in the sandbox.
    SceneArgs sa = full_detail_args(a);
    if (!a.eye.empty() && !(sa.eye = parse_world_pos(a.eye)))
        return bad_input("--eye must be X,Y,Z (decimals, inside the world), got '" + a.eye + "'");
    auto full_info = scene_load_info(sa);
    if (!full_info)
        return bad_input(full_info.error());
    engine::JobSystem jobs(engine::batch_job_system_info(a.threads));
    if (const std::string why = job_system_problem(jobs.start_error()); !why.empty())
        return failed(why);
    auto full_scene = engine::load_scene(jobs, *full_info);
    if (!full_scene)
        return bad_input(full_scene.error());
    const auto cam = make_camera(a, *full_scene);
    if (!cam)
        return bad_input(cam.error());
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec)
        return bad_input("cannot create --out directory '" + a.out + "': " + ec.message());
    auto renderer = render::Renderer::create({.device = *choice});
    if (!renderer)
        return bad_input("cannot render: " + renderer.error());
    render::Renderer& r = **renderer;
    if (Status fits = r.check_frame_size(base.width, base.height); !fits) // As vx render.
        return bad_input("cannot render: " + fits.error());
    r.set_registry(full_scene->world->registry());
    std::printf("vx bench lod: %s; %ux%u on %s\n", full_scene->description.c_str(), base.width, base.height,
                r.device().name.c_str());
    return measure_lod(r, jobs, std::move(*full_scene), sa, *radii, base, *cam, a);
}

} // namespace

int run_bench_lod_command(int argc, char** argv) {
    CLI::App app{"vx bench lod: levels of detail against full detail to the same view distance", "vx bench lod"};
    BenchLodArgs a;
    app.add_option("--seed", a.seed, "Terrain seed (default 1)")
        ->check(seed_range());
    app.add_option("--view-distance", a.view_distance, "Blocks drawn from the camera, both scenes (default 512)")
        ->check(decimal_range(1, 16384, "must be 1..16384 blocks"));
    app.add_option("--radii", a.radii, "Level-0 radii of the LOD scenes, chunks, comma separated (default 4,8,12,16)");
    app.add_option("--vradius", a.vradius, "Level-0 vertical radius of the LOD scenes, chunks (default 4)")
        ->check(decimal_range(0, 64, "must be 0..64 chunks"));
    app.add_option("--lod-ring", a.ring, "Coarse levels' box half-width in their own chunks (default 12)");
    app.add_option("--size", a.size, "Image size WxH (lavapipe: keep it small, e.g. 160x90)");
    app.add_option("--eye", a.eye, "Camera X,Y,Z in blocks (default: the terrain's default view)");
    app.add_option("--target", a.target, "Point looked at, X,Y,Z in blocks");
    app.add_option("--repeat", a.repeat, "Timed frames per scene and shading (medians)")->check(CLI::Range(1u, 10000u));
    app.add_option("--threads", a.threads, "Generation and meshing threads (0 = all cores; at most 256)")
        ->check(CLI::Range(0u, unsigned(engine::kMaxWorkerThreads)));
    app.add_option("--device", a.device, "auto, cpu, gpu or a device index");
    app.add_option("--out", a.out, "Directory for the report, CSV and PNGs");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return parse_failure(app, e);
    }
    return run_bench_lod(a);
}

} // namespace vx::tools
