// The see-through check (RenderSettings::see_through_check; gpu::kCheckMark in
// shaders/shared/render_types.h): a frame whose chunks hold water or glass is traced first with
// the variant without see-through code, and only the pixels whose rays met a see-through face are
// traced again with it. Its images must be those of one dispatch with the see-through code, byte
// for byte (the G-buffer's floats: test::same_gbuffer), whatever ray met the face (a view ray, a
// sky ray, a shadow ray, a mirror's ray), and its failures fall back to that one dispatch.
#include <memory>
#include <string>

#include "gbuffer_compare.h"
#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Hills with a pond dug into them, a glass wall standing on them, a mirror and a lamp.
world::World pond_and_pane() {
    world::World w = test::hills();
    const world::BlockId water = test::block_id("water"), glass = test::block_id("glass");
    for (int64_t z = -4; z < 3; ++z)
        for (int64_t x = -6; x < 1; ++x)
            for (int64_t y = 2; y < 14; ++y)
                w.set_block({x, y, z}, y < 7 ? water : world::kAir);
    test::fill_box(w, {4, 6, -6}, {5, 12, 2}, glass);
    w.set_block({2, 9, -8}, test::block_id("mirror"));
    w.set_block({-8, 9, 4}, test::block_id("lamp"));
    return w;
}

Camera pond_view() { return Camera::look_at({-12.5, 16.0, 14.5}, {0.0, 5.0, -2.0}); }

// Full mode with sun, sky, the area light, a lamp and two reflections at 40x40.
RenderSettings pond_settings() {
    RenderSettings s = test::daylight(2);
    s.width = 40;
    s.height = 40;
    s.max_bounces = 2;
    s.light.emission = glm::vec3(3.f);
    return s;
}

// The checked frame draws what one dispatch with the see-through code draws, image and G-buffer,
// with some but not all pixels traced again. Then over the share (0): the next frame traces in
// one dispatch and counts the same view rays, and the image stays the same; the share 1 checks
// at once. Checked: without the walk's flag (raygen_common.glsl) the pond's pixels come out as
// opaque water and differ.
TEST_F(RendererTest, TheSeeThroughCheckDrawsWhatOneDispatchDraws) {
    const world::MeshMap meshes = test::mesh_world(pond_and_pane());
    test::load_meshes(*m_renderer, meshes);
    RenderSettings s = pond_settings();
    s.see_through_check = RenderSettings::SeeThroughCheck::kOff;
    GBufferImage g_one;
    const RenderImage one = m_renderer->render(s, pond_view(), &g_one);
    EXPECT_FALSE(m_renderer->last_stats().see_through_checked);
    EXPECT_EQ(m_renderer->last_stats().see_through_pixels, 0u);

    s.see_through_check = RenderSettings::SeeThroughCheck::kOn;
    s.see_through_check_share = 0.f;
    GBufferImage g_checked;
    const RenderImage checked = m_renderer->render(s, pond_view(), &g_checked);
    test::maybe_save(checked, "see_through_check");
    const RenderStats st = m_renderer->last_stats();
    EXPECT_TRUE(st.see_through_checked);
    EXPECT_GT(st.see_through_pixels, 100u);
    EXPECT_LT(st.see_through_pixels, s.width * s.height - 100u);
    EXPECT_GT(st.see_through_view_pixels, 20u); // The pond seen, its mirrored and sky rays not counted.
    EXPECT_LT(st.see_through_view_pixels, st.see_through_pixels);
    EXPECT_EQ(test::differing_bytes(one, checked), 0);
    EXPECT_TRUE(test::same_gbuffer(g_one, g_checked, m_renderer->device().driver_info, "checked"));

    const RenderImage counted = m_renderer->render(s, pond_view()); // The last share is above 0.
    EXPECT_FALSE(m_renderer->last_stats().see_through_checked);
    EXPECT_EQ(m_renderer->last_stats().see_through_view_pixels, st.see_through_view_pixels);
    EXPECT_EQ(test::differing_bytes(one, counted), 0);
    s.see_through_check_share = 1.f; // Checked again.
    m_renderer->render(s, pond_view());
    EXPECT_TRUE(m_renderer->last_stats().see_through_checked);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The denoised output (it also reads the first mirror bounce's images) and the auto exposure's
// meter: the same with the check as without.
TEST_F(RendererTest, TheSeeThroughCheckKeepsTheDenoisedImageAndTheMeter) {
    const world::MeshMap meshes = test::mesh_world(pond_and_pane());
    test::load_meshes(*m_renderer, meshes);
    RenderSettings s = pond_settings();
    s.denoise = true;
    s.exposure.automatic = true;
    s.see_through_check = RenderSettings::SeeThroughCheck::kOff;
    const RenderImage one = m_renderer->render(s, pond_view());
    m_renderer->render(s, pond_view()); // The meter of the first frame adapts the second's exposure.
    const float ev_one = m_renderer->last_stats().ev100;

    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    test::load_meshes(*r, meshes);
    s.see_through_check = RenderSettings::SeeThroughCheck::kOn;
    s.see_through_check_share = 1.f;
    const RenderImage checked = r->render(s, pond_view());
    EXPECT_TRUE(r->last_stats().see_through_checked);
    EXPECT_EQ(test::differing_bytes(one, checked), 0);
    r->render(s, pond_view());
    EXPECT_EQ(r->last_stats().ev100, ev_one);
    EXPECT_EQ(r->validation_errors(), 0u);
}

// Only shadow rays meet see-through faces: the sun alone over ground under a glass roof the view
// does not see. Every lit pixel is marked, and its light is tinted by the glass, as in one
// dispatch. Checked: without trace_shadow's flag (raygen.rgen) none is marked and the ground is
// lit as if the roof were not there.
TEST_F(RendererTest, ShadowRaysThroughGlassAloneAreCheckedToo) {
    world::World w;
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
    test::fill_box(w, {-24, 12, -24}, {24, 13, 24}, test::block_id("glass"));
    const world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*m_renderer, meshes);
    RenderSettings s = test::sun_alone({0.2f, 1.f, 0.1f});
    s.see_through_check = RenderSettings::SeeThroughCheck::kOff;
    const Camera cam = Camera::look_at({0.5, 3.0, 8.5}, {0.5, 0.0, 0.5});
    const RenderImage one = m_renderer->render(s, cam);
    s.see_through_check = RenderSettings::SeeThroughCheck::kOn;
    const RenderImage checked = m_renderer->render(s, cam);
    EXPECT_TRUE(m_renderer->last_stats().see_through_checked);
    EXPECT_GT(m_renderer->last_stats().see_through_pixels, s.width * s.height / 2);
    EXPECT_EQ(test::differing_bytes(one, checked), 0);
    EXPECT_GT(test::mean_byte(one), 20.0) << "the ground is lit";
    EXPECT_EQ(m_renderer->last_stats().see_through_view_pixels, 0u);
    // No view ray meets the roof, so the view share stays under the default share; the checked
    // frames marked over it, so each holds one dispatch for 8 frames, then 16.
    s.see_through_check_share = 0.25f;
    s.width = s.height = 16; // The pattern alone.
    std::string pattern;
    for (int frame = 0; frame < 27; ++frame) {
        m_renderer->render(s, cam);
        pattern += m_renderer->last_stats().see_through_checked ? 'c' : '1';
    }
    EXPECT_EQ(pattern, "11111111c1111111111111111c1");
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// Water in the chunks but no ray meets it (a view of the hills away from the pond, no sky rays
// or reflections): checked, nothing marked. kAuto checks on a GPU, not on a CPU device. The eye in
// water: no check at all (every view ray starts in it). Flat mode: no check.
TEST_F(RendererTest, TheSeeThroughCheckMarksNothingWhereNoRayMeetsWater) {
    test::load_meshes(*m_renderer, test::mesh_world(pond_and_pane()));
    RenderSettings s = test::sun_alone({0.f, 1.f, 0.f});
    const Camera away = Camera::look_at({20.5, 14.0, 20.5}, {28.0, 6.0, 28.0});
    m_renderer->render(s, away);
    EXPECT_EQ(m_renderer->last_stats().see_through_checked, m_renderer->device().type != DeviceType::Cpu)
        << "kAuto on " << device_type_name(m_renderer->device().type);
    s.see_through_check = RenderSettings::SeeThroughCheck::kOn;
    m_renderer->render(s, away);
    EXPECT_TRUE(m_renderer->last_stats().see_through_checked);
    EXPECT_EQ(m_renderer->last_stats().see_through_pixels, 0u);
    s.eye_block = test::block_id("water");
    m_renderer->render(s, away);
    EXPECT_FALSE(m_renderer->last_stats().see_through_checked);
    s.eye_block = world::kAir;
    s.mode = ShadingMode::Flat;
    m_renderer->render(s, away);
    EXPECT_FALSE(m_renderer->last_stats().see_through_checked);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// Out of memory for the check's marks, its count's read-back or the variant without see-through
// code: the frame traces in one dispatch (the same image, not checked) and the next, with memory,
// is checked.
TEST_F(RendererTest, NoMemoryForTheSeeThroughCheckTracesInOneDispatch) {
    const world::MeshMap meshes = test::mesh_world(pond_and_pane());
    RenderSettings s = pond_settings();
    s.see_through_check = RenderSettings::SeeThroughCheck::kOff;
    const RenderImage expected = test::fresh_render(meshes, s, pond_view());
    s.see_through_check = RenderSettings::SeeThroughCheck::kOn;
    for (const char* resource : {"see-through check marks", "see-through check count", "rt pipeline, opaque only"}) {
        std::unique_ptr<Renderer> r = test::make_renderer();
        ASSERT_NE(r, nullptr);
        test::load_meshes(*r, meshes);
        r->fail_allocations(resource);
        Result<RenderImage> img = r->try_render(s, pond_view());
        ASSERT_TRUE(img) << resource << ": " << img.error();
        EXPECT_FALSE(r->last_stats().see_through_checked) << resource;
        EXPECT_EQ(test::differing_bytes(*img, expected), 0) << resource;
        r->fail_allocations("");
        img = r->try_render(s, pond_view());
        ASSERT_TRUE(img) << resource << ": " << img.error();
        EXPECT_TRUE(r->last_stats().see_through_checked) << resource;
        EXPECT_EQ(test::differing_bytes(*img, expected), 0) << resource;
        EXPECT_EQ(r->validation_errors(), 0u) << resource;
    }
}

} // namespace
} // namespace vx::render
