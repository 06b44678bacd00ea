// `vx render`: load and mesh a scene, ray trace it with vx_render, write a PNG and print where
// the time went (GPU timestamps per phase where the device has them). --repeat and --edit-burst
// make it a benchmark: medians over many frames and over edit bursts (slice uploads + refits,
// whole-chunk uploads + refits, rebuilds). It also prints the scene's GPU memory by kind.
// --view-distance draws terrain to that distance, with levels of detail (--lod on) or at full
// detail (--lod off, the reference), and prints chunks, BLASes and GPU memory per level.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "cmd_render_settings.h"
#include "render_versus.h"
#include "commands.h"
#include "engine/job_batch.h"
#include "engine/scene_loader.h"
#include "world/base/median.h"
#include "world/coords.h"
#include "world/mesh/edit_mesher.h"
#include "render/renderer.h"
#include "scene_args.h"

namespace vx::tools {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;

// --lighting thesis: the thesis's ray tracer (its chapter 6.3 and Table 6.3): one rectangular
// area light, no sun and no sky light, 25 shadow samples at every hit (bounces too, unless
// --bounce-spp says otherwise: its closest-hit shader recursed with the same 25) and 5
// reflection bounces. Missed rays still show the sky colour (the thesis does not say what its
// miss shader returned; the colour lights nothing), and no haze. Options given explicitly win over the
// preset; `given` says which were.
struct LightingGiven {
    bool spp = false, reflections = false, sun = false, sky_light = false, area_light = false, haze = false;
};
void apply_lighting_preset(RenderArgs& a, const LightingGiven& given) {
    if (a.lighting != "thesis")
        return;
    if (!given.spp)
        a.spp = 25;
    if (!given.reflections)
        a.reflections = 5;
    if (!given.sun)
        a.sun = "off";
    if (!given.sky_light)
        a.sky_light = 0.f;
    if (!given.area_light)
        a.area_light = "on";
    if (!given.haze) // The thesis had none; with no sky light it would only darken.
        a.haze = "off";
}

std::string ms(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, v < 0 ? "n/a" : v < 10 ? "%.3f ms" : "%.1f ms", v);
    return buf;
}

std::string mb(uint64_t bytes) {
    char buf[32];
    if (bytes < 1000000)
        std::snprintf(buf, sizeof buf, "%.1f KB", double(bytes) / 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.2f MB", double(bytes) / 1e6);
    return buf;
}

void print_frame(const char* what, const render::RenderStats& st, double wall_ms) {
    std::printf("  %s: BLAS %s (%u builds, %u refits, %u compactions; upload %s), TLAS %s (%u instances), trace %s, "
                "readback copy %s; frame %s wall\n",
                what, ms(st.gpu_blas_ms).c_str(), st.blas_builds, st.blas_refits, st.blas_compactions,
                mb(st.upload_bytes).c_str(), ms(st.gpu_tlas_ms).c_str(), st.instances, ms(st.gpu_trace_ms).c_str(),
                ms(st.gpu_copy_ms).c_str(), ms(wall_ms).c_str());
    if (st.failed_chunks > 0)
        std::printf("  %u chunks not drawn: out of GPU memory\n", st.failed_chunks);
    if (st.touching_probes) // The pipeline variant with the coincident-face probe (render/touching_pairs.h).
        std::printf("  two different see-through blocks touch: traced with the coincident-face probe\n");
    if (st.see_through_checked) // RenderSettings::see_through_check.
        std::printf("  see-through check: %u pixels traced again with the see-through code\n", st.see_through_pixels);
    else if (st.see_through_view_pixels > 0)
        std::printf("  see-through check: %u view rays met see-through faces, over the share: one dispatch\n",
                    st.see_through_view_pixels);
}

// Device memory of the scene by kind; B/quad counts what each chunk holds (BLAS, vertices, quad
// records) over the real quads drawn.
void print_memory(const render::RenderStats& st) {
    const render::GpuMemoryStats& m = st.memory;
    std::printf("  GPU memory: BLAS %s, vertices %s, quad records %s, TLAS %s, scratch %s, indices %s; total %s; "
                "%.1f B/quad over %" PRIu64 " quads (%u chunks hot)\n",
                mb(m.blas).c_str(), mb(m.vertices).c_str(), mb(m.quads).c_str(), mb(m.tlas).c_str(),
                mb(m.scratch).c_str(), mb(m.indices).c_str(), mb(m.total()).c_str(), m.bytes_per_quad(), m.quad_count,
                st.hot_chunks);
}

// View-distance scenes: per level, the chunks loaded, those with triangles (a BLAS each), their
// triangles, the chunks drawn (TLAS instances) and the device memory their chunks hold.
void print_levels(const engine::LoadedScene& scene, const render::RenderStats& st) {
    for (int k = 0; k <= world::kMaxLodLevel; ++k) {
        const engine::LevelCounts& n = scene.levels[size_t(k)];
        if (n.chunks == 0)
            continue;
        std::printf("  level %d (cells of %" PRId64 " blocks): %" PRIu64 " chunks, %" PRIu64
                    " with triangles (BLAS), %" PRIu64 " triangles; %u drawn, GPU memory %s\n",
                    k, world::lod_cell_size(k), n.chunks, n.meshed, 2 * n.quads, st.level_instances[size_t(k)],
                    mb(st.level_gpu_bytes[size_t(k)]).c_str());
    }
}

// Renders and returns the wall time of the call (it waits for the GPU). A failed frame is kept in
// s.failure (and makes later calls return 0 at once).
double timed_render(render::Renderer& r, const Settings& s, render::RenderImage* image) {
    return s.failure.empty() ? timed_frame(r, s.settings, s.camera, s.failure, image) : 0.0;
}

// --accumulate N: frames 2..N of the still camera, averaged by the denoiser's temporal pass;
// `image` becomes the last (the average). Prints the denoiser's GPU time (median) when it ran.
void accumulate_frames(render::Renderer& r, const Settings& s, render::RenderImage* image) {
    const render::RenderSettings& rs = s.settings;
    if (rs.denoise || rs.accumulate > 1)
        std::printf("  denoiser: %s, accumulate %u (%s)\n", rs.denoise ? "on" : "off", rs.accumulate,
                    rs.pipeline == render::PipelineKind::RayTraced && rs.mode == render::ShadingMode::Full
                        ? "on the ray tracer's radiance"
                        : "ignored: only the ray tracer's full shading is denoised");
    std::vector<double> denoise_ms{r.last_stats().gpu_denoise_ms}, wall;
    for (uint32_t i = 1; i < rs.accumulate; ++i) {
        wall.push_back(timed_render(r, s, image));
        denoise_ms.push_back(r.last_stats().gpu_denoise_ms);
    }
    if (rs.accumulate > 1)
        std::printf("  accumulated frames 2..%u: frame %s wall, denoiser %s GPU (medians)\n", rs.accumulate,
                    ms(median(wall)).c_str(), ms(median(denoise_ms)).c_str());
    else if (rs.denoise)
        std::printf("  denoiser: %s GPU\n", ms(denoise_ms[0]).c_str());
}

// Frames 2..N of the same view: medians of the GPU phases and the wall time.
void repeat_frames(render::Renderer& r, const Settings& s, uint32_t n) {
    std::vector<double> tlas, trace, denoise, copy, wall, cpu;
    for (uint32_t i = 1; i < n; ++i) {
        wall.push_back(timed_render(r, s, nullptr));
        const render::RenderStats& st = r.last_stats();
        tlas.push_back(st.gpu_tlas_ms);
        trace.push_back(st.gpu_trace_ms);
        denoise.push_back(st.gpu_denoise_ms);
        copy.push_back(st.gpu_copy_ms);
        cpu.push_back(st.cpu_ms);
    }
    // The denoiser's passes only where they ran (RenderStats::gpu_denoise_ms 0: they did not).
    const double denoise_ms = median(denoise);
    const std::string denoised = denoise_ms > 0.0 ? ", denoiser " + ms(denoise_ms) : std::string();
    std::printf("  frames 2..%u (medians of %u): TLAS %s, trace %s%s, readback copy %s; frame %s wall, recording %s "
                "CPU\n",
                n, n - 1, ms(median(tlas)).c_str(), ms(median(trace)).c_str(), denoised.c_str(),
                ms(median(copy)).c_str(), ms(median(wall)).c_str(), ms(median(cpu)).c_str());
}

struct BurstFigures {
    std::vector<double> blas_ms, upload;
    uint64_t refits = 0, builds = 0;
    void add(const render::RenderStats& st) {
        blas_ms.push_back(st.gpu_blas_ms);
        upload.push_back(double(st.upload_bytes));
        refits += st.blas_refits;
        builds += st.blas_builds;
    }
    void print(const char* what, size_t chunks) const {
        const double n = double(blas_ms.size()), up = median(upload);
        std::printf("    %-8s BLAS %s, upload %s (%.0f B per chunk), %.1f refits + %.1f builds per burst\n", what,
                    ms(median(blas_ms)).c_str(), mb(uint64_t(up)).c_str(), up / double(chunks), double(refits) / n,
                    double(builds) / n);
    }
};

// Edit bursts: `k` chunks each get one block toggled at their centre, remeshed through the
// six-slice edit path (world::EditMesher, as the engine does). The meshes reach the renderer in
// three ways, medians of the BLAS phase (uploads, builds, refits, compaction copies: GPU
// timestamps) and of the bytes uploaded over `rounds` bursts each:
//   slices:  set_chunk(c, mesh, changed slices), the engine's path: those slices, then a refit;
//   whole:   set_chunk(c, mesh): the chunk's whole hot layout uploaded, then a refit;
//   rebuild: remove_chunk + set_chunk: a cold build (exact size), compacted two frames later
//            (that frame's BLAS phase is reported as "compact").
// The first burst turns the loaded (cold) chunks hot, a rebuild each, and is reported alone.
void edit_bursts(render::Renderer& r, engine::LoadedScene& scene, const Settings& s, uint32_t k, uint32_t rounds) {
    std::vector<ChunkCoord> coords;
    for (const auto& [c, mc] : scene.meshes)
        if (mc.mesh.quad_count() > 0)
            coords.push_back(c);
    std::sort(coords.begin(), coords.end(), [](ChunkCoord a, ChunkCoord b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    });
    coords.resize(std::min<size_t>(coords.size(), k));
    if (coords.empty()) { // Figures per chunk of no chunk were NaN.
        std::printf("  edit burst: no chunk of the scene has a face to edit\n");
        return;
    }
    const BlockId stone = scene.world->registry().find("stone").value_or(BlockId(1));
    EditMesher em(scene.isolated);
    enum Mode { Slices, Whole, Rebuild };
    auto burst = [&](Mode mode) {
        for (ChunkCoord c : coords) {
            const BlockPos p = chunk_origin(c) + BlockPos(kChunkSize / 2);
            const BlockId id = scene.world->get_block(p) == kAir ? stone : kAir;
            const EditResult e = em.apply(*scene.world, p, id, scene.meshes);
            for (const SliceUpdate& u : e.updates) {
                const ChunkMesh& mesh = scene.meshes[u.chunk].mesh;
                if (mode == Rebuild)
                    r.remove_chunk(u.chunk);
                if (mode == Slices && !u.full)
                    r.set_chunk(u.chunk, mesh, std::span<const int>(u.slices.data(), size_t(u.count)));
                else
                    r.set_chunk(u.chunk, mesh);
            }
        }
        timed_render(r, s, nullptr);
        return r.last_stats();
    };
    BurstFigures first, slices, whole, rebuild, compact;
    first.add(burst(Slices));
    for (uint32_t round = 0; round < rounds; ++round) {
        slices.add(burst(Slices));
        whole.add(burst(Whole));
    }
    for (uint32_t round = 0; round < rounds; ++round) {
        rebuild.add(burst(Rebuild));
        timed_render(r, s, nullptr);
        timed_render(r, s, nullptr); // The rebuilt chunks are compacted in this frame.
        compact.add(r.last_stats());
    }
    std::printf("  edit burst of %zu chunks, one block each (medians of %u bursts; GPU timestamps):\n", coords.size(),
                rounds);
    first.print("first", coords.size());
    slices.print("slices", coords.size());
    whole.print("whole", coords.size());
    rebuild.print("rebuild", coords.size());
    compact.print("compact", coords.size());
}

int run_render(RenderArgs a) {
    const auto t_start = Clock::now();
    if (const std::string why = output_file_problem(a.out); !why.empty())
        return bad_input("--out: " + why); // Before the scene loads and renders, not after.
    if (const std::string in = output_overwrites(a.out, {a.scene.world_path, a.scene.raw}); !in.empty())
        return bad_input("--out '" + a.out + "' is '" + in + "', which the render reads: the image would replace it");
    if (!a.eye.empty()) {
        a.scene.eye = parse_world_pos(a.eye);
        if (!a.scene.eye)
            return bad_input("--eye must be X,Y,Z (decimals, inside the world), got '" + a.eye + "'");
    }
    const auto choice = render::parse_device_choice(a.device);
    if (!choice)
        return bad_input(choice.error());
    const auto info = scene_load_info(a.scene);
    if (!info)
        return bad_input(info.error());
    // The process's one job system: loading, generation and meshing run on it.
    engine::JobSystem jobs(engine::batch_job_system_info(a.scene.threads));
    if (const std::string why = job_system_problem(jobs.start_error()); !why.empty())
        return failed(why);
    auto scene = engine::load_scene(jobs, *info);
    if (!scene)
        return bad_input(scene.error());
    Settings s;
    if (auto err = make_settings(a, *scene, s))
        return bad_input(*err);
    apply_pipeline_args(a, s.settings);
    const char* env = std::getenv("VX_VALIDATION");
    const bool validation = a.validation || (env && std::strcmp(env, "0") != 0 && *env);
    auto renderer = render::Renderer::create({.validation = validation,
                                              .device = *choice,
                                              .allow_refit = a.blas_update == "on",
                                              .pipeline_statistics = a.pipeline_report});
    if (!renderer)
        return bad_input("cannot render: " + renderer.error());
    render::Renderer& r = **renderer;
    // Before the first frame: on lavapipe a 16384² one took all host memory (the kernel killed it).
    if (Status fits = r.check_frame_size(s.settings.width, s.settings.height); !fits)
        return bad_input("cannot render: " + fits.error());
    r.set_registry(scene->world->registry());
    const uint32_t non_empty = engine::send_scene(*scene, r);
    std::printf("vx render: %s\n", scene->description.c_str());
    std::printf("  scene: %zu chunks (%u with triangles), %" PRIu64 " triangles; load %s, mesh %s",
                scene->meshes.size() + scene->coarse.size(), non_empty, scene->triangles, ms(scene->load_ms).c_str(),
                ms(scene->mesh_ms).c_str());
    if (!scene->coarse.empty())
        std::printf(", coarse levels %s (generated and meshed)", ms(scene->coarse_ms).c_str());
    std::printf("\n");
    const render::DeviceReport& dev = r.device();
    std::printf("  device: %s (%s, %s)%s\n", dev.name.c_str(), render::device_type_name(dev.type),
                dev.driver_info.c_str(), validation ? ", validation on" : "");
    const std::string bounce_samples =
        s.settings.samples_by_weight
            ? std::string(" x each hit's weight") + weight_exponent_text(s.settings.weight_exponent)
            : ", " + std::to_string(s.settings.bounce_shadow_samples.value_or(s.settings.shadow_samples)) + " on bounces";
    std::printf("  image: %ux%u, %s shading, shadows %s (%u samples%s), reflections %u\n", s.settings.width,
                s.settings.height, a.shading.c_str(), a.shadows.c_str(), s.settings.shadow_samples,
                bounce_samples.c_str(), s.settings.max_bounces);
    std::printf("  lights%s: sun %s, sky term x%g%s, area light %s\n",
                a.lighting == "thesis" ? " (--lighting thesis)" : "", a.sun.c_str(), double(a.sky_light),
                a.sky_access == "on" ? "" : " (sky access off: no sun or sky rays)", a.area_light.c_str());
    if (s.settings.pipeline == render::PipelineKind::Raster)
        std::printf("  pipeline: raster (Phong, point light at the area light's centre, no shadows)\n");
    else if (s.settings.mode == render::ShadingMode::Full && s.settings.haze.enabled)
        std::printf("  haze: visibility %g blocks, height falloff %g per block above y %g\n",
                    double(s.settings.haze.visibility), double(s.settings.haze.height_falloff),
                    s.settings.haze.base_height);
    render::RenderImage image;
    const double first = timed_render(r, s, &image);
    if (!s.failure.empty())
        return failed("cannot render: " + s.failure);
    print_frame("frame 1", r.last_stats(), first);
    if (s.settings.mode == render::ShadingMode::Full)
        std::printf("  exposure: EV100 %.2f (%s)\n", double(r.last_stats().ev100),
                    s.settings.exposure.automatic ? "auto: metered, key 0.18" : "manual");
    accumulate_frames(r, s, &image);
    if (a.repeat > 1)
        repeat_frames(r, s, a.repeat);
    if (a.versus_raw > 0 && s.failure.empty()) {
        const uint32_t pairs = std::max<uint32_t>(a.repeat, 2);
        const VersusFigures f = versus_raw(r, s.settings, s.camera, a.versus_raw, pairs);
        s.failure = f.failure;
        if (f.failure.empty())
            std::printf("%s", format_versus(f, a.versus_raw).c_str());
    }
    for (uint32_t i = std::max<uint32_t>(a.repeat, 1); i < 3; ++i)
        timed_render(r, s, nullptr); // Cold chunks are compacted in frame 3.
    print_memory(r.last_stats());
    if (a.scene.view_distance)
        print_levels(*scene, r.last_stats());
    if (a.edit_burst > 0)
        edit_bursts(r, *scene, s, a.edit_burst, std::max<uint32_t>(a.repeat, 1));
    if (!s.failure.empty()) // The figures above stop at the failed frame.
        return failed("a later frame failed: " + s.failure);
    if (a.pipeline_report) {
        Result<render::PipelineReport> report = r.pipeline_report();
        if (!report)
            return failed("cannot report the pipelines: " + report.error());
        std::printf("%s", render::format_pipeline_report(*report).c_str());
    }
    if (Status w = render::write_png(a.out, image); !w)
        return bad_input(w.error());
    std::printf("  wrote %s; total %s\n", a.out.c_str(),
                ms(std::chrono::duration<double, std::milli>(Clock::now() - t_start).count()).c_str());
    if (validation) {
        std::printf("  validation errors: %u\n", r.validation_errors());
        if (r.validation_errors() > 0)
            return kExitFailure;
    }
    return kExitOk;
}

// The scene: what `vx render` loads or generates, and around which point. Returns --seed's option
// (its value is taken only when given).
CLI::Option* add_scene_options(CLI::App* cmd, RenderArgs& a, uint64_t& seed) {
    cmd->add_option("--world", a.scene.world_path, "A stored world (SQLite); every chunk, or --radius around the camera if large");
    CLI::Option* seed_opt = cmd->add_option("--seed", seed, "Generate terrain of this seed around the camera")
                                ->check(seed_range());
    cmd->add_option("--scene", a.scene.scene, "Built-in scene: 'seed' (thesis: 1024 chunks, 10% random, isolated)");
    cmd->add_option("--scene-block", a.scene.scene_block, "Block of the seed scene (e.g. stone, mirror)");
    cmd->add_option("--raw", a.scene.raw, "Raw volume of block ids (as vx mesh)");
    cmd->add_option("--dims", a.scene.dims, "Raw volume size X,Y,Z");
    cmd->add_option("--type", a.scene.type, "Raw block id type")->check(CLI::IsMember({"u8", "u16"}));
    cmd->add_option("--origin", a.scene.origin, "World position X,Y,Z of the raw volume's first block");
    cmd->add_option("--radius", a.scene.radius, "Chunks around the camera, horizontal (--seed: default 8)")
        ->check(decimal_range(0, 64, "must be 0..64 chunks"));
    cmd->add_option("--vradius", a.scene.vradius, "Chunks around the camera, vertical (default 4)")
        ->check(decimal_range(0, 64, "must be 0..64 chunks"));
    cmd->add_option("--view-distance", a.scene.view_distance,
                    "Terrain (--seed) to this many blocks: --radius/--vradius stay the full-detail box, levels "
                    "of detail beyond it (--lod on), or full detail all the way (--lod off)");
    cmd->add_option("--lod", a.scene.lod, "With --view-distance: levels of detail (on, default) or full detail (off)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--lod-ring", a.scene.lod_ring,
                    "Coarse levels' box half-width in their own chunks (default 12; each level reaches about "
                    "ring x 32 x 2^level blocks)");
    cmd->add_option("--threads", a.scene.threads, "Generation and meshing threads (0 = all cores; at most 256)")
        ->check(CLI::Range(0u, unsigned(engine::kMaxWorkerThreads)));
    return seed_opt;
}

// The camera and the image size.
void add_camera_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--eye", a.eye, "Camera position X,Y,Z in blocks (decimal; integer part read as 64-bit)");
    cmd->add_option("--target", a.target, "Point looked at, X,Y,Z in blocks");
    cmd->add_option("--up", a.up, "Up vector X,Y,Z");
    cmd->add_option("--fov", a.fov, "Vertical field of view, degrees");
    cmd->add_option("--size", a.size, "Image size WxH");
}

// Shadow samples and their random numbers, and the passes hits are traced in.
void add_sampling_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--spp", a.spp,
                    "Shadow samples per pixel at the first hit, per light, and as many sky rays (one primary ray "
                    "per pixel)")
        ->check(CLI::Range(uint32_t(0), uint32_t(65536))); // As --bounce-spp: 2^32 ran for hours.
    cmd->add_option("--sample-seed", a.sample_seed,
                    "Seed of the samples' random numbers (same seed, same image; accumulated frames add "
                    "their frame number)");
    cmd->add_option("--bounce-spp", a.bounce_spp, "The same on reflection bounces (default: as --spp)")
        ->check(CLI::Range(int64_t(0), int64_t(65536)));
    cmd->add_option("--samples-by", a.samples_by,
                    "count: --spp at the first hit, --bounce-spp on bounces; weight: every hit ceil(--spp x its "
                    "weight in the pixel), at least 1 (render::RenderSettings::samples_by_weight)")
        ->check(CLI::IsMember({"count", "weight"}));
    cmd->add_option("--weight-exponent", a.weight_exponent,
                    "With --samples-by weight: every hit ceil(--spp x weight^E) (0.8: the weak bounces get more "
                    "rays; render::RenderSettings::weight_exponent)")
        ->check(finite_range(0.05, 1.0, "an exponent from 0.05 to 1"));
    cmd->add_option("--first-hit-pass", a.first_hit_pass,
                    "on: trace the primary hits' light in a pass of its own, then the reflections (the same "
                    "image; --split-hits 1)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--split-hits", a.split_hits,
                    "Trace the first N hits of every path each in a pass of its own, then the rest (the same "
                    "image; render::RenderSettings::split_hits); 0: one pass")
        ->check(CLI::Range(0u, 64u));
    cmd->add_option("--see-through-check", a.see_through_check,
                    "on: trace without the see-through code first, then again with it only the pixels whose rays "
                    "met water or glass (the same image); off: with it everywhere; auto (default): on but on a CPU "
                    "device (render::RenderSettings::see_through_check)")
        ->check(CLI::IsMember({"auto", "on", "off"}));
    cmd->add_option("--see-through-check-share", a.see_through_check_share,
                    "Check while at most this share of the last frame's view rays met water or glass, else "
                    "trace in one dispatch (render::RenderSettings::see_through_check_share; default 0.25; "
                    "1: always)")
        ->check(finite_range(0.0, 1.0, "a share from 0 to 1"));
}

// The lights, shading, shadows and reflections.
void add_lighting_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--sun", a.sun, "Direction towards the sun X,Y,Z, or off (Full shading)");
    cmd->add_option("--sun-radius", a.sun_radius, "Angular radius of the sun's disc, degrees (soft shadows)");
    cmd->add_option("--sky-light", a.sky_light, "Sky term: scale of the sky's light on surfaces (0: none)");
    cmd->add_option("--sky-access", a.sky_access, "off: the view is sealed from the sky (no sun or sky rays)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--area-light", a.area_light, "The rectangular area light above the scene")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--shading", a.shading, "Shading")->check(CLI::IsMember({"flat", "full"}));
    cmd->add_option("--shadows", a.shadows, "Shadows of all lights and sky occlusion")->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--reflections", a.reflections, "Reflection depth (0..16): mirror blocks, and the surfaces of water and glass")
        ->check(CLI::Range(0u, render::kMaxMirrorBounces));
    cmd->add_option("--light", a.light, "Centre of the area light X,Y,Z (default: above the scene)");
}

// The device, the output, the benchmark's repeats and edits, and the pipeline.
void add_run_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--device", a.device, "auto, cpu, gpu or a device index (see vx info)");
    cmd->add_option("--out", a.out, "PNG file to write");
    cmd->add_option("--repeat", a.repeat, "Render N frames of the view; print medians of frames 2..N");
    cmd->add_option("--versus-raw", a.versus_raw,
                    "Then time the view against N spp raw (no denoiser, no light cache), the two frames "
                    "interleaved: --repeat pairs (at least 2), the median of each pair's ratio")
        ->check(CLI::Range(1u, 65536u));
    cmd->add_option("--edit-burst", a.edit_burst,
                    "Then edit one block in each of K chunks: GPU time and bytes uploaded of slice refits, whole-chunk "
                    "refits and rebuilds (--repeat rounds)");
    cmd->add_option("--blas-update", a.blas_update, "Build BLASes updatable (edits refit) or not (edits rebuild)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--pipeline", a.pipeline,
                    "rt: ray tracer; raster: the baseline (Phong, one point light at the area light's centre, depth "
                    "buffer, no shadows or reflections)")
        ->check(CLI::IsMember({"rt", "raster"}));
}

// The denoiser and the still camera's accumulation; emitter sampling and the light cache (less noise).
void add_denoiser_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--denoise", a.denoise,
                    "Guided a-trous denoiser on the ray tracer's full-shading radiance (SVGF-style)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--denoise-passes", a.denoise_passes,
                    "The denoiser's a-trous passes, steps 1, 2, 4, ... pixels (default 5; 1..8; with the light "
                    "cache fewer suffice: render::RenderSettings::denoise_passes)")
        ->check(CLI::Range(1u, render::kMaxDenoisePasses));
    cmd->add_option("--accumulate", a.accumulate,
                    "Render N frames of the still camera and average them (temporal pass; with --denoise on, "
                    "filtered too); the PNG is the last")
        ->check(CLI::Range(1u, 65536u));
    cmd->add_option("--history-clamp", a.history_clamp,
                    "on (default): the temporal pass drops or clamps history this frame says is stale (no ghosts "
                    "in a game); off: the plain mean of the frames (a converged reference)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--emitter-sampling", a.emitter_sampling,
                    "on (default): emissive blocks light by shadow rays aimed at their faces; off: only sky rays "
                    "that happen to hit them (same mean, noisier)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--light-cache", a.light_cache,
                    "on: hits share their light (all but the sun's) within the frame over patches of each face a "
                    "few pixels wide (far less noise, a small blur); off (default): each keeps its own samples")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--light-cache-pixels", a.light_cache_pixels,
                    "The light cache's patch width in pixels at its distance, up to the next power of two "
                    "blocks (default 3; from 1/64 to 4096, the renderer's bounds)")
        ->check(finite_range(render::kMinLightCachePixels, render::kMaxLightCachePixels,
                             "a patch width from 1/64 to 4096 pixels"));
}

// Exposure and haze, the lighting preset, and validation.
void add_exposure_options(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--exposure", a.exposure,
                    "Full shading's camera exposure: EV100 (default 14.7: albedo 0.18 in daylight at "
                    "mid-grey; +1 halves the light) or auto (metered from the frame)");
    cmd->add_option("--haze", a.haze,
                    "Aerial perspective of full shading: haze towards the sky colour with distance")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--visibility", a.visibility,
                    "The haze's visibility in blocks, where contrast falls to 2% (default 20000; inf: clear)");
    cmd->add_option("--lighting", a.lighting,
                    "default; thesis: one area light, no sun or sky light, 25 shadow samples at every hit, 5 "
                    "reflections (the thesis's Table 6.3; options given explicitly win)")
        ->check(CLI::IsMember({"default", "thesis"}));
    cmd->add_flag("--validation", a.validation, "Enable the Vulkan validation layer (also VX_VALIDATION=1)");
    cmd->add_flag("--pipeline-report", a.pipeline_report,
                  "Print each ray tracing pipeline variant's stack sizes and the driver's statistics "
                  "(register counts...)");
}

} // namespace

void add_render_command(CLI::App& app, std::function<int()>& action) {
    auto a = std::make_shared<RenderArgs>();
    auto seed = std::make_shared<uint64_t>(0);
    CLI::App* cmd = app.add_subcommand("render", "Ray trace a scene to PNG and print timings");
    // In this order: --help lists the options as declared.
    CLI::Option* seed_opt = add_scene_options(cmd, *a, *seed);
    add_camera_options(cmd, *a);
    add_sampling_options(cmd, *a);
    add_lighting_options(cmd, *a);
    add_run_options(cmd, *a);
    add_denoiser_options(cmd, *a);
    add_exposure_options(cmd, *a);
    auto given = [cmd](const char* name) { return cmd->get_option(name)->count() > 0; };
    cmd->callback([a, seed, seed_opt, given, &action] {
        if (seed_opt->count() > 0)
            a->scene.seed = *seed;
        apply_lighting_preset(*a, {given("--spp"), given("--reflections"), given("--sun"),
                                   given("--sky-light"), given("--area-light"),
                                   given("--haze") || given("--visibility")});
        action = [a] { return run_render(*a); };
    });
}

} // namespace vx::tools
