#pragma once
// The camera-path section of `vx bench render` (issue 18): what a moving player sees. Three paths
// over the scene, each frame compared with a converged reference at the same pose:
//   orbit:     the default view's eye circles the scene centre, kOrbitDegrees per frame;
//   fly-over:  the default view slides towards and over the centre, a fixed step per frame;
//              both after 8 still frames at their first pose, not counted (a player who stood,
//              then moves: a full history, not the renderer's start-up);
//   edit:      the default view, still, from a cold start (frame 7: the still camera's 8th
//              frame); a stone cube (a twelfth of the scene's width) appears on the surface at
//              the centre halfway in (edited through world::EditMesher, as the engine does).
// For each game-like configuration: per-frame RMSE median and p95; flicker (median RMS change
// between successive frames, beside the references' own); after the edit, the frames until the
// error in the pixels it changed is within 1.25x of its steady value (ghosting and the history's
// restart), and the ghost: frames whose error there exceeds the raw row's. Main thread only.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene_loader.h"
#include "render/image_metrics.h"
#include "render/renderer.h"

namespace vx::tools {

// One configuration every path runs: a name for the tables and its settings (size, lights, the
// whole of it).
struct PathRow {
    std::string name;
    render::RenderSettings s;
};

struct PathBenchInfo {
    render::RenderSettings base; // Size and lights; samples, bounces and denoiser set per row.
    render::Camera camera;       // The default view (paths start there).
    uint32_t frames = 24;        // Frames per path.
    uint32_t reference_spp = 64; // Per pose: frames of 8 samples, accumulated, no filter.
    uint32_t reflections = 5;    // Mirror bounces of every row and of the references.
    std::string out;             // Directory for paths.csv.
    // The configurations; empty: default_path_rows(). The last is the ghost's yardstick (raw).
    std::vector<PathRow> rows;
};

// 1 / 1, 4 / 4 and 8 / 1 spp (first hit / bounces) denoised with an 8-frame history, and 4 / 4 raw
// (last: the ghost's yardstick); the sandbox's (vx::RenderSettings::recommended()) marked among
// them or added before the raw row. info.reflections bounces.
std::vector<PathRow> default_path_rows(const PathBenchInfo& info);

// A camera path: one pose per frame.
struct CameraPath {
    std::string name;
    std::vector<render::Camera> poses;
    uint32_t edit_frame = 0; // Frame that first shows the edit; 0: no edit.
};

// The moving paths from `start` (the default view), `frames` poses each: the orbit about the
// scene's box centre, then the fly-over towards it (see the top of this file).
std::vector<CameraPath> moving_paths(const engine::LoadedScene& scene, const render::Camera& start, uint32_t frames);

// The converged reference of one pose: render_reference() (tools/bench_render_frames.h: the
// plain mean of max(1, spp / 8) + parity frames of 8 samples) of `base`'s lights and size in Full
// shading with 8 samples on each of `bounces` mirror bounces; adds the frames rendered to
// `*frames` when given.
render::ImageF path_reference(render::Renderer& r, const render::RenderSettings& base, uint32_t bounces, uint32_t spp,
                              const render::Camera& cam, uint32_t parity, uint64_t* frames = nullptr);

// The value at fraction p (0..1) of sorted `v`, nearest rank; -1 when empty.
double percentile(std::vector<double> v, double p);

// Renders the paths with `r` (whose scene `scene` holds) and returns the report's markdown
// ("## Camera paths", one table); writes info.out/paths.csv with every frame's RMSE. The edit
// path changes `scene`'s world, meshes and `r`'s chunks and undoes it at the end. Prints each row.
std::string run_path_bench(render::Renderer& r, engine::LoadedScene& scene, const PathBenchInfo& info);

} // namespace vx::tools
