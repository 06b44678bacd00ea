#include "bench_render_frames.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <vx/vx.h>

#include "cli_common.h"
#include "world/base/median.h"

namespace vx::tools {

render::RenderImage bench_frame(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam,
                                render::GBufferImage* gbuffer) {
    Result<render::RenderImage> img = r.try_render(s, cam, gbuffer);
    if (!img) {
        std::fprintf(stderr, "vx bench: a frame failed, no report: %s\n", img.error().c_str());
        std::fflush(stdout);
        std::exit(kExitFailure);
    }
    return std::move(*img);
}

Timing time_frames(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam, uint32_t repeat,
                   render::RenderImage* image, double warmup_s) {
    Timing t;
    const auto start = std::chrono::steady_clock::now();
    do {
        bench_frame(r, s, cam);
        ++t.warmup_frames;
    } while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < warmup_s);
    std::vector<double> frame, trace, denoise;
    for (uint32_t i = 0; i < repeat; ++i) {
        *image = bench_frame(r, s, cam);
        const render::RenderStats& st = r.last_stats();
        frame.push_back(st.gpu_frame_ms);
        trace.push_back(st.gpu_trace_ms);
        denoise.push_back(st.gpu_denoise_ms);
    }
    t.frame = median(frame);
    t.trace = median(trace);
    t.denoise = median(denoise);
    return t;
}

uint32_t reference_frames(uint32_t spp) { return std::max(1u, spp / 8); }

render::RenderImage render_reference(render::Renderer& r, render::RenderSettings s, const render::Camera& cam,
                                     uint32_t spp, uint32_t parity, render::GBufferImage* gbuffer) {
    s.shadow_samples = 8;
    s.accumulate = reference_frames(spp) + parity;
    s.denoise = false;
    s.history_clamp = false; // The plain mean (bench_render_frames.h).
    render::RenderImage img;
    for (uint32_t i = 0; i < s.accumulate; ++i)
        img = bench_frame(r, s, cam, i + 1 == s.accumulate ? gbuffer : nullptr);
    return img;
}

GameSettings sandbox_settings() {
    const ::vx::RenderSettings game = ::vx::RenderSettings::recommended();
    return {game.shadow_samples, game.bounce_shadow_samples.value_or(game.shadow_samples), game.denoise,
            std::max(game.accumulate, 1u)};
}

render::RenderSettings with_game_settings(const render::RenderSettings& base, const GameSettings& g,
                                          uint32_t bounces) {
    render::RenderSettings s = base;
    s.mode = render::ShadingMode::Full;
    s.shadow_samples = g.spp;
    s.bounce_shadow_samples = g.bounce_spp;
    s.max_bounces = bounces;
    s.denoise = g.denoise;
    s.accumulate = g.history;
    return s;
}

} // namespace vx::tools
