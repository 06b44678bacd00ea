// GPU faults through the facade (headless, lavapipe, validation on), injected with the engine's
// test hooks (engine/engine_testing.h): a frame resource that cannot be allocated makes the
// frame call return one line and the next frame renders; a lost device fails every frame call
// while the world, its edits and saving keep working, and recreate_renderer() brings back the
// same picture; a headless target too large for the device is refused at create. CTest label
// vulkan.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "engine/engine_testing.h"
#include "facade_test_util.h"

namespace {

std::string gpu_fault_world(const char* name) { return vx::test::temp_world_path("vx_facade_gpu_fault_test", name); }

using vx::test::settle;

vx::EngineCreateInfo headless_info(vx::WorldSource source) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    info.streaming.save_delay_s = 3600; // Nothing saves on its own: only save() does.
    info.render.target = vx::RenderTarget::headless(32, 24);
    info.render.device = vx::test::test_device();
    info.render.validation = true;
    return info;
}

// 8 blocks above terrain seed 7 at the origin, looking down the slope.
vx::Viewer view() {
    vx::Viewer v;
    v.block = {0, vx::terrain_height(7, 0, 0) + 8, 0};
    v.forward = {1, -0.6, 0.3};
    return v;
}

bool out_of_memory_line(const vx::Status& s) {
    return !s && s.error().find("out of GPU memory") != std::string::npos && s.error().find('\n') == std::string::npos;
}

TEST(FacadeGpuFault, FrameResourceFailuresReturnAStatusAndTheNextFrameRenders) {
    auto created = vx::Engine::create(headless_info(vx::WorldSource::terrain(7)));
    if (!created)
        GTEST_SKIP() << "no ray-tracing device: " << created.error();
    vx::Engine& e = **created;
    ASSERT_TRUE(e.set_viewer(view()));
    ASSERT_TRUE(settle(e));

    // The first frame's target (made at the first frame).
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, "render target"));
    vx::Image img;
    EXPECT_TRUE(out_of_memory_line(e.render_to_image(img)));
    EXPECT_TRUE(img.rgba.empty()); // Untouched.
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, ""));
    ASSERT_TRUE(e.render_to_image(img));
    vx::Image again;
    ASSERT_TRUE(e.render_to_image(again));
    EXPECT_EQ(img.rgba, again.rgba);

    // The denoiser's images (made at the first frame that uses it).
    vx::RenderSettings rs;
    rs.denoise = true;
    e.set_render_settings(rs);
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, "denoise"));
    EXPECT_TRUE(out_of_memory_line(e.render_to_image(again)));
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, ""));
    EXPECT_TRUE(e.render_to_image(again));

    // The UI texture (allocated when set): refused, then taken.
    const std::vector<uint8_t> texel = {255, 255, 255, 255};
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, "ui texture"));
    EXPECT_TRUE(out_of_memory_line(e.set_ui_texture(1, 1, texel)));
    ASSERT_TRUE(vx::EngineTesting::fail_allocations(e, ""));
    EXPECT_TRUE(e.set_ui_texture(1, 1, texel));
    EXPECT_TRUE(e.render_to_image(again));

    const vx::Stats s = e.stats();
    EXPECT_FALSE(s.device_lost);
    EXPECT_EQ(s.device_losses, 0u);
    EXPECT_EQ(s.validation_errors, 0u);
}

// An unsaved edit in a SQLite world, then the device is lost: frames fail with the loss line,
// the edit stays, save() + wait() make it durable, and recreate_renderer() renders the picture
// of before the loss. The edit is in the database when the world reopens.
TEST(FacadeGpuFault, DeviceLossKeepsTheWorldAndItsEdits) {
    const std::string path = gpu_fault_world("device_loss");
    const vx::Viewer v = view();
    vx::BlockPos edited{0};
    vx::BlockId lamp = 0;
    {
        auto created = vx::Engine::create(headless_info(vx::WorldSource::sqlite(path, 7)));
        if (!created)
            GTEST_SKIP() << "no ray-tracing device: " << created.error();
        vx::Engine& e = **created;
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(settle(e));
        auto hit = e.raycast(v.block, v.offset, v.forward, 100.0);
        ASSERT_TRUE(hit);
        ASSERT_EQ(hit->kind, vx::RayHit::Kind::Hit);
        edited = hit->previous;
        lamp = *e.find_block("lamp");
        ASSERT_TRUE(e.set_block(edited, lamp));
        e.update();
        vx::Image before;
        ASSERT_TRUE(e.render_to_image(before));
        EXPECT_EQ(e.stats().dirty_chunks, 1u); // Not saved (save_delay_s is an hour).

        ASSERT_TRUE(vx::EngineTesting::lose_device(e));
        vx::Image lost;
        for (int i = 0; i < 2; ++i) {
            const vx::Status s = e.render_to_image(lost);
            ASSERT_FALSE(s);
            EXPECT_NE(s.error().find("device was lost"), std::string::npos) << s.error();
            EXPECT_NE(s.error().find("recreate_renderer"), std::string::npos) << s.error();
        }
        EXPECT_TRUE(lost.rgba.empty());
        vx::Stats st = e.stats();
        EXPECT_TRUE(st.device_lost);
        EXPECT_EQ(st.device_losses, 1u);
        EXPECT_FALSE(e.set_ui_texture(1, 1, std::vector<uint8_t>{1, 2, 3, 4}));

        // The world goes on: the edit is there, streaming updates, saving works.
        e.update();
        EXPECT_EQ(e.get_block(edited), lamp);
        auto ticket = e.save();
        ASSERT_TRUE(ticket) << ticket.error();
        ASSERT_TRUE(e.wait(*ticket));
        EXPECT_EQ(e.save_state(*ticket), vx::SaveState::Durable);

        ASSERT_TRUE(e.recreate_renderer());
        vx::Image after;
        ASSERT_TRUE(e.render_to_image(after));
        ASSERT_EQ(after.rgba.size(), before.rgba.size());
        EXPECT_EQ(after.rgba, before.rgba);
        st = e.stats();
        EXPECT_FALSE(st.device_lost);
        EXPECT_EQ(st.device_losses, 1u);
        EXPECT_EQ(st.validation_errors, 0u);
        ASSERT_TRUE(e.shutdown());
    }
    vx::EngineCreateInfo reopen;
    reopen.world = vx::WorldSource::sqlite(path, 7);
    reopen.streaming.view_radius = 1;
    reopen.streaming.view_radius_vertical = 1;
    auto again = vx::Engine::create(reopen);
    ASSERT_TRUE(again) << again.error();
    ASSERT_TRUE((*again)->set_viewer(v));
    ASSERT_TRUE(settle(**again));
    EXPECT_EQ((*again)->get_block(edited), lamp);
}

// 16384^2 pixels need about 60 GiB of frame resources (240 bytes a pixel): more than lavapipe's
// heap on a machine of less memory, so create() refuses it in one line naming the size and the
// estimate, instead of aborting at the first frame.
TEST(FacadeGpuFault, HeadlessTargetTooLargeForTheDeviceIsRefusedAtCreate) {
    vx::EngineCreateInfo info = headless_info(vx::WorldSource::terrain(7));
    info.render.target = vx::RenderTarget::headless(16384, 16384);
    auto created = vx::Engine::create(info);
    if (created)
        GTEST_SKIP() << "this device's memory heap holds a 16384x16384 frame";
    const std::string& why = created.error();
    if (why.find("ray") != std::string::npos && why.find("16384") == std::string::npos)
        GTEST_SKIP() << "no ray-tracing device: " << why;
    EXPECT_NE(why.find("16384x16384"), std::string::npos) << why;
    EXPECT_NE(why.find("GiB"), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
}

} // namespace
