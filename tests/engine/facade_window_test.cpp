// The facade presenting to a GLFW window (under xvfb-run, lavapipe, validation on): frames reach
// the window, an edit shows in the very next presented frame and its removal in the one after,
// a resize is followed, set_vsync switches the present mode in place, a lost device is
// recovered with recreate_renderer, and the validation layer reports nothing. CTest label vulkan.
#include <chrono>
#include <cstdlib>
#include <thread>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <vx/vx.h>

#include "engine/engine_testing.h"
#include "facade_test_util.h"

using Clock = std::chrono::steady_clock;

namespace {

using vx::test::settle;

glm::u8vec4 centre(const vx::Image& img) { return img.at(img.width / 2, img.height / 2); }

// GLFW once per process: under Xvfb a second glfwInit after glfwTerminate finds no display.
struct Glfw {
    Glfw() {
        static const bool init = [] {
            const bool done = glfwInit() == GLFW_TRUE;
            if (done)
                std::atexit(glfwTerminate);
            return done;
        }();
        ok = init;
    }
    bool ok = false;
};

// Terrain of seed 5 around a small view, presented to `window` on lavapipe with validation.
vx::EngineCreateInfo window_info(GLFWwindow* window, int view_radius) {
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::terrain(5);
    info.streaming.view_radius = view_radius;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    info.render.target = vx::RenderTarget::glfw_window(window);
    info.render.device = vx::test::test_device();
    info.render.validation = true;
    info.render.vsync = false;
    return info;
}

} // namespace

TEST(FacadeWindow, EditsShowInTheNextPresentedFrame) {
    Glfw glfw;
    if (!glfw.ok)
        GTEST_SKIP() << "no X display for GLFW (run under xvfb-run)";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(96, 64, "vx facade test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);

    const vx::EngineCreateInfo info = window_info(window, 2);
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
        // Screen rays need the window's frame size, known once a frame was presented.
        auto early = e.screen_ray({48, 32});
        ASSERT_FALSE(early);
        EXPECT_NE(early.error().find("no frame presented yet"), std::string::npos) << early.error();

        vx::Image before, after, removed;
        for (int i = 0; i < 4; ++i) { // Fill both frames in flight.
            glfwPollEvents();
            vx::Status s = e.render_to_window(i == 3 ? &before : nullptr);
            ASSERT_TRUE(s) << s.error();
        }
        ASSERT_EQ(before.width, 96u);
        auto centre_ray = e.screen_ray({48, 32}); // The centre of 96 x 64: the forward direction.
        ASSERT_TRUE(centre_ray) << centre_ray.error();
        EXPECT_NEAR(glm::length(centre_ray->direction - glm::normalize(v.forward)), 0.0, 1e-9);
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
        auto resized_ray = e.screen_ray({32, 20}); // The centre of the new 64 x 40 frame.
        ASSERT_TRUE(resized_ray) << resized_ray.error();
        EXPECT_NEAR(glm::length(resized_ray->direction - glm::normalize(v.forward)), 0.0, 1e-9);
        EXPECT_GE(e.stats().frame_ms, 0.0);
        EXPECT_EQ(e.stats().validation_errors, 0u);
        ASSERT_TRUE(e.shutdown());
    }
    glfwDestroyWindow(window);
}

// Engine::set_ui: a half-transparent red quad blends over the presented frame (and its capture)
// inside its clip rectangle only, a textured quad shows the UI texture's texel, an empty list
// removes them, and a malformed list is refused.
TEST(FacadeWindow, UiIsBlendedOverTheFrame) {
    Glfw glfw;
    if (!glfw.ok)
        GTEST_SKIP() << "no X display for GLFW (run under xvfb-run)";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(64, 48, "vx ui test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    const vx::EngineCreateInfo info = window_info(window, 1);
    {
        auto created = vx::Engine::create(info);
        if (!created) {
            glfwDestroyWindow(window);
            GTEST_SKIP() << "no ray-tracing device that can present: " << created.error();
        }
        vx::Engine& e = **created;
        vx::Viewer v;
        v.block = {0, vx::terrain_height(5, 0, 0) + 200, 0}; // Sky only: a flat background.
        v.forward = {0, 1, -0.2};
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(settle(e));
        vx::Image plain, drawn, removed;
        glfwPollEvents();
        vx::Status first = e.render_to_window(&plain);
        ASSERT_TRUE(first) << first.error();

        // One texel, green; uv (0.5, 0.5) of it on the second quad, the white default nowhere.
        const uint8_t texel[4] = {5, 240, 30, 255};
        ASSERT_TRUE(e.set_ui_texture(1, 1, texel));
        vx::UiDrawList ui;
        auto quad = [&](glm::vec2 p0, glm::vec2 p1, glm::vec2 uv, uint32_t rgba) {
            const uint32_t b = uint32_t(ui.vertices.size());
            ui.vertices.push_back({p0, uv, rgba});
            ui.vertices.push_back({{p1.x, p0.y}, uv, rgba});
            ui.vertices.push_back({p1, uv, rgba});
            ui.vertices.push_back({{p0.x, p1.y}, uv, rgba});
            for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
                ui.indices.push_back(b + i);
        };
        quad({4, 6}, {14, 11}, {0.5f, 0.5f}, 0x80ffffffu); // White x green texel, alpha 128.
        quad({40, 30}, {43, 33}, {0.5f, 0.5f}, 0xff0000ffu); // Red x green = (5, 0, 0), opaque.
        ui.cmds.push_back({0, 6, {0, 0, 64, 8}});  // The first quad clipped to rows 0..7.
        ui.cmds.push_back({6, 6, {0, 0, 64, 48}});
        ASSERT_TRUE(e.set_ui(ui));
        ASSERT_TRUE(e.render_to_window(&drawn));
        ASSERT_EQ(drawn.width, 64u);
        // Blended: texel * a + frame * (1 - a), a = 128 / 255, per 8-bit channel (+-1 rounding).
        const glm::u8vec4 sky = plain.at(5, 7), got = drawn.at(5, 7);
        for (int c = 0; c < 3; ++c) {
            const float want = texel[c] * (128.f / 255.f) + sky[c] * (127.f / 255.f);
            EXPECT_NEAR(float(got[c]), want, 1.5f) << "channel " << c;
        }
        EXPECT_EQ(got.a, sky.a);
        EXPECT_EQ(drawn.at(5, 8), plain.at(5, 8));   // Below the clip rectangle: untouched.
        EXPECT_EQ(drawn.at(14, 7), plain.at(14, 7)); // Right of the quad.
        EXPECT_EQ(drawn.at(41, 31), glm::u8vec4(5, 0, 0, 255));

        ASSERT_TRUE(e.set_ui(vx::UiDrawList{}));
        ASSERT_TRUE(e.render_to_window(&removed));
        EXPECT_EQ(removed.at(5, 7), plain.at(5, 7));

        vx::UiDrawList bad = ui;
        bad.indices[3] = 99; // Past the 8 vertices.
        EXPECT_FALSE(e.set_ui(bad));
        bad = ui;
        bad.cmds[1].index_count = 7;
        EXPECT_FALSE(e.set_ui(bad));
        EXPECT_FALSE(e.set_ui_texture(2, 2, texel));
        EXPECT_EQ(e.stats().validation_errors, 0u);
        ASSERT_TRUE(e.shutdown());
    }
    glfwDestroyWindow(window);
}

// set_vsync: the swapchain is recreated with the other present mode at the next frame, frames
// keep coming, and the engine (its world, its edits) is the same object throughout. Lavapipe
// under Xvfb offers FIFO and IMMEDIATE (and MAILBOX), so vsync off leaves FIFO.
TEST(FacadeWindow, SetVsyncSwitchesThePresentModeWithoutARestart) {
    Glfw glfw;
    if (!glfw.ok)
        GTEST_SKIP() << "no X display for GLFW (run under xvfb-run)";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(64, 48, "vx vsync test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    {
        vx::EngineCreateInfo info = window_info(window, 1);
        info.render.vsync = true;
        auto created = vx::Engine::create(info);
        if (!created) {
            glfwDestroyWindow(window);
            GTEST_SKIP() << "no ray-tracing device that can present: " << created.error();
        }
        vx::Engine& e = **created;
        vx::Viewer v;
        v.block = {0, vx::terrain_height(5, 0, 0) + 6, 0};
        v.forward = {0.3, -1, 0.2};
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(settle(e));
        // An edit that is never saved (terrain world): it must survive the switch.
        const vx::BlockPos edit{0, vx::terrain_height(5, 0, 0) + 2, 0};
        ASSERT_TRUE(e.set_block(edit, *e.find_block("lamp")));
        glfwPollEvents();
        ASSERT_TRUE(e.render_to_window());
        EXPECT_TRUE(e.stats().vsync);

        ASSERT_TRUE(e.set_vsync(false));
        for (int i = 0; i < 3; ++i) {
            glfwPollEvents();
            ASSERT_TRUE(e.render_to_window());
        }
        EXPECT_FALSE(e.stats().vsync); // IMMEDIATE or MAILBOX: the swapchain was recreated.
        ASSERT_TRUE(e.set_vsync(true));
        vx::Image shot;
        glfwPollEvents();
        ASSERT_TRUE(e.render_to_window(&shot));
        EXPECT_TRUE(e.stats().vsync);
        EXPECT_EQ(shot.width, 64u);
        EXPECT_EQ(e.get_block(edit), e.find_block("lamp"));
        EXPECT_EQ(e.stats().validation_errors, 0u);
    }
    glfwDestroyWindow(window);
}

// set_vsync needs a window target: a headless engine says so and keeps going.
TEST(FacadeWindow, SetVsyncWithoutAWindowIsAnError) {
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::terrain(5);
    info.render.target = vx::RenderTarget::none();
    auto created = vx::Engine::create(info);
    ASSERT_TRUE(created) << created.error();
    const vx::Status s = (*created)->set_vsync(false);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("window"), std::string::npos) << s.error();
}

// Frame resources out of memory under a window, then a lost device: render_to_window fails with the loss line (the frame's acquired
// image and semaphore are released with the old renderer), recreate_renderer() makes a new
// swapchain on the same window, and it presents the picture of before the loss.
TEST(FacadeWindow, DeviceLossThenRecreateRendererPresentsAgain) {
    Glfw glfw;
    if (!glfw.ok)
        GTEST_SKIP() << "no X display for GLFW (run under xvfb-run)";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(64, 48, "vx device loss test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    {
        auto created = vx::Engine::create(window_info(window, 1));
        if (!created) {
            glfwDestroyWindow(window);
            GTEST_SKIP() << "no ray-tracing device that can present: " << created.error();
        }
        vx::Engine& e = **created;
        vx::RenderSettings rs;
        rs.shading = vx::RenderSettings::Shading::Flat;
        e.set_render_settings(rs);
        vx::Viewer v;
        v.block = {0, vx::terrain_height(5, 0, 0) + 6, 0};
        v.forward = {0.3, -1, 0.2};
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(settle(e));
        // Out of memory for the first frame's target and TLAS (both made before the acquire):
        // the call fails holding no swapchain image, and the next one presents.
        for (const char* resource : {"render target", "TLAS"}) {
            ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, resource));
            glfwPollEvents();
            const vx::Status s = e.render_to_window();
            ASSERT_FALSE(s);
            EXPECT_NE(s.error().find("out of GPU memory"), std::string::npos) << s.error();
        }
        ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, ""));
        vx::Image before, after;
        glfwPollEvents();
        ASSERT_TRUE(e.render_to_window(&before));

        ASSERT_TRUE(vx::EngineTesting::lose_device(e));
        glfwPollEvents();
        const vx::Status lost = e.render_to_window();
        ASSERT_FALSE(lost);
        EXPECT_NE(lost.error().find("device was lost"), std::string::npos) << lost.error();
        EXPECT_TRUE(e.stats().device_lost);
        EXPECT_FALSE(e.render_to_window());

        ASSERT_TRUE(e.recreate_renderer());
        glfwPollEvents();
        ASSERT_TRUE(e.render_to_window(&after));
        EXPECT_EQ(after.rgba, before.rgba);
        EXPECT_FALSE(e.stats().device_lost);
        EXPECT_EQ(e.stats().validation_errors, 0u);
    }
    glfwDestroyWindow(window);
}
