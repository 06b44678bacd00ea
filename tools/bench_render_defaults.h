#pragma once
// The defaults section of `vx bench render` (issue 18): the settings a game picks, swept over
// the two moving camera paths of the paths section (tools/bench_render_paths.h), and the pick by
// issue 18's rule (tools/defaults_rule.h): the cheapest settings whose moving-camera error is
// within 1.25x of the best measured at up to twice their cost.
//
// Candidates: shadow spp in {1, 2, 4, 8}, bounce spp in {1, spp}, the denoiser off (no history)
// or on with an 8-frame history, all at the facade's default reflection depth
// (vx::RenderSettings::max_bounces, which the sandbox keeps); and the sandbox's current settings
// (the facade's defaults with the denoiser on, samples/sandbox/game.cpp) when not among them.
// Each candidate first renders 8 still frames at a path's first pose (a player who stood, then
// moves: the history is full), uncounted, then the path. Cost: the median over both paths'
// frames of the GPU's trace + denoiser time (ms; the frame's submit-to-fence time where the
// queue has no timestamps), from a pass of its own that renders the paths back to back in three
// rounds, each taking every candidate in turn. Error: the larger of the two paths' per-frame
// RMSE p95 against one converged reference per pose, rendered once and shared by every
// candidate. Main thread only.

#include <cstdint>
#include <string>

#include "engine/scene_loader.h"
#include "render/renderer.h"

namespace vx::tools {

struct DefaultsBenchInfo {
    render::RenderSettings base; // Size and lights; samples, bounces and denoiser set per candidate.
    render::Camera camera;       // The default view (the paths start there).
    uint32_t frames = 24;        // Frames per path (>= 4).
    uint32_t reference_spp = 64; // Per pose: frames of 8 samples, accumulated, no filter.
    std::string out;             // Directory for defaults.csv.
};

// Renders the references and every candidate with `r` (whose scene `scene` holds), prints each
// candidate as it is measured, then the table and the pick. Returns the report's markdown
// ("## Sandbox defaults from the curves": the table, the pick, the frames rendered) and writes
// info.out/defaults.csv (one line per candidate).
std::string run_defaults_bench(render::Renderer& r, const engine::LoadedScene& scene, const DefaultsBenchInfo& info);

} // namespace vx::tools
