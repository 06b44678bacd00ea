#include "bench_render_frames.h"

#include <algorithm>
#include <vector>

#include "world/base/median.h"

namespace vx::tools {

Timing time_frames(render::Renderer& r, const render::RenderSettings& s, const render::Camera& cam, uint32_t repeat,
                   render::RenderImage* image) {
    r.render(s, cam);
    std::vector<double> frame, trace, denoise;
    for (uint32_t i = 0; i < repeat; ++i) {
        *image = r.render(s, cam);
        const render::RenderStats& st = r.last_stats();
        frame.push_back(st.gpu_frame_ms);
        trace.push_back(st.gpu_trace_ms);
        denoise.push_back(st.gpu_denoise_ms);
    }
    return {median(frame), median(trace), median(denoise)};
}

uint32_t reference_frames(uint32_t spp) { return std::max(1u, spp / 8); }

render::RenderImage render_reference(render::Renderer& r, render::RenderSettings s, const render::Camera& cam,
                                     uint32_t spp) {
    s.shadow_samples = 8;
    s.accumulate = reference_frames(spp);
    s.denoise = false;
    s.history_clamp = false; // The plain mean (bench_render_frames.h).
    render::RenderImage img;
    for (uint32_t i = 0; i < s.accumulate; ++i)
        img = r.render(s, cam);
    return img;
}

} // namespace vx::tools
