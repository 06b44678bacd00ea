// `vx bench render` section 5: camera paths (tools/bench_render_paths.h).
#include "bench_render_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "bench_render_frames.h"
#include "cli_common.h"
#include "render/image_metrics.h"
#include "world/base/median.h"
#include "world/mesh/edit_mesher.h"

namespace vx::tools {
namespace {

using render::ImageF;

constexpr double kOrbitDegrees = 3.0; // Per frame: a brisk turn (a whole orbit in 2 s at 60 fps).
constexpr double kFlyStep = 0.02;     // Per frame, of the eye's distance to the centre.
constexpr double kRecovered = 1.25;   // After the edit: error within this of its median before.
// Still frames at a moving path's first pose before it, not counted: a player who stood, then
// moves (the history is full, as in the defaults section). Without them the first frames are
// the renderer's start-up, the same as a still camera's first frames (at 1 / 1 spp denoised on
// the H200 they were the path's p95: 0.0257, 0.0219, 0.0200 against about 0.017 after).
constexpr uint32_t kMovingWarmup = 8;

// The top solid block of the column through the scene's centre, or nullopt.
std::optional<world::BlockPos> surface_at_centre(const engine::LoadedScene& scene) {
    const glm::i64vec3 c = (scene.box_min + scene.box_max) / int64_t(2);
    for (int64_t y = scene.box_max.y - 1; y >= scene.box_min.y; --y)
        if (scene.world->get_block({c.x, y, c.z}) != world::kAir)
            return world::BlockPos{c.x, y, c.z};
    return std::nullopt;
}

// The edit's cube side: a twelfth of the scene's width (a few pixels at any image size), 3..16.
int64_t cube_side(const engine::LoadedScene& scene) {
    return std::clamp<int64_t>((scene.box_max.x - scene.box_min.x) / 12, 3, 16);
}

// Sets the blocks of the cube standing on `top` (x fastest, then z, then y) to `ids` (one id for
// all, or one per block) through the engine's edit path, and hands the changed slices to the
// renderer. Returns the blocks they held, so a second call puts them back.
std::vector<world::BlockId> set_cube(render::Renderer& r, engine::LoadedScene& scene, world::BlockPos top,
                                     const std::vector<world::BlockId>& ids) {
    world::EditMesher em(scene.isolated);
    const int64_t side = cube_side(scene), lo = -side / 2;
    std::vector<world::BlockId> previous;
    for (int64_t y = 1; y <= side; ++y)
        for (int64_t z = lo; z < lo + side; ++z)
            for (int64_t x = lo; x < lo + side; ++x) {
                const world::BlockPos p = top + world::BlockPos{x, y, z};
                const world::BlockId id = ids.size() == 1 ? ids[0] : ids[previous.size()];
                previous.push_back(scene.world->get_block(p));
                const world::EditResult e = em.apply(*scene.world, p, id, scene.meshes);
                for (const world::SliceUpdate& u : e.updates) {
                    const world::ChunkMesh& mesh = scene.meshes[u.chunk].mesh;
                    if (u.full)
                        r.set_chunk(u.chunk, mesh);
                    else
                        r.set_chunk(u.chunk, mesh, std::span<const int>(u.slices.data(), size_t(u.count)));
                }
            }
    // As the engine's edit path tells it (engine/engine_sink.h): the denoiser drops the history
    // near the cube.
    r.note_edit(top + world::BlockPos{lo, 1, lo}, top + world::BlockPos{lo + side - 1, side, lo + side - 1});
    return previous;
}

// Median RMS change between successive images.
double flicker(const std::vector<ImageF>& images) {
    std::vector<double> change;
    for (size_t i = 1; i < images.size(); ++i)
        change.push_back(render::rmse(images[i], images[i - 1]));
    return median(change);
}

// The report's opening, up to the table's header: what the paths are and what the columns say.
std::string paths_intro(const engine::LoadedScene& scene, const PathBenchInfo& info, uint32_t n) {
    return "## Camera paths\n\nEach frame against a converged reference at its pose (" +
           std::to_string(std::max(1u, info.reference_spp / 8) * 8) + " samples per pixel, " +
           std::to_string(info.reflections) + " reflection bounces). " + std::to_string(n) +
           " frames per path: orbit " + std::to_string(int(kOrbitDegrees)) +
           " degrees per frame around the centre; fly-over towards the centre, 2% of the view distance "
           "per frame; each after " + std::to_string(kMovingWarmup) +
           " still frames at its first pose, not counted (a player who stood, then moves); edit: the "
           "still default view from a cold start (its frame 7 is the still camera's 8th frame), a "
           "stone cube of side " +
           std::to_string(cube_side(scene)) + " added on the surface at the centre in frame " +
           std::to_string(n / 2) +
           ". Flicker: median RMS change between successive frames (the references': the change the "
           "motion itself makes). Recovery: frames after the edit until the error in the pixels it "
           "changed (references before and after differ by > 0.1) is within 1.25x of its steady "
           "value (median over n/2 more frames of the edited view after the path): it counts the "
           "history's restart too. Ghost: frames after the edit whose error there exceeds the raw "
           "row's (worse than no history).\n\n"
           "| path | configuration | RMSE median | RMSE p95 | flicker | reference flicker | recovery "
           "frames | ghost frames |\n|---|---|---|---|---|---|---|---|\n";
}

// What every path and row of run_path_bench() renders with: `top`, the surface the edit path's
// cube stands on (none: no edit path); `n`, frames per path.
struct PathRun {
    render::Renderer& r;
    engine::LoadedScene& scene;
    const PathBenchInfo& info;
    std::optional<world::BlockPos> top;
    world::BlockId stone;
    uint32_t n;
};

// One reference per pose (two for the still edit path: before and after, and `mask`, the pixels
// the edit changed).
std::vector<ImageF> path_references(const PathRun& run, const CameraPath& path, std::vector<bool>& mask) {
    const PathBenchInfo& info = run.info;
    std::vector<ImageF> refs;
    if (path.edit_frame > 0) {
        const ImageF before = path_reference(run.r, info.base, info.reflections, info.reference_spp, path.poses[0], 0);
        const std::vector<world::BlockId> held = set_cube(run.r, run.scene, *run.top, {run.stone});
        const ImageF after = path_reference(run.r, info.base, info.reflections, info.reference_spp, path.poses[0], 1);
        set_cube(run.r, run.scene, *run.top, held);
        mask = render::changed_pixels(before, after);
        for (uint32_t i = 0; i < run.n; ++i)
            refs.push_back(i < path.edit_frame ? before : after);
    } else {
        for (uint32_t i = 0; i < run.n; ++i)
            refs.push_back(
                path_reference(run.r, info.base, info.reflections, info.reference_spp, path.poses[i], i % 2));
    }
    return refs;
}

// One row's figures on one path.
struct PathResult {
    std::string row, recovery;
    double median = 0, p95 = 0, flicker = 0;
    std::vector<double> edited;
};

// Renders `row` along `path` against `refs` (every frame's RMSE to `csv`); on the edit path also
// its recovery, from the steady error of n / 2 more still frames, the edit then undone.
PathResult run_path_row(const PathRun& run, const CameraPath& path, const PathRow& row,
                        const std::vector<ImageF>& refs, const std::vector<bool>& mask, ReportFile& csv) {
    const uint32_t n = run.n;
    std::vector<world::BlockId> held; // What the cube's blocks were before the edit.
    std::vector<ImageF> frames;
    std::vector<double> error, edited; // Whole image; the edit's pixels.
    if (path.edit_frame == 0) // A moving path; the still edit path starts cold (its 8th frame).
        for (uint32_t i = 0; i < kMovingWarmup; ++i)
            bench_frame(run.r, row.s, path.poses[0]);
    for (uint32_t i = 0; i < n; ++i) {
        if (path.edit_frame > 0 && i == path.edit_frame)
            held = set_cube(run.r, run.scene, *run.top, {run.stone});
        frames.push_back(render::to_float(bench_frame(run.r, row.s, path.poses[i])));
        error.push_back(render::rmse(frames.back(), refs[i]));
        if (!mask.empty())
            edited.push_back(render::masked_rmse(frames.back(), refs[i], mask));
        csv << path.name << ",\"" << row.name << "\"," << i << ',' << error.back() << ','
            << (mask.empty() ? -1.0 : edited.back()) << '\n';
    }
    std::string recovery = "";
    if (path.edit_frame > 0) {
        // The steady error of the edited view: n / 2 more frames, still, after the path.
        std::vector<double> steady;
        for (uint32_t i = 0; i < n / 2; ++i)
            steady.push_back(render::masked_rmse(render::to_float(bench_frame(run.r, row.s, path.poses[0])),
                                                 refs[n - 1], mask));
        set_cube(run.r, run.scene, *run.top, held);
        const double normal = kRecovered * median(steady);
        uint32_t k = path.edit_frame;
        while (k < n && edited[k] > normal)
            ++k;
        recovery = k < n ? std::to_string(k - path.edit_frame) : "> " + std::to_string(n - path.edit_frame);
        if (std::find(mask.begin(), mask.end(), true) == mask.end())
            recovery = "edit not visible";
    }
    return {row.name, recovery, median(error), percentile(error, 0.95), flicker(frames), edited};
}

// The path's rows of the table (printed as well), with each row's ghost.
std::string path_table(const CameraPath& path, const std::vector<PathResult>& results,
                       const std::vector<ImageF>& refs, uint32_t n) {
    std::string md;
    char line[512];
    for (const PathResult& res : results) {
        // The ghost: frames from the edit on whose error in the edited pixels exceeds the raw
        // row's (the last row), i.e. worse than no history at all.
        std::string ghost = "";
        if (path.edit_frame > 0) {
            const std::vector<double>& raw = results.back().edited;
            uint32_t k = path.edit_frame;
            while (k < n && res.edited[k] > raw[k])
                ++k;
            ghost = k < n ? std::to_string(k - path.edit_frame) : "> " + std::to_string(n - path.edit_frame);
        }
        std::snprintf(line, sizeof line, "| %s | %s | %.4f | %.4f | %.4f | %.4f | %s | %s |\n",
                      path.name.c_str(), res.row.c_str(), res.median, res.p95, res.flicker, flicker(refs),
                      res.recovery.c_str(), ghost.c_str());
        md += line;
        std::printf("  %s", line);
    }
    return md;
}

} // namespace

std::vector<PathRow> default_path_rows(const PathBenchInfo& info) {
    auto name_of = [](const GameSettings& g) {
        return std::to_string(g.spp) + " / " + std::to_string(g.bounce_spp) + " spp, " +
               (g.denoise ? "denoiser on, history " + std::to_string(g.history) : std::string("raw"));
    };
    // The sandbox's settings, at this bench's bounce depth: marked where the fixed rows have
    // them, else added before the raw row (the last).
    const GameSettings sandbox = sandbox_settings();
    std::vector<GameSettings> configs = {{1, 1, true, 8}, {4, 4, true, 8}, {8, 1, true, 8}, {4, 4, false, 1}};
    if (std::find(configs.begin(), configs.end(), sandbox) == configs.end())
        configs.insert(configs.end() - 1, sandbox);
    std::vector<PathRow> rows;
    for (const GameSettings& g : configs)
        rows.push_back(
            {(g == sandbox ? "sandbox: " : "") + name_of(g), with_game_settings(info.base, g, info.reflections)});
    return rows;
}

std::vector<CameraPath> moving_paths(const engine::LoadedScene& scene, const render::Camera& start, uint32_t frames) {
    // The start's eye and the point it looks at (Camera: block + offset, forward).
    const glm::dvec3 eye = glm::dvec3(start.block) + glm::dvec3(start.offset);
    const glm::dvec3 centre = glm::dvec3(scene.box_min + scene.box_max) * 0.5;
    std::vector<CameraPath> paths(2);
    paths[0].name = "orbit";
    paths[1].name = "fly-over";
    for (uint32_t i = 0; i < frames; ++i) {
        const double a = glm::radians(kOrbitDegrees * double(i));
        const glm::dvec3 d = eye - centre;
        const glm::dvec3 rotated(d.x * std::cos(a) - d.z * std::sin(a), d.y, d.x * std::sin(a) + d.z * std::cos(a));
        paths[0].poses.push_back(render::Camera::look_at(centre + rotated, centre));
        glm::dvec3 ahead = centre - eye;
        ahead.y = 0.0;
        const glm::dvec3 step = kFlyStep * glm::length(d) * double(i) * glm::normalize(ahead);
        paths[1].poses.push_back(render::Camera::look_at(eye + step, centre + step));
    }
    return paths;
}

render::ImageF path_reference(render::Renderer& r, const render::RenderSettings& base, uint32_t bounces, uint32_t spp,
                              const render::Camera& cam, uint32_t parity, uint64_t* frames) {
    render::RenderSettings s = base;
    s.mode = render::ShadingMode::Full;
    s.bounce_shadow_samples = 8;
    s.max_bounces = bounces;
    if (frames)
        *frames += reference_frames(spp) + parity;
    return render::to_float(render_reference(r, s, cam, spp, parity));
}

double percentile(std::vector<double> v, double p) {
    if (v.empty())
        return -1;
    std::sort(v.begin(), v.end());
    return v[size_t(std::lround(p * double(v.size() - 1)))];
}

std::string run_path_bench(render::Renderer& r, engine::LoadedScene& scene, const PathBenchInfo& info) {
    const uint32_t n = std::max(info.frames, 4u);
    std::vector<CameraPath> paths = moving_paths(scene, info.camera, n);
    paths.push_back({"edit", std::vector<render::Camera>(n, info.camera), 0});
    const std::optional<world::BlockPos> top = surface_at_centre(scene);
    const world::BlockId stone = scene.world->registry().find("stone").value_or(world::BlockId(1));
    if (top)
        paths[2].edit_frame = n / 2; // After a full history (8 frames) at the default 24.
    else
        paths.pop_back(); // Nothing solid under the centre: no surface to build on.

    std::string md = paths_intro(scene, info, n);
    ReportFile csv(info.out + "/paths.csv");
    csv << "path,configuration,frame,rmse,edited_rmse\n"; // edited_rmse: the edit's pixels (edit path).
    const std::vector<PathRow> rows = info.rows.empty() ? default_path_rows(info) : info.rows;
    const PathRun run{r, scene, info, top, stone, n};
    for (const CameraPath& path : paths) {
        // References first: one per pose (two for the still edit path: before and after).
        std::vector<bool> mask;
        const std::vector<ImageF> refs = path_references(run, path, mask);
        std::vector<PathResult> results;
        for (const PathRow& row : rows)
            results.push_back(run_path_row(run, path, row, refs, mask, csv));
        md += path_table(path, results, refs, n);
    }
    return md;
}

} // namespace vx::tools
