#pragma once
// The camera-path section of `vx bench render` (issue 18): what a moving player sees. Three paths
// over the scene, each frame compared with a converged reference at the same pose:
//   orbit:     the default view's eye circles the scene centre, kOrbitDegrees per frame;
//   fly-over:  the default view slides towards and over the centre, a fixed step per frame;
//   edit:      the default view, still; a stone cube (a twelfth of the scene's width) appears on
//              the surface at the centre a third of the way in (edited through world::EditMesher,
//              as the engine does).
// For each game-like configuration: per-frame RMSE median and p95; flicker (median RMS change
// between successive frames, beside the references' own); after the edit, the frames until the
// error in the pixels it changed is within 1.25x of its steady value (ghosting and the history's
// restart), and the ghost: frames whose error there exceeds the raw row's. Main thread only.

#include <cstdint>
#include <string>

#include "engine/scene_loader.h"
#include "render/renderer.h"

namespace vx::tools {

struct PathBenchInfo {
    render::RenderSettings base; // Size and lights; samples, bounces and denoiser set per row.
    render::Camera camera;       // The default view (paths start there).
    uint32_t frames = 24;        // Frames per path.
    uint32_t reference_spp = 64; // Per pose: frames of 8 samples, accumulated, no filter.
    uint32_t reflections = 5;    // Mirror bounces of every row and of the references.
    std::string out;             // Directory for paths.csv.
};

// Renders the paths with `r` (whose scene `scene` holds) and returns the report's markdown
// ("## Camera paths", one table); writes info.out/paths.csv with every frame's RMSE. The edit
// path changes `scene`'s world, meshes and `r`'s chunks and undoes it at the end. Prints each row.
std::string run_path_bench(render::Renderer& r, engine::LoadedScene& scene, const PathBenchInfo& info);

} // namespace vx::tools
