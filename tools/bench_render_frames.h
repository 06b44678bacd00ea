#pragma once
// Frame timing and converged references shared by the sections of `vx bench render`
// (tools/cmd_bench_render.cpp, tools/bench_render_equal_error.h). Main thread only (they render).

#include <cstdint>

#include "render/renderer.h"

namespace vx::tools {

struct Timing {
    double frame = -1, trace = -1, denoise = -1; // GPU ms (medians); -1 without timestamps.
    uint32_t warmup_frames = 0;                  // Rendered before the timed ones (not timed).
};

// One frame (Renderer::try_render) for the benches: on a failure (out of GPU memory, a lost
// device) prints the renderer's line and exits 1: a report with figures missing is no report, and
// Renderer::render would abort with a core dump.
render::RenderImage bench_frame(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                                render::GBufferImage* gbuffer = nullptr);

// Renders one frame, then more until `warmup_s` seconds (wall clock) have passed since it began,
// then `repeat` timed frames; returns their medians and the last image. Why the warm-up: in
// device call 56 (H200) the short rows of the equal-error bench, each timed after one frame,
// ran 1.1-3.6x slower than the same configurations in calls 57 and 58 (4 spp: 8.77 against 3.42
// ms). Call 58 timed every configuration both ways and found no difference (within 0.3%, the SM
// clock at 1980 MHz throughout), so the cause is not known; a configuration's own frames first
// keep whatever state the GPU was left in out of its figure (docs/render_report.md, stop 28).
Timing time_frames(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam, uint32_t repeat,
                   render::RenderImage* image, double warmup_s = 0.0);

// Frames of 8 shadow samples a reference of `spp` samples per pixel accumulates (at least 1).
uint32_t reference_frames(uint32_t spp);

// A converged reference: `s` (its bounces, lights and seed) with 8 shadow samples, accumulated
// over reference_frames(spp) + parity frames, no filter and no history clamp: the plain mean of
// the frames. References of successive poses pass alternating `parity` (0, 1): it changes the
// history length by one, which restarts the history, so no pose inherits the last one's frames.
// (The clamp keeps a game's history from ghosting, but it also pulls a still camera's mean of
// mirror light towards each frame's neighbourhood: references with it were off by 0.0068 RMSE on
// a lavapipe mirror field, docs/render_report.md, 2026-12-02 stop 20.) Returns the last frame;
// with `gbuffer`, that frame's G-buffer too (its display values: render::display_float).
render::RenderImage render_reference(render::Renderer& r, render::RenderSettings s, const render::Camera& cam,
                                     uint32_t spp, uint32_t parity = 0, render::GBufferImage* gbuffer = nullptr);

// A game's sample settings as the paths and defaults sections sweep them: shadow samples at the
// first hit and on bounces, the denoiser, and the frames of history (1: none).
struct GameSettings {
    uint32_t spp = 0, bounce_spp = 0;
    bool denoise = false;
    uint32_t history = 1;
    bool operator==(const GameSettings&) const = default;
};

// What the sandbox runs: vx::RenderSettings::recommended() (bounce samples resolved).
GameSettings sandbox_settings();

// `base` (size, lights, seed) with g's samples, denoiser and history, Full shading and `bounces`
// mirror bounces.
render::RenderSettings with_game_settings(const render::RenderSettings& base, const GameSettings& g,
                                          uint32_t bounces);

} // namespace vx::tools
