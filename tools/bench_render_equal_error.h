#pragma once
// The equal-error section of `vx bench render` (issue 18: Table 6.3 with the thesis's lighting,
// at equal error). For each thesis row with noise (shadows; shadows + reflections; all on, which
// is the same features plus the thesis's denoiser), the target is the one-frame RMSE of the
// thesis's own configuration (25 shadow samples at every hit, raw) against a converged reference
// of the same features; the search (tools/equal_error_pick.h) then finds the cheapest one-frame
// configuration of those features (shadow spp, bounce spp, denoiser) whose RMSE is at most the
// target, and sets its frame time over the RT flat row's beside the thesis's ratio (8.14x,
// 19.12x, 34.82x). Main thread only.

#include <cstdint>
#include <string>

#include "render/renderer.h"

namespace vx::tools {

struct EqualErrorBenchInfo {
    render::RenderSettings base; // Size, lights and seed; samples, bounces and denoiser set per row.
    render::Camera camera;
    uint32_t repeat = 5;          // Frames per timing (medians).
    uint32_t reflections = 5;     // Mirror bounces of the reflection rows and their reference.
    uint32_t reference_spp = 1024; // Per feature set: frames of 8 samples, accumulated, no filter.
    uint32_t seeds = 4;           // Sample seeds per RMSE (base.seed on; root mean square over them).
    std::string lighting;         // For the report: "thesis" or "default".
    std::string out;              // Directory for equal_error.csv.
    // The search's RMSE: of the output before its 8-bit rounding (render::display_float), or
    // false: of the 8-bit image. Both are measured and written; under the thesis's light the
    // errors are a fraction of an 8-bit step, where rounding distorts them (stop 27).
    bool display_metric = true;
    // Seconds of frames of a configuration before its timed ones (time_frames()); each is also
    // timed as before, right after the last one's error frames (EqualErrorCandidate::cold_ms).
    double warmup_s = 0.25;
};

// Upper bound on the frames run_equal_error_bench() renders besides its warm-up frames (the
// second before it starts, and each configuration's info.warmup_s; every candidate measured, the
// search skips some): for the caller to print before it starts.
uint64_t equal_error_frames_at_most(const EqualErrorBenchInfo& info);

// Renders the references, the RT flat row and the candidates with `r` (holding the scene),
// printing each; returns the report's markdown ("## Table 6.3 at equal error": the rows, then
// every measured candidate) and writes info.out/equal_error.csv (one line per measured candidate).
std::string run_equal_error_bench(render::Renderer& r, const EqualErrorBenchInfo& info);

} // namespace vx::tools
