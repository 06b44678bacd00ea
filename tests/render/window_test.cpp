// Presentation to a GLFW window (run under xvfb-run on lavapipe, validation on): frames reach
// the swapchain, the window's pixels equal a headless render() of the same camera byte for byte
// (so the sRGB encoding happens once), the extent follows a resized window, a minimised window
// skips frames, and the validation layer stays silent.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <optional>

#include <volk.h>

#include "render/swapchain.h"
#include "scene_util.h"

namespace vx::render {
namespace {

// A small lit scene: a floor, a stone pillar and a glowing block, seen from above at an angle.
world::World small_world() {
    world::World w;
    test::fill_box(w, {-8, -1, -8}, {8, 0, 8}, test::block_id("grass"));
    test::fill_box(w, {-2, 0, -2}, {1, 4, 1}, test::block_id("stone"));
    test::fill_box(w, {3, 0, 2}, {5, 2, 4}, test::block_id("wood"));
    return w;
}

RenderSettings small_settings() {
    RenderSettings s;
    s.mode = ShadingMode::Full; // sRGB-encoded in the shader: the colour path under test.
    s.shadow_samples = 1;
    s.max_bounces = 1;
    s.light.block = {-10, 12, -10};
    s.light.edge_u = {20, 0, 0};
    s.light.edge_v = {0, 0, 20};
    s.light.emission = glm::vec3(40.f);
    return s;
}

const Camera kCamera = Camera::look_at({9.5, 7.2, 10.3}, {0, 0.5, 0});

// Distinct colours in an image: a blank or uniform frame would have one or two.
size_t distinct_colours(const RenderImage& img) {
    std::vector<uint32_t> c;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        c.push_back(uint32_t(img.rgba[i]) | uint32_t(img.rgba[i + 1]) << 8 | uint32_t(img.rgba[i + 2]) << 16);
    std::sort(c.begin(), c.end());
    return size_t(std::unique(c.begin(), c.end()) - c.begin());
}

// Polls until the window's framebuffer is `w` x `h` (X servers apply a resize asynchronously).
bool wait_for_size(GLFWwindow* window, int w, int h) {
    for (int i = 0; i < 200; ++i) {
        glfwWaitEventsTimeout(0.01);
        int fw = 0, fh = 0;
        glfwGetFramebufferSize(window, &fw, &fh);
        if (fw == w && fh == h)
            return true;
    }
    return false;
}

class WindowTest : public ::testing::Test {
protected:
    void SetUp() override {
        glfwSetErrorCallback([](int code, const char* what) { std::fprintf(stderr, "GLFW error %d: %s\n", code, what); });
        ASSERT_TRUE(glfwInit()) << "no display (run under xvfb-run -a)";
        ASSERT_TRUE(glfwVulkanSupported());
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
        m_window = glfwCreateWindow(96, 64, "vx window test", nullptr, nullptr);
        ASSERT_NE(m_window, nullptr);
        ASSERT_TRUE(wait_for_size(m_window, 96, 64));
    }
    void TearDown() override {
        if (m_renderer) {
            EXPECT_EQ(m_renderer->validation_errors(), 0u);
            m_renderer.reset();
        }
        if (m_window)
            glfwDestroyWindow(m_window);
        glfwTerminate();
    }
    void make_renderer(bool vsync) {
        RendererCreateInfo ci;
        ci.validation = true;
        ci.sync_validation = std::getenv("VX_SYNC_VALIDATION") != nullptr;
        ci.device = test::test_device_choice();
        ci.glfw_window = m_window;
        ci.vsync = vsync;
        Result<std::unique_ptr<Renderer>> r = Renderer::create(ci);
        ASSERT_TRUE(r.ok()) << r.error();
        m_renderer = std::move(*r);
        test::load_meshes(*m_renderer, test::mesh_world(small_world()));
    }
    // Presents `n` frames; the last one captured into *last when given.
    void present_frames(int n, RenderImage* last = nullptr) {
        for (int i = 0; i < n; ++i) {
            glfwPollEvents();
            Result<PresentResult> r = m_renderer->present(small_settings(), kCamera, i == n - 1 ? last : nullptr);
            ASSERT_TRUE(r.ok()) << r.error();
            EXPECT_EQ(*r, PresentResult::Presented) << "frame " << i;
        }
    }
    // The presented frame equals render() of the same camera at the window's size.
    void expect_matches_headless(const RenderImage& shown, uint32_t w, uint32_t h) {
        ASSERT_EQ(shown.width, w);
        ASSERT_EQ(shown.height, h);
        RenderSettings s = small_settings();
        s.width = w;
        s.height = h;
        const RenderImage ref = m_renderer->render(s, kCamera);
        test::maybe_save(shown, "window_presented");
        test::maybe_save(ref, "window_headless");
        EXPECT_GT(distinct_colours(ref), 20u) << "the scene should be visible";
        size_t differ = 0;
        for (size_t i = 0; i < ref.rgba.size(); ++i)
            differ += ref.rgba[i] != shown.rgba[i] ? 1 : 0;
        EXPECT_EQ(differ, 0u) << "presented bytes differ from the headless render (first pixel " << int(shown.rgba[0])
                              << "," << int(shown.rgba[1]) << "," << int(shown.rgba[2]) << " vs " << int(ref.rgba[0])
                              << "," << int(ref.rgba[1]) << "," << int(ref.rgba[2]) << ")";
    }

    GLFWwindow* m_window = nullptr;
    std::unique_ptr<Renderer> m_renderer;
};

TEST_F(WindowTest, PresentsTheHeadlessImageAndFollowsResizes) {
    make_renderer(false);
    ASSERT_NE(m_renderer, nullptr);
    RenderImage shown;
    present_frames(10, &shown);
    // GPU timestamps arrive two frames late; frame periods are measured from the second call.
    const RenderStats st = m_renderer->last_stats();
    EXPECT_GE(st.frame_ms, 0.0);
    EXPECT_GE(st.wait_ms, 0.0);
    EXPECT_GT(st.gpu_frame_ms, 0.0);
    EXPECT_GT(st.gpu_trace_ms, 0.0);
    EXPECT_GE(st.gpu_frame_ms, st.gpu_trace_ms);
    expect_matches_headless(shown, 96, 64);

    // A resize: the next present() renders at the new size.
    glfwSetWindowSize(m_window, 64, 40);
    ASSERT_TRUE(wait_for_size(m_window, 64, 40));
    present_frames(5, &shown);
    expect_matches_headless(shown, 64, 40);
}

// Auto exposure through present(): a frame's meter is read when its slot comes round again
// (kFramesInFlight = 2 presents later), so the first two frames use the manual ev100, later ones
// the metered value. With a very fast adaptation (gap x e^-1000 per second) it settles at the
// frame's own target, which a headless render() of the same view (now adapted: one trace)
// reaches too.
TEST_F(WindowTest, AutoExposureMetersPresentedFrames) {
    make_renderer(false);
    ASSERT_NE(m_renderer, nullptr);
    RenderSettings s = small_settings();
    s.exposure.automatic = true;
    s.exposure.adapt_speed = 1000.f;
    s.exposure.ev100 = 5.f; // Far from daylight's: the metered value must differ.
    std::vector<float> ev;
    for (int i = 0; i < 8; ++i) {
        glfwPollEvents();
        Result<PresentResult> r = m_renderer->present(s, kCamera);
        ASSERT_TRUE(r.ok()) << r.error();
        ev.push_back(m_renderer->last_stats().ev100);
    }
    EXPECT_EQ(ev[0], 5.f);
    EXPECT_EQ(ev[1], 5.f);
    EXPECT_GT(ev[7], 10.f); // A lit scene: daylight's EV100 is near 15.
    EXPECT_LT(ev[7], 20.f);
    EXPECT_NEAR(ev[7], ev[6], 0.1f);
    s.width = 96;
    s.height = 64;
    m_renderer->render(s, kCamera);
    EXPECT_NEAR(m_renderer->last_stats().ev100, ev[7], 0.1f);
}

// Resizes that land between present()'s size check and its acquire or present make the surface
// report out-of-date or suboptimal: every call must still succeed (Presented or Skipped), the
// swapchain must follow, and the validation layer must stay silent.
TEST_F(WindowTest, SurvivesAResizeEveryFrame) {
    make_renderer(false);
    ASSERT_NE(m_renderer, nullptr);
    int presented = 0;
    for (int i = 0; i < 12; ++i) {
        glfwSetWindowSize(m_window, 40 + 8 * (i % 5), 30 + 6 * (i % 3));
        glfwPollEvents();
        Result<PresentResult> r = m_renderer->present(small_settings(), kCamera);
        ASSERT_TRUE(r.ok()) << r.error();
        presented += *r == PresentResult::Presented ? 1 : 0;
    }
    EXPECT_GT(presented, 0);
    glfwSetWindowSize(m_window, 72, 56);
    ASSERT_TRUE(wait_for_size(m_window, 72, 56));
    RenderImage shown;
    present_frames(3, &shown);
    expect_matches_headless(shown, 72, 56);
}

// Out of memory while the swapchain's images and semaphores are made (its first creation or a
// resize) is a lost context the game recovers from with a new renderer, not an abort (they were
// VK_CHECKed); nothing leaks when the lost renderer is destroyed.
TEST_F(WindowTest, OutOfMemoryMakingTheSwapchainIsALostDeviceNotAnAbort) {
    for (const char* call : {"vkGetSwapchainImagesKHR", "vkCreateSemaphore (swapchain)"}) {
        std::optional<test::LayerErrorCounter> layer(std::in_place);
        make_renderer(false);
        ASSERT_NE(m_renderer, nullptr);
        m_renderer->context().inject_result(call, VK_ERROR_OUT_OF_HOST_MEMORY);
        Result<PresentResult> r = m_renderer->present(small_settings(), kCamera);
        ASSERT_FALSE(r.ok()) << call;
        EXPECT_NE(r.error().find("device was lost"), std::string::npos) << call << ": " << r.error();
        EXPECT_TRUE(m_renderer->device_lost()) << call;
        EXPECT_EQ(m_renderer->validation_errors(), 0u) << call;
        m_renderer.reset(); // What the game does: a new renderer, which presents.
        EXPECT_EQ(layer->errors(), 0) << call; // Leaked objects are reported at destroy.
        layer.reset();
        make_renderer(false);
        ASSERT_NE(m_renderer, nullptr);
        RenderImage shown;
        present_frames(2, &shown);
        expect_matches_headless(shown, 96, 64);
        m_renderer.reset();
    }
}

// Out of memory (or a lost surface: the same path) while the surface is queried (when the device
// is picked too) or the acquire semaphores are made at create (they were VK_CHECK aborts): an
// error from create naming the call, nothing leaked, and the next renderer presents.
TEST_F(WindowTest, ARefusedSurfaceQueryOrSemaphoreIsAnErrorFromCreate) {
    {
        const test::LayerErrorCounter layer;
        for (const char* call : {"vkGetPhysicalDeviceSurfaceSupportKHR", "vkGetPhysicalDeviceSurfaceFormatsKHR",
                                 "vkGetPhysicalDeviceSurfacePresentModesKHR", "vkCreateSemaphore (image acquired)"}) {
            RendererCreateInfo ci;
            ci.validation = true;
            ci.device = test::test_device_choice();
            ci.glfw_window = m_window;
            ci.fail_allocations = call;
            Result<std::unique_ptr<Renderer>> r = Renderer::create(ci);
            ASSERT_FALSE(r.ok()) << call;
            EXPECT_NE(r.error().find(std::string(call) + " failed (VK_ERROR_OUT_OF_HOST_MEMORY)"), std::string::npos)
                << r.error();
        }
        EXPECT_EQ(layer.errors(), 0);
    }
    make_renderer(false);
    ASSERT_NE(m_renderer, nullptr);
    RenderImage shown;
    present_frames(2, &shown);
    expect_matches_headless(shown, 96, 64);
}

TEST_F(WindowTest, VsyncPresentsToo) {
    make_renderer(true);
    ASSERT_NE(m_renderer, nullptr);
    RenderImage shown;
    present_frames(4, &shown);
    expect_matches_headless(shown, 96, 64);
}

TEST_F(WindowTest, MinimisedWindowSkipsFrames) {
    make_renderer(false);
    ASSERT_NE(m_renderer, nullptr);
    present_frames(2);
    glfwIconifyWindow(m_window);
    for (int i = 0; i < 20 && !glfwGetWindowAttrib(m_window, GLFW_ICONIFIED); ++i)
        glfwWaitEventsTimeout(0.01);
    if (glfwGetWindowAttrib(m_window, GLFW_ICONIFIED)) {
        Result<PresentResult> r = m_renderer->present(small_settings(), kCamera);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(*r, PresentResult::Skipped);
        glfwRestoreWindow(m_window);
    } else {
        // No window manager under Xvfb: iconifying is a no-op there. The 0x0 rule is checked
        // on the swapchain's extent choice, which present() goes through.
        std::printf("note: the X server did not iconify the window (no window manager)\n");
    }
    VkSurfaceCapabilitiesKHR caps{};
    caps.currentExtent = {UINT32_MAX, UINT32_MAX};
    caps.minImageExtent = {1, 1};
    caps.maxImageExtent = {4096, 4096};
    EXPECT_EQ(choose_extent(caps, {0, 0}).width, 0u);
    EXPECT_EQ(choose_extent(caps, {640, 0}).height, 0u);
    EXPECT_EQ(choose_extent(caps, {8000, 300}).width, 4096u);
    caps.currentExtent = {96, 64};
    EXPECT_EQ(choose_extent(caps, {0, 0}).width, 0u); // Minimised wins over the surface's size.
    EXPECT_EQ(choose_extent(caps, {96, 64}).height, 64u);
    present_frames(2);
}

TEST(WindowChoices, FormatAndPresentMode) {
    const VkSurfaceFormatKHR formats[] = {{VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR},
                                          {VK_FORMAT_B8G8R8A8_SRGB, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR}};
    EXPECT_EQ(choose_surface_format(formats).format, VK_FORMAT_B8G8R8A8_SRGB);
    EXPECT_EQ(choose_surface_format(std::span(formats, 1)).format, VK_FORMAT_B8G8R8A8_UNORM);
    const VkPresentModeKHR modes[] = {VK_PRESENT_MODE_FIFO_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR};
    EXPECT_EQ(choose_present_mode(modes, true), VK_PRESENT_MODE_FIFO_KHR);
    EXPECT_EQ(choose_present_mode(modes, false), VK_PRESENT_MODE_IMMEDIATE_KHR);
    EXPECT_EQ(choose_present_mode(std::span(modes, 1), false), VK_PRESENT_MODE_FIFO_KHR);
}

TEST(WindowChoices, HeadlessRendererCannotPresent) {
    RendererCreateInfo ci;
    ci.validation = true;
    ci.device = test::test_device_choice();
    Result<std::unique_ptr<Renderer>> r = Renderer::create(ci);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_FALSE((*r)->present(small_settings(), kCamera).ok());
    EXPECT_EQ((*r)->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
