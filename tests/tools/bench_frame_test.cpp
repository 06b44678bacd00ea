// The benches' frame (tools/bench_render_frames.h): a frame the renderer cannot make ends the
// process with the renderer's line and exit 1. Renderer::render aborted (a core dump, no code a
// script could read). Lavapipe, validation on.
#include <gtest/gtest.h>

#include "bench_render_frames.h"
#include "cli_common.h"

namespace vx::tools {
namespace {

TEST(BenchFrame, AFailedFrameExitsOneWithTheRenderersLine) {
    auto renderer = render::Renderer::create({.validation = true});
    ASSERT_TRUE(renderer) << renderer.error();
    render::Renderer& r = **renderer;
    render::RenderSettings s;
    s.width = 16;
    s.height = 12;
    const render::Camera cam = render::Camera::look_at(glm::dvec3(0.5, 8.5, 0.5), glm::dvec3(8.5, 0.5, 8.5));
    const render::RenderImage image = bench_frame(r, s, cam); // The same renderer makes a frame first.
    EXPECT_EQ(image.width, 16u);
    r.fail_allocations("render target");
    s.width = 24; // New frame resources, which now fail.
    EXPECT_EXIT(bench_frame(r, s, cam), ::testing::ExitedWithCode(kExitFailure),
                "vx bench: a frame failed, no report: .*out of GPU memory");
}

} // namespace
} // namespace vx::tools
