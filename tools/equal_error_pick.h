#pragma once
// The search behind `vx bench render --sections equal-error` (issue 18: Table 6.3 at equal
// error): which sample counts and denoiser settings to try, which to skip, and the cheapest one
// whose one-frame error meets a target. No GPU here: pure functions, thread-safe.

#include <cstdint>
#include <span>
#include <vector>

namespace vx::tools {

// One configuration of a feature set (shadows; or shadows and reflections) and what it measured.
struct EqualErrorCandidate {
    uint32_t spp = 0;        // Shadow samples at the first hit.
    uint32_t bounce_spp = 0; // Shadow samples on each reflection bounce; 0 without reflections.
    bool denoise = false;    // One frame through the denoiser (no history).
    double frame_ms = -1;    // Median GPU frame time; -1: not measured (skipped).
    double rmse = -1;        // One-frame RMSE against the reference in the search's metric; -1: not measured.
    bool light_cache = false; // Hits share their light through the light cache (render/light_cache.h).
    double rmse_display = -1; // Of the output before 8-bit rounding (render::display_float).
    double rmse_8bit = -1;    // Of the 8-bit output.
    // Each hit's samples by its weight in the pixel (render::RenderSettings::samples_by_weight):
    // `spp` is the count of a matte first hit; bounce_spp is 0. With weight_exponent
    // (render::RenderSettings::weight_exponent) below 1 the bounces get more of them.
    bool by_weight = false;
    float weight_exponent = 1.f;
    // Median GPU frame time of the first frames after the previous candidate's error frames
    // (after one frame, as frame_ms was before stop 28): beside frame_ms it shows whether the
    // GPU was slow to resume (tools/bench_render_frames.h, time_frames()).
    double cold_ms = -1;
};

// The thesis's sample count (its Table 6.3 rows traced 25 shadow rays at every hit).
inline constexpr uint32_t kThesisSpp = 25;

// Shadow spp in {1, 2, 4, 8, 16, 25}; with reflections, bounce spp in {1, 2, 4, 8, 16, spp} up to spp
// (without: 0); raw, then denoised; all without, then all with the light cache. In measuring
// order: no candidate precedes one with fewer samples of the same denoiser and cache setting, so
// equal_error_skip() can bound a candidate by earlier ones. The thesis's configuration (25, 25
// or 0, raw, no cache) is among them. With reflections, last: samples by weight (spp in {16, 25,
// 32, 40, 44, 48, 52, 54, 56, 64}, raw then denoised, no cache), then by weight^0.8 (spp in {32,
// 36, 40, 42, 44, 46, 48, 52, 56}, raw then denoised, no cache).
std::vector<EqualErrorCandidate> equal_error_candidates(bool reflections);

// True when `c` cannot be cheaper than `best_ms` (the cheapest frame time meeting the target so
// far; <= 0: none yet): a measured candidate of the same sample allocation (by weight or not)
// with no more samples of either kind, and no denoiser or light cache where `c` has none,
// already took at least `best_ms`. More rays, the denoiser and
// the cache only add work.
bool equal_error_skip(const EqualErrorCandidate& c, std::span<const EqualErrorCandidate> measured, double best_ms);

// The measured candidate of least frame time whose RMSE is at most `target_rmse`; nullptr when
// none is (an empty span, or every one is worse or unmeasured). Ties: the first.
const EqualErrorCandidate* cheapest_meeting(std::span<const EqualErrorCandidate> candidates, double target_rmse);

} // namespace vx::tools
