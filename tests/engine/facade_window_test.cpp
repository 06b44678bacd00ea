// The facade presenting to a GLFW window (under xvfb-run, lavapipe, validation on): frames reach
// the window, an edit shows in the very next presented frame and its removal in the one after,
// a resize is followed, and the validation layer reports nothing. CTest label vulkan.
#include <chrono>
#include <thread>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <vx/vx.h>

using Clock = std::chrono::steady_clock;

namespace {

bool settle(vx::Engine& e) {
    const auto limit = Clock::now() + std::chrono::minutes(3);
    while (Clock::now() < limit) {
        e.update();
        if (e.settled())
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

glm::u8vec4 centre(const vx::Image& img) { return img.at(img.width / 2, img.height / 2); }

struct Glfw {
    Glfw() { ok = glfwInit() == GLFW_TRUE; }
    ~Glfw() {
        if (ok)
            glfwTerminate();
    }
    bool ok = false;
};

} // namespace

TEST(FacadeWindow, EditsShowInTheNextPresentedFrame) {
    Glfw glfw;
    if (!glfw.ok)
        GTEST_SKIP() << "no X display for GLFW (run under xvfb-run)";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(96, 64, "vx facade test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);

    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::terrain(5);
    info.streaming.view_radius = 2;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    info.render.target = vx::RenderTarget::glfw_window(window);
    info.render.device = "cpu";
    info.render.validation = true;
    info.render.vsync = false;
    {
        auto created = vx::Engine::create(info);
        if (!created) {
            glfwDestroyWindow(window);
            GTEST_SKIP() << "no ray-tracing device that can present: " << created.error();
        }
        vx::Engine& e = **created;
        vx::RenderSettings rs;
        rs.shading = vx::RenderSettings::Shading::Flat; // Exact colours: albedo at the hit.
        e.set_render_settings(rs);
        vx::Viewer v;
        v.block = {0, vx::terrain_height(5, 0, 0) + 6, 0};
        v.forward = {0.3, -1, 0.2};
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(settle(e));

        vx::Image before, after, removed;
        for (int i = 0; i < 4; ++i) { // Fill both frames in flight.
            glfwPollEvents();
            vx::Status s = e.render_to_window(i == 3 ? &before : nullptr);
            ASSERT_TRUE(s) << s.error();
        }
        ASSERT_EQ(before.width, 96u);
        // The block under the centre pixel, and the air block in front of it.
        auto hit = e.raycast(v.block, v.offset, v.forward, 64);
        ASSERT_TRUE(hit);
        ASSERT_EQ(hit->kind, vx::RayHit::Kind::Hit);
        const auto lamp = e.find_block("lamp");
        ASSERT_TRUE(lamp);
        ASSERT_TRUE(e.set_block(hit->previous, *lamp));
        e.update();
        ASSERT_TRUE(e.render_to_window(&after)); // The very next frame.
        EXPECT_NE(centre(after), centre(before)) << "the placed block is not in the next frame";
        ASSERT_TRUE(e.set_block(hit->previous, 0));
        e.update();
        ASSERT_TRUE(e.render_to_window(&removed));
        EXPECT_EQ(centre(removed), centre(before)) << "the removed block is still shown";
        EXPECT_GE(e.stats().blas_refits + e.stats().blas_builds, 1u);

        // A resize: the next frames follow the framebuffer.
        glfwSetWindowSize(window, 64, 40);
        vx::Image resized;
        for (int i = 0; i < 6 && resized.width != 64; ++i) {
            glfwPollEvents();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            ASSERT_TRUE(e.render_to_window(&resized));
        }
        EXPECT_EQ(resized.width, 64u);
        EXPECT_EQ(resized.height, 40u);
        EXPECT_GE(e.stats().frame_ms, 0.0);
        EXPECT_EQ(e.stats().validation_errors, 0u);
        ASSERT_TRUE(e.shutdown());
    }
    glfwDestroyWindow(window);
}
