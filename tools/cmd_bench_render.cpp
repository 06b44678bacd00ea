// `vx bench render`: the renderer's report. One scene and view (terrain of --seed, or any scene
// `vx render` takes via --scene/--world), rendered
//   1. by each pipeline and feature set (raster, RT flat, and RT full with every combination of
//      shadows, reflections and denoiser: the thesis's Table 6.3), medians of GPU timestamps,
//      each also as a ratio to the RT flat and all-off rows (and the thesis's ratio beside it);
//   2. for speed against error: a converged reference (--reference-spp samples per pixel,
//      accumulated frames of 8 samples, no filter), then spp in {1, 2, 4, 8, 16, 25, 64},
//      bounce spp in {1, spp}, denoiser off and on: median GPU frame time and RMSE, PSNR, SSIM
//      against the reference (render/image_metrics.h); then a still camera's accumulated frames;
//      last a line naming the cheapest row that matches the thesis-style frame's error (25 spp,
//      bounce spp 25, raw) and its frame-time ratio (the target: >= 4x less frame time).
//   equal error (tools/bench_render_equal_error.h): Table 6.3's noisy rows at the error of the
//      thesis's 25 samples raw, the cheapest configuration reaching it beside the thesis's ratio;
//   4. geometry (tools/bench_render_geometry.h): naive, culled and greedy meshes; refit against
//      rebuild over k edits;
//   5. camera paths (tools/bench_render_paths.h): orbit, fly-over and an edit, every frame
//      against a converged reference at its pose;
//   6. sandbox defaults (tools/bench_render_defaults.h): game settings over the moving paths,
//      and the cheapest within 1.25x of the best error at up to twice its cost.
// --sections picks them: all (default), report (1-3), equal-error, geometry (4), paths (5) or
// defaults (6). --lighting thesis lights every row with the area light alone (no sun, no sky
// light), as the thesis did. Writes DIR/render_report.md (tables), DIR/render_bench.csv
// (equal_error.csv, defaults.csv), PNGs of the reference and of each sweep image;
// scripts/plot_render_bench.py draws error against frame time from any of the CSVs.
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_render_equal_error.h"
#include "bench_render_frames.h"
#include "bench_render_defaults.h"
#include "bench_render_geometry.h"
#include "bench_render_paths.h"
#include "cli_common.h"
#include "commands.h"
#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "render/image_metrics.h"
#include "render/renderer.h"
#include "scene_args.h"
#include "world/base/median.h"

namespace vx::tools {
namespace {

struct BenchRenderArgs {
    SceneArgs scene;
    std::string size = "160x90", out = "render_bench", device = "auto", sections = "all";
    std::string lighting = "default"; // --lighting: default (sun, sky, area light) or thesis.
    uint32_t reference_spp = 1024, repeat = 5, reflections = 5;
    uint32_t path_frames = 24, path_reference_spp = 64; // Sections 5 and 6.
    uint32_t error_seeds = 4;                           // Equal error: sample seeds per RMSE.
    std::string error_metric = "display";               // Equal error: display (before 8-bit rounding) or 8bit.
    uint32_t warmup_ms = 250; // Frames of a configuration before its timed ones (time_frames()).
    std::string first_hit_pass = "off"; // on: --split-hits 1.
    uint32_t split_hits = 0;            // render::RenderSettings::split_hits of every row.
};

struct Config {
    std::string name;
    render::RenderSettings s;
    double thesis_ratio = -1; // The thesis's Table 6.3 frame time over its "all off" row; -1: none.
};

// The view `vx render` picks by default: over the scene's box from (-1, 0.9, -1), light above.
render::Camera default_view(const engine::LoadedScene& scene, render::RenderSettings& s) {
    const glm::dvec3 lo(scene.box_min), hi(scene.box_max), centre = 0.5 * (lo + hi), ext = hi - lo;
    const double dist = 0.35 * glm::length(ext) / std::tan(glm::radians(30.0));
    const glm::dvec3 eye = centre + dist * glm::normalize(glm::dvec3(-1.0, 0.9, -1.0));
    const double above = std::max(32.0, 0.25 * std::max(ext.x, ext.z));
    const float side = float(above * 0.5);
    s.light.edge_u = {side, 0, 0};
    s.light.edge_v = {0, 0, side};
    const glm::dvec3 corner = glm::dvec3(centre.x, hi.y + above, centre.z) - 0.5 * glm::dvec3(side, 0, side);
    const glm::dvec3 cell = glm::floor(corner);
    s.light.block = world::BlockPos(cell);
    s.light.offset = glm::vec3(corner - cell);
    return render::Camera::look_at(eye, centre);
}

// One row of the speed-against-error sweep: full shading with `reflections` bounces.
render::RenderSettings sweep_settings(const render::RenderSettings& base, uint32_t reflections, uint32_t spp,
                                      uint32_t bounce_spp, bool denoise, bool light_cache = false) {
    render::RenderSettings s = base;
    s.light_cache = light_cache;
    s.max_bounces = reflections;
    s.shadow_samples = spp;
    s.bounce_shadow_samples = bounce_spp;
    s.denoise = denoise;
    return s;
}

// The thesis's Table 6.3: every combination of shadows (25 samples) x reflections (`reflections`
// bounces) x denoiser, after the raster baseline and RT flat. The thesis's own ratios to its
// "all off" row (RTX 2080 Ti; 1.00 ms) ride along, indexed [shadows][reflections][denoiser].
std::vector<Config> feature_configs(const render::RenderSettings& base, uint32_t reflections) {
    using render::ShadingMode;
    auto make = [&](std::string name, ShadingMode mode, uint32_t spp, uint32_t bounces, bool denoise) {
        Config c{std::move(name), base};
        c.s.mode = mode;
        c.s.shadow_samples = spp;
        c.s.max_bounces = bounces;
        c.s.denoise = denoise;
        return c;
    };
    std::vector<Config> v = {
        make("raster (Phong, point light)", ShadingMode::Full, 0, 0, false),
        make("RT flat", ShadingMode::Flat, 0, 0, false),
    };
    v[0].s.pipeline = render::PipelineKind::Raster;
    const std::string refl = "reflections (" + std::to_string(reflections) + " bounces)";
    constexpr double kThesis[2][2][2] = {{{1.00, 16.47}, {2.09, 17.83}}, {{8.14, 23.30}, {19.12, 34.82}}};
    for (bool shadows : {false, true})
        for (bool reflect : {false, true})
            for (bool denoise : {false, true}) {
                std::string name = "RT full: shadows ";
                name += shadows ? "25 spp" : "off";
                name += ", " + refl + (reflect ? " on" : " off");
                name += denoise ? ", denoiser on" : ", denoiser off";
                v.push_back(make(name, ShadingMode::Full, shadows ? 25 : 0, reflect ? reflections : 0, denoise));
                v.back().thesis_ratio = kThesis[shadows][reflect][denoise];
            }
    return v;
}

// One row of the speed-against-error tables, for the goal line.
struct SweepRow {
    std::string name;
    double frame_ms = -1, rmse = -1;
};

// The speed-up at equal error, computed from the rows: the cheapest row faster than the
// thesis-style one whose RMSE is at most the thesis-style row's, and its frame-time ratio
// (the target is >= 4x); and the lowest RMSE among the rows at >= 4x less frame time (what that
// budget buys).
std::string goal_line(const SweepRow& thesis, const std::vector<SweepRow>& rows) {
    const SweepRow *best = nullptr, *at4 = nullptr;
    for (const SweepRow& r : rows) {
        if (r.frame_ms <= 0 || r.frame_ms >= thesis.frame_ms)
            continue;
        if (r.rmse <= thesis.rmse && (!best || r.frame_ms < best->frame_ms))
            best = &r;
        if (4.0 * r.frame_ms <= thesis.frame_ms && (!at4 || r.rmse < at4->rmse))
            at4 = &r;
    }
    char buf[512];
    std::snprintf(buf, sizeof buf, "Speed-up at equal error: the thesis-style frame (%s) has RMSE %.5f at %.3f ms; ",
                  thesis.name.c_str(), thesis.rmse, thesis.frame_ms);
    std::string line = buf;
    if (best) {
        const double ratio = thesis.frame_ms / best->frame_ms;
        std::snprintf(buf, sizeof buf,
                      "the cheapest row with RMSE <= that is %s: RMSE %.5f at %.3f ms, %.2fx less frame time "
                      "(target >= 4x: %s). ",
                      best->name.c_str(), best->rmse, best->frame_ms, ratio, ratio >= 4.0 ? "met" : "not met");
        line += buf;
    } else {
        line += "no faster row reaches that error (target >= 4x: not met). ";
    }
    if (at4) {
        std::snprintf(buf, sizeof buf, "Lowest RMSE at >= 4x less frame time: %s, RMSE %.5f at %.3f ms.\n",
                      at4->name.c_str(), at4->rmse, at4->frame_ms);
        line += buf;
    } else {
        line += "No row is 4x faster.\n";
    }
    return line;
}

// Section 1: each row's median GPU times, then the table with every frame time also as a ratio
// to the RT flat row and to the all-off row (RT full, no shadows, reflections or denoiser: the
// thesis's 1.00 ms row) of this run, beside the thesis's ratio (Table 6.3).
std::string feature_table(render::Renderer& r, const render::RenderSettings& base, const render::Camera& cam,
                          const BenchRenderArgs& a) {
    const std::vector<Config> configs = feature_configs(base, a.reflections);
    std::vector<Timing> t;
    render::RenderImage img;
    for (const Config& c : configs) {
        t.push_back(time_frames(r, c.s, cam, a.repeat, &img, a.warmup_ms / 1000.0));
        std::printf("  %s: frame %.3f ms, trace/raster %.3f ms, denoise %.3f ms\n", c.name.c_str(),
                    t.back().frame, t.back().trace, t.back().denoise);
    }
    const double flat = t[1].frame, all_off = t[2].frame; // feature_configs' order.
    auto ratio = [](double v, double to) {
        char buf[32];
        std::snprintf(buf, sizeof buf, v > 0 && to > 0 ? "%.2f" : "n/a", v / to);
        return std::string(buf);
    };
    std::string md = "## Pipelines and features\n\nLighting: " +
                     std::string(a.lighting == "thesis" ? "thesis (one area light, no sun, no sky light)"
                                                        : "default (sun, sky light, area light)") +
                     ". Ratios are frame times over this run's RT flat and all-off rows (same GPU); the "
                     "thesis's are over its all-off row (Table 6.3, RTX 2080 Ti).\n\n"
                     "| configuration | frame ms | trace/raster ms | denoise ms | x RT flat | x all off | "
                     "thesis x all off |\n|---|---|---|---|---|---|---|\n";
    char line[640];
    for (size_t i = 0; i < configs.size(); ++i) {
        std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %.3f | %s | %s | %s |\n",
                      configs[i].name.c_str(), t[i].frame, t[i].trace, t[i].denoise,
                      ratio(t[i].frame, flat).c_str(), ratio(t[i].frame, all_off).c_str(),
                      configs[i].thesis_ratio > 0 ? ratio(configs[i].thesis_ratio, 1.0).c_str() : "");
        md += line;
        std::printf("  %s", line);
    }
    return md;
}

// The scene the bench renders: --seed, --world, --scene or --raw as given, else terrain of seed 1
// (radius 2 unless given).
SceneArgs bench_scene_args(const SceneArgs& given) {
    SceneArgs sa = given;
    if (!sa.seed && sa.world_path.empty() && sa.scene.empty() && sa.raw.empty()) {
        sa.seed = 1;
        if (sa.radius < 0)
            sa.radius = 2;
    }
    return sa;
}

// Hands every chunk of `scene` with quads to `r`.
void send_bench_scene(render::Renderer& r, const engine::LoadedScene& scene) {
    r.set_registry(scene.world->registry());
    for (const auto& [c, mc] : scene.meshes)
        if (mc.mesh.quad_count() > 0)
            r.set_chunk(c, mc.mesh);
}

// What every row shares beyond the size and the light: --first-hit-pass/--split-hits and
// --lighting.
void apply_row_args(const BenchRenderArgs& a, render::RenderSettings& base) {
    base.split_hits = split_hits_arg(a.first_hit_pass, a.split_hits);
    if (a.lighting == "thesis") { // As `vx render --lighting thesis`: the area light alone.
        base.sun.irradiance = glm::vec3(0.f);
        base.sky_light = 0.f;
        base.haze.enabled = false; // The thesis had none (and unlit haze would only darken).
    }
}

// The report's opening: scene, size, device, how the times were taken.
std::string render_report_intro(const engine::LoadedScene& scene, const render::RenderSettings& base,
                                const render::Renderer& r, const BenchRenderArgs& a) {
    return "# Renderer report (`vx bench render`)\n\nScene: " + scene.description + ", " +
           std::to_string(base.width) + "x" + std::to_string(base.height) + ", device " + r.device().name +
           ". GPU times are medians of " + std::to_string(a.repeat) + " frames (timestamps), after " +
           std::to_string(a.warmup_ms) +
           " ms of each configuration's frames; the machine may be shared: read them side by "
           "side. Hits in passes of their own (split hits): " + std::to_string(base.split_hits) +
           ".\n\n";
}

// The inputs of the sections other than 1-3.
struct SectionInfos {
    GeometryBenchInfo geometry;
    PathBenchInfo paths;
    DefaultsBenchInfo defaults;
    EqualErrorBenchInfo equal;
};

SectionInfos section_infos(render::DeviceChoice choice, const render::RenderSettings& base, const render::Camera& cam,
                           const BenchRenderArgs& a) {
    return {{choice, base, cam, a.repeat, a.reflections, a.out},
            {base, cam, a.path_frames, a.path_reference_spp, a.reflections, a.out, {}},
            {base, cam, a.path_frames, a.path_reference_spp, a.out},
            {base, cam, a.repeat, a.reflections, a.reference_spp, a.error_seeds, a.lighting, a.out,
             a.error_metric == "display", a.warmup_ms / 1000.0}};
}

// --sections equal-error, defaults, paths or geometry: that section alone, the report written;
// its exit code. nullopt for all and report.
std::optional<int> run_one_section(std::unique_ptr<render::Renderer>& renderer, engine::LoadedScene& scene,
                                   const SectionInfos& info, const BenchRenderArgs& a, std::string& md) {
    render::Renderer& r = *renderer;
    if (a.sections == "equal-error") {
        md += run_equal_error_bench(r, info.equal);
        ReportFile(a.out + "/render_report.md") << md;
        std::printf("  wrote %s/render_report.md and equal_error.csv\n", a.out.c_str());
        return report_outputs();
    }
    if (a.sections == "defaults") { // Only section 6.
        md += run_defaults_bench(r, scene, info.defaults);
        ReportFile(a.out + "/render_report.md") << md;
        std::printf("  wrote %s/render_report.md and defaults.csv\n", a.out.c_str());
        return report_outputs();
    }
    if (a.sections == "paths") { // Only section 5.
        md += run_path_bench(r, scene, info.paths);
        ReportFile(a.out + "/render_report.md") << md;
        std::printf("  wrote %s/render_report.md and paths.csv\n", a.out.c_str());
        return report_outputs();
    }
    if (a.sections == "geometry") { // Only section 4.
        renderer.reset(); // Its renderers are made one at a time (volk loads one device's entry points).
        md += run_geometry_bench(scene, info.geometry);
        ReportFile(a.out + "/render_report.md") << md;
        std::printf("  wrote %s/render_report.md and geometry.csv\n", a.out.c_str());
        return report_outputs();
    }
    return std::nullopt;
}

// Section 2's reference: rendered into `img` (and reference.png), its paragraph added to `md`.
render::ImageF speed_reference(render::Renderer& r, const render::RenderSettings& base, const render::Camera& cam,
                               const BenchRenderArgs& a, render::RenderImage& img, std::string& md) {
    char line[512];
    render::RenderSettings ref_s = base;
    ref_s.max_bounces = a.reflections;
    img = render_reference(r, ref_s, cam, a.reference_spp);
    render::ImageF reference = render::to_float(img);
    note_png(a.out + "/reference.png", img);
    std::snprintf(line, sizeof line,
                  "\n## Speed against error\n\nReference: %u samples per pixel (%u frames of 8, accumulated, no "
                  "filter), %u reflection bounces.\n\n",
                  reference_frames(a.reference_spp) * 8, reference_frames(a.reference_spp), a.reflections);
    md += line;
    return reference;
}

// Section 2's sweep against `reference`: its table; each row also to `csv`, a PNG, and the goal
// line's rows (`thesis`, the thesis-style one, or `candidates`). `img` ends as the last row's.
std::string sweep_table(render::Renderer& r, const render::RenderSettings& base, const render::Camera& cam,
                        const BenchRenderArgs& a, const render::ImageF& reference, render::RenderImage& img,
                        ReportFile& csv, SweepRow& thesis, std::vector<SweepRow>& candidates) {
    char line[512];
    std::string md = "| spp | bounce spp | denoiser | light cache | frame ms | RMSE | PSNR dB | SSIM |\n"
                     "|---|---|---|---|---|---|---|---|\n";
    for (bool cache : {false, true})
        for (uint32_t spp : {1u, 2u, 4u, 8u, 16u, 25u, 64u}) {
            const std::vector<uint32_t> bounce_spps = spp == 1 ? std::vector<uint32_t>{1} : std::vector<uint32_t>{1, spp};
            for (uint32_t bounce : bounce_spps)
                for (bool denoise : {false, true}) {
                    const render::RenderSettings s = sweep_settings(base, a.reflections, spp, bounce, denoise, cache);
                    const Timing t = time_frames(r, s, cam, a.repeat, &img, a.warmup_ms / 1000.0);
                    const render::ImageError e = render::compare(render::to_float(img), reference);
                    std::snprintf(line, sizeof line, "| %u | %u | %s | %s | %.3f | %.4f | %.2f | %.4f |\n", spp, bounce,
                                  denoise ? "on" : "off", cache ? "on" : "off", t.frame, e.rmse, e.psnr, e.ssim);
                    md += line;
                    std::printf("  %s", line);
                    const std::string row = std::to_string(spp) + " spp, bounce spp " + std::to_string(bounce) +
                                            ", denoiser " + (denoise ? "on" : "off") + (cache ? ", light cache" : "");
                    if (spp == 25 && bounce == 25 && !denoise && !cache)
                        thesis = {row, t.frame, e.rmse};
                    else
                        candidates.push_back({row, t.frame, e.rmse});
                    csv << spp << ',' << bounce << ',' << (denoise ? 1 : 0) << ',' << t.frame << ',' << e.rmse << ','
                        << e.psnr << ',' << e.ssim << ',' << (cache ? 1 : 0) << '\n';
                    const std::string png = a.out + "/spp" + std::to_string(spp) + "_b" + std::to_string(bounce) +
                                            (denoise ? "_denoised" : "") + (cache ? "_cache" : "") + ".png";
                    note_png(png, img);
                }
        }
    return md;
}

// Section 3's table; each row also to the goal line's `candidates`. `img` ends as the last row's.
std::string still_camera_table(render::Renderer& r, const render::RenderSettings& base, const render::Camera& cam,
                               const BenchRenderArgs& a, const render::ImageF& reference, render::RenderImage& img,
                               std::vector<SweepRow>& candidates) {
    char line[512];
    std::string md = "\n## Still camera, 8 frames accumulated\n\nFrame ms is per frame, the error that of the 8th "
                     "frame.\n\n| spp | bounce spp | denoiser | frame ms | RMSE | PSNR dB | SSIM |\n"
                     "|---|---|---|---|---|---|---|\n";
    for (uint32_t spp : {1u, 2u, 4u})
        for (uint32_t bounce : spp == 1 ? std::vector<uint32_t>{1} : std::vector<uint32_t>{1, spp})
            for (bool denoise : {false, true}) {
                render::RenderSettings s = sweep_settings(base, a.reflections, spp, bounce, denoise);
                s.accumulate = 8;
                std::vector<double> frame;
                for (uint32_t i = 0; i < 8; ++i) {
                    img = bench_frame(r, s, cam);
                    frame.push_back(r.last_stats().gpu_frame_ms);
                }
                const render::ImageError e = render::compare(render::to_float(img), reference);
                std::snprintf(line, sizeof line, "| %u | %u | %s | %.3f | %.4f | %.2f | %.4f |\n", spp, bounce,
                              denoise ? "on" : "off", median(frame), e.rmse, e.psnr, e.ssim);
                md += line;
                std::printf("  accumulated %s", line);
                const std::string row = std::to_string(spp) + " spp, bounce spp " + std::to_string(bounce) +
                                        ", denoiser " + (denoise ? "on" : "off") + ", still camera after 8 frames";
                candidates.push_back({row, median(frame), e.rmse});
            }
    return md;
}

// --sections all or report: sections 1-3 (with all, then the others), the report, render_bench.csv
// and the PNGs. `md` holds the report's opening.
int run_report(std::unique_ptr<render::Renderer>& renderer, engine::LoadedScene& scene,
               const render::RenderSettings& base, const render::Camera& cam, const BenchRenderArgs& a,
               const SectionInfos& info, std::string& md) {
    render::Renderer& r = *renderer;
    // 1. Pipelines and features.
    md += feature_table(r, base, cam, a);
    render::RenderImage img;

    // 2. Speed against error.
    const render::ImageF reference = speed_reference(r, base, cam, a, img, md);
    std::vector<SweepRow> candidates;
    SweepRow thesis{"25 spp, bounce spp 25, denoiser off"};
    ReportFile csv(a.out + "/render_bench.csv");
    csv << "spp,bounce_spp,denoise,frame_ms,rmse,psnr,ssim,light_cache\n";
    md += sweep_table(r, base, cam, a, reference, img, csv, thesis, candidates);
    // 3. A still camera: frames accumulated by the temporal pass (SVGF moments once 4 are in).
    md += still_camera_table(r, base, cam, a, reference, img, candidates);
    const std::string goal = goal_line(thesis, candidates);
    md += "\n" + goal;
    std::printf("  %s", goal.c_str());
    md += "\nPlot: `scripts/plot_render_bench.py " + a.out + "/render_bench.csv` writes error against "
          "frame time (PNG) next to the CSV.\n";
    if (a.sections == "all") {
        md += "\n" + run_equal_error_bench(r, info.equal);
        md += "\n" + run_path_bench(r, scene, info.paths);
        md += "\n" + run_defaults_bench(r, scene, info.defaults);
        renderer.reset();
        md += run_geometry_bench(scene, info.geometry);
    }
    ReportFile(a.out + "/render_report.md") << md;
    csv.finish();
    std::printf("  wrote %s/render_report.md, render_bench.csv and PNGs\n", a.out.c_str());
    return report_outputs();
}

int run_bench_render(const BenchRenderArgs& a) {
    render::RenderSettings base;
    const std::optional<glm::uvec2> size = parse_image_size(a.size);
    if (!size)
        return bad_input("--size must be WxH (1..16384), got '" + a.size + "'");
    base.width = size->x;
    base.height = size->y;
    const auto choice = render::parse_device_choice(a.device);
    if (!choice)
        return bad_input(choice.error());
    const SceneArgs sa = bench_scene_args(a.scene);
    const auto info = scene_load_info(sa);
    if (!info)
        return bad_input(info.error());
    engine::JobSystem jobs(engine::batch_job_system_info(sa.threads));
    if (const std::string why = job_system_problem(jobs.start_error()); !why.empty())
        return failed(why);
    auto scene = engine::load_scene(jobs, *info);
    if (!scene)
        return bad_input(scene.error());
    if (scene->box_min == scene->box_max) // The default view of nothing looked from the centre at itself.
        return bad_input("the scene holds no chunk to measure (" + scene->description + ")");
    auto renderer = render::Renderer::create({.device = *choice});
    if (!renderer)
        return bad_input("cannot render: " + renderer.error());
    render::Renderer& r = **renderer;
    if (Status fits = r.check_frame_size(base.width, base.height); !fits) // As vx render.
        return bad_input("cannot render: " + fits.error());
    send_bench_scene(r, *scene);
    const render::Camera cam = default_view(*scene, base);
    apply_row_args(a, base);
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec)
        return bad_input("cannot create --out directory '" + a.out + "': " + ec.message());
    std::printf("vx bench render: %s; %ux%u on %s\n", scene->description.c_str(), base.width, base.height,
                r.device().name.c_str());
    std::string md = render_report_intro(*scene, base, r, a);
    const SectionInfos sections = section_infos(*choice, base, cam, a);
    if (const std::optional<int> rc = run_one_section(*renderer, *scene, sections, a, md))
        return *rc;
    return run_report(*renderer, *scene, base, cam, a, sections, md);
}

} // namespace

int run_bench_render_command(int argc, char** argv) {
    CLI::App app{"vx bench render: pipelines, features, and speed against error", "vx bench render"};
    BenchRenderArgs a;
    uint64_t seed = 0;
    CLI::Option* seed_opt = app.add_option("--seed", seed, "Terrain of this seed (default 1, radius 2)")
                                ->check(seed_range());
    app.add_option("--scene", a.scene.scene, "Built-in scene: 'seed' (thesis)");
    app.add_option("--scene-block", a.scene.scene_block, "Block of the seed scene (e.g. mirror: reflections)");
    app.add_option("--world", a.scene.world_path, "A stored world (SQLite)");
    app.add_option("--raw", a.scene.raw, "A raw volume of block ids (with --dims; as `vx render`)");
    app.add_option("--dims", a.scene.dims, "Size of the --raw volume, X,Y,Z blocks");
    app.add_option("--radius", a.scene.radius, "Chunks around the camera, horizontal")
        ->check(decimal_range(0, 64, "must be 0..64 chunks"));
    app.add_option("--vradius", a.scene.vradius, "Chunks around the camera, vertical")
        ->check(decimal_range(0, 64, "must be 0..64 chunks"));
    app.add_option("--size", a.size, "Image size WxH (lavapipe: keep it small, e.g. 160x90)");
    app.add_option("--reference-spp", a.reference_spp, "Samples per pixel of the converged reference")
        ->check(CLI::Range(8u, 1u << 20));
    app.add_option("--repeat", a.repeat, "Frames per configuration (medians)")->check(CLI::Range(1u, 10000u));
    app.add_option("--warmup-ms", a.warmup_ms,
                   "Milliseconds of a configuration's own frames before its timed ones (default 250; 0: one "
                   "frame)")
        ->check(CLI::Range(0u, 60000u));
    app.add_option("--first-hit-pass", a.first_hit_pass,
                   "on: every ray-traced row traces the primary hits' light in a pass of its own, then the "
                   "reflections (--split-hits 1; the same images)")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--split-hits", a.split_hits,
                   "Every ray-traced row traces the first N hits of each path each in a pass of its own, then "
                   "the rest (render::RenderSettings::split_hits; the same images); 0: one pass")
        ->check(CLI::Range(0u, 64u));
    app.add_option("--reflections", a.reflections,
                   "Reflection bounces of the full-shading rows, 0..16 (defaults: the facade's default instead)")
        ->check(CLI::Range(0u, render::kMaxMirrorBounces));
    app.add_option("--device", a.device, "auto, cpu, gpu or a device index");
    app.add_option("--out", a.out, "Directory for the report, CSV and PNGs");
    app.add_option("--lighting", a.lighting,
                   "default: sun, sky light and area light; thesis: the area light alone (Table 6.3 like "
                   "for like)")
        ->check(CLI::IsMember({"default", "thesis"}));
    app.add_option("--sections", a.sections,
                   "all; report: pipelines, features, speed against error; equal-error: Table 6.3's shadow and "
                   "reflection rows at the thesis's one-frame error; geometry: meshers, refit against rebuild; "
                   "paths: orbit, fly-over and an edit against references at every pose; defaults: game settings "
                   "over the moving paths and the pick for the sandbox")
        ->check(CLI::IsMember({"all", "report", "equal-error", "geometry", "paths", "defaults"}));
    app.add_option("--error-seeds", a.error_seeds, "Equal error: sample seeds per one-frame RMSE")
        ->check(CLI::Range(1u, 64u));
    app.add_option("--error-metric", a.error_metric,
                   "Equal error: the RMSE the search uses, of the output before its 8-bit rounding (display) or "
                   "of the 8-bit image (8bit); both are written")
        ->check(CLI::IsMember({"display", "8bit"}));
    app.add_option("--path-frames", a.path_frames, "Frames per camera path (paths, defaults)")
        ->check(CLI::Range(4u, 10000u));
    app.add_option("--path-reference-spp", a.path_reference_spp,
                   "Samples per pixel of each path pose's reference (paths, defaults)")
        ->check(CLI::Range(8u, 1u << 20));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return parse_failure(app, e);
    }
    if (seed_opt->count() > 0)
        a.scene.seed = seed;
    return run_bench_render(a);
}

} // namespace vx::tools
