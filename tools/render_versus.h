#pragma once
// `vx render --versus-raw N`: the frame time of the view's settings against N samples per pixel
// raw (no denoiser, no light cache), the two kinds of frame interleaved in one process. Issue
// 18's check is a ratio of two frame times ("at >= 4x less frame time than 25 spp raw"); timed
// in two processes a few seconds apart, each round's ratio on this shared 2-core VM ranged
// 3.42-4.02 around a median of 3.80 (docs/render_report.md, stop 66): the host's load drifts
// between the runs. Frames a tenth of a second apart see nearly the same load, so the ratio of
// each adjacent pair is what is reported. Main thread only (it renders).

#include <cstdint>
#include <string>
#include <vector>

#include "render/renderer.h"

namespace vx::tools {

struct VersusFigures {
    uint32_t pairs = 0;          // Timed pairs (after one untimed pair).
    double frame_ms = -1;        // The view's settings: wall ms a frame, median.
    double raw_ms = -1;          // N spp raw: wall ms a frame, median.
    double ratio = -1;           // raw over the view's, per pair: median,
    double ratio_q1 = -1, ratio_q3 = -1; // and quartiles (the medians of the lower and upper halves).
    double gpu_ratio = -1;       // The same of the GPU frame times (first to last timestamp); -1: none.
    std::string failure;         // The first failed frame's line (Renderer::try_render); figures -1.
};

// One frame of `s` seen from `cam` (Renderer::try_render); returns the call's wall time in ms (it
// waits for the GPU). A failed frame (out of GPU memory, a lost device) sets `failure` to the
// renderer's line; else `image`, if given, receives the frame. `vx render`'s frames all come here.
double timed_frame(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                   std::string& failure, render::RenderImage* image = nullptr);

// `s` with `spp` shadow samples at the first hit and on bounces, no denoiser, no accumulation
// and no light cache: the raw frame the denoised one is compared with.
render::RenderSettings raw_settings(const render::RenderSettings& s, uint32_t spp);

// One untimed frame of each, then `pairs` pairs of frames: the view's settings `s` and
// raw_settings(s, spp), which goes first alternating (so neither always follows the other).
// Stops at the first failed frame (out of GPU memory, a lost device) with its line.
VersusFigures versus_raw(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                         uint32_t spp, uint32_t pairs);

// One line for `vx render`: the medians, the ratio and its quartiles (and the GPU's ratio).
std::string format_versus(const VersusFigures& f, uint32_t spp);

// The lower quartile, median and upper quartile of `v` (quartiles: medians of the halves below
// and above the median, the median itself left out of both for an odd count); -1s when empty.
struct Quartiles {
    double q1 = -1, median = -1, q3 = -1;
};
Quartiles quartiles(std::vector<double> v);

} // namespace vx::tools
