#include "render_versus.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "world/base/median.h"

namespace vx::tools {

render::RenderSettings raw_settings(const render::RenderSettings& s, uint32_t spp) {
    render::RenderSettings raw = s;
    raw.shadow_samples = spp;
    raw.bounce_shadow_samples = spp;
    raw.samples_by_weight = false;
    raw.denoise = false;
    raw.accumulate = 1;
    raw.light_cache = false;
    return raw;
}

Quartiles quartiles(std::vector<double> v) {
    if (v.empty())
        return {};
    std::sort(v.begin(), v.end());
    const size_t half = v.size() / 2; // Each half's size; an odd count's middle is in neither.
    const std::vector<double> lower(v.begin(), v.begin() + std::ptrdiff_t(half));
    const std::vector<double> upper(v.end() - std::ptrdiff_t(half), v.end());
    const double mid = median(v);
    return {lower.empty() ? mid : median(lower), mid, upper.empty() ? mid : median(upper)};
}

double timed_frame(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                   std::string& failure, render::RenderImage* image) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    Result<render::RenderImage> img = r.try_render(s, cam);
    const double wall = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!img)
        failure = img.error();
    else if (image)
        *image = std::move(*img);
    return wall;
}

namespace {

struct Frame {
    double wall_ms = 0, gpu_ms = -1;
};

// One frame; false (with `failure` set) when the renderer could not make it.
bool frame(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam, Frame& out,
           std::string& failure) {
    out.wall_ms = timed_frame(r, s, cam, failure);
    if (!failure.empty())
        return false;
    out.gpu_ms = r.last_stats().gpu_frame_ms;
    return true;
}

} // namespace

VersusFigures versus_raw(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                         uint32_t spp, uint32_t pairs) {
    const render::RenderSettings raw = raw_settings(s, spp);
    VersusFigures f;
    std::vector<double> walls, raw_walls, ratios, gpu_ratios;
    bool gpu = true;
    for (uint32_t i = 0; i <= pairs; ++i) { // Pair 0: untimed (resources, pipelines, caches).
        Frame a, b;
        const bool raw_first = i % 2 == 1;
        if (!frame(r, raw_first ? raw : s, cam, raw_first ? b : a, f.failure) ||
            !frame(r, raw_first ? s : raw, cam, raw_first ? a : b, f.failure))
            return {.failure = f.failure};
        if (i == 0)
            continue;
        walls.push_back(a.wall_ms);
        raw_walls.push_back(b.wall_ms);
        ratios.push_back(b.wall_ms / a.wall_ms);
        gpu = gpu && a.gpu_ms > 0 && b.gpu_ms > 0;
        if (gpu)
            gpu_ratios.push_back(b.gpu_ms / a.gpu_ms);
    }
    f.pairs = pairs;
    f.frame_ms = median(walls);
    f.raw_ms = median(raw_walls);
    const Quartiles q = quartiles(ratios);
    f.ratio = q.median;
    f.ratio_q1 = q.q1;
    f.ratio_q3 = q.q3;
    f.gpu_ratio = gpu ? median(gpu_ratios) : -1;
    return f;
}

std::string format_versus(const VersusFigures& f, uint32_t spp) {
    char line[320];
    std::snprintf(line, sizeof line,
                  "  versus %u spp raw, frames interleaved (%u pairs): frame %.2f ms against %.2f ms wall "
                  "(medians); %.3fx less time (pair ratios: median; quartiles %.3f-%.3f)",
                  spp, f.pairs, f.frame_ms, f.raw_ms, f.ratio, f.ratio_q1, f.ratio_q3);
    std::string out = line;
    if (f.gpu_ratio > 0) {
        std::snprintf(line, sizeof line, "; GPU frame time %.3fx", f.gpu_ratio);
        out += line;
    }
    return out + "\n";
}

} // namespace vx::tools
