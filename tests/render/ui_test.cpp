// The UI pass (render/ui_pass.h): a known draw list over a known frame (an empty scene in Flat
// mode: every pixel the sky colour). Straight-alpha blending on the 8-bit values, a scissor per
// command, commands drawn in order, texels fetched at their centres, the same UI over the raster
// pipeline's frame, and an empty list removing it.
#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Two triangles covering pixels [p0, p1) with one uv and one colour.
void quad(UiDrawList& ui, glm::vec2 p0, glm::vec2 p1, glm::vec2 uv, uint32_t rgba) {
    const uint32_t b = uint32_t(ui.vertices.size());
    ui.vertices.push_back({p0, uv, rgba});
    ui.vertices.push_back({{p1.x, p0.y}, uv, rgba});
    ui.vertices.push_back({p1, uv, rgba});
    ui.vertices.push_back({{p0.x, p1.y}, uv, rgba});
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
        ui.indices.push_back(b + i);
}

// src * a + dst * (1 - a) per channel, a = alpha / 255 (the blend unit's straight alpha).
float blend(float src, float dst, float alpha) { return src * alpha / 255.f + dst * (1.f - alpha / 255.f); }

TEST_F(RendererTest, UiIsBlendedOverTheFrameInsideItsScissor) {
    RenderSettings s;
    s.width = 48;
    s.height = 32;
    s.mode = ShadingMode::Flat; // No chunks: the sky everywhere, a known background.
    const Camera cam = Camera::look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0});
    const RenderImage plain = m_renderer->render(s, cam);
    const glm::u8vec4 sky = plain.at(0, 0);

    // Texels: red, green / blue, white-transparent (alpha 0).
    m_renderer->set_ui_texture(2, 2, {250, 0, 0, 255, 0, 250, 0, 255, 0, 0, 250, 255, 255, 255, 255, 0});
    UiDrawList ui;
    quad(ui, {4, 4}, {20, 20}, {0.25f, 0.25f}, 0x80ffffffu); // Red texel, alpha 128; clipped to x < 12.
    quad(ui, {10, 10}, {14, 14}, {0.75f, 0.25f}, 0xffffffffu); // Green texel, opaque, over the first.
    quad(ui, {30, 4}, {34, 8}, {0.75f, 0.75f}, 0xffffffffu);   // Transparent texel: nothing shows.
    quad(ui, {30, 20}, {34, 24}, {0.25f, 0.75f}, 0xff00ffffu); // Blue texel x yellow = black.
    ui.cmds.push_back({0, 6, {0, 0, 12, 32}});
    ui.cmds.push_back({6, 18, {0, 0, 48, 32}});
    ASSERT_TRUE(ui_draw_list_error(ui).empty());
    m_renderer->set_ui(ui);
    const RenderImage drawn = m_renderer->render(s, cam);

    const glm::u8vec4 red = drawn.at(5, 5);
    EXPECT_NEAR(red.r, blend(250, sky.r, 128), 1.0);
    EXPECT_NEAR(red.g, blend(0, sky.g, 128), 1.0);
    EXPECT_NEAR(red.b, blend(0, sky.b, 128), 1.0);
    EXPECT_EQ(red.a, sky.a);                     // The frame's alpha stays.
    EXPECT_EQ(drawn.at(11, 19), red);            // Last column and row inside scissor and quad.
    EXPECT_EQ(drawn.at(12, 5), sky);             // Scissored off (the quad goes on to x 19).
    EXPECT_EQ(drawn.at(5, 20), sky);             // Below the quad.
    EXPECT_EQ(drawn.at(3, 4), sky);              // Left of the quad.
    EXPECT_EQ(drawn.at(10, 10), glm::u8vec4(0, 250, 0, sky.a)); // The later command on top.
    EXPECT_EQ(drawn.at(13, 13), glm::u8vec4(0, 250, 0, sky.a));
    EXPECT_EQ(drawn.at(31, 5), sky);             // Alpha 0.
    EXPECT_EQ(drawn.at(31, 21), glm::u8vec4(0, 0, 0, sky.a));
    EXPECT_EQ(drawn.at(40, 28), sky);

    // The raster pipeline's frame gets the same UI.
    s.pipeline = PipelineKind::Raster;
    const RenderImage raster = m_renderer->render(s, cam);
    EXPECT_EQ(raster.at(10, 10), glm::u8vec4(0, 250, 0, raster.at(0, 0).a));
    EXPECT_EQ(raster.at(12, 5), raster.at(0, 0));

    m_renderer->set_ui({});
    s.pipeline = PipelineKind::RayTraced;
    EXPECT_EQ(m_renderer->render(s, cam).rgba, plain.rgba);
}

TEST(UiDrawList, MalformedListsAreNamed) {
    UiDrawList ui;
    quad(ui, {0, 0}, {1, 1}, {0, 0}, 0);
    ui.cmds.push_back({0, 6, {0, 0, 1, 1}});
    EXPECT_EQ(ui_draw_list_error(ui), "");
    UiDrawList bad = ui;
    bad.indices[2] = 4;
    EXPECT_NE(ui_draw_list_error(bad).find("index 4 past its 4 vertices"), std::string::npos);
    bad = ui;
    bad.cmds[0].index_offset = 3;
    EXPECT_NE(ui_draw_list_error(bad), "");
    bad = ui;
    bad.cmds[0].index_count = 5;
    EXPECT_NE(ui_draw_list_error(bad), "");
}

} // namespace
} // namespace vx::render
