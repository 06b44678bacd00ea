// The pipeline variant without see-through code (render/rt_pipeline.h, SeeThrough::kNone: the
// walk, the tints and the surfaces compiled out): frames trace it while no chunk set holds a
// see-through block and the eye is in none (RenderStats::see_through_code), and it draws what the
// full variant draws there.
#include <string>
#include <vector>

#include "scene_util.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Hills with a mirror block on them, and, when `hidden_water`, a water block in an air cell
// sealed in stone under the hills (its faces are meshed, towards the cell; no ray can reach it).
world::World hills_with(bool hidden_water) {
    world::World w = test::hills();
    w.set_block({2, 6, -3}, test::block_id("mirror"));
    test::fill_box(w, {-3, -12, -3}, {4, -5, 4}, test::block_id("stone"));
    w.set_block({0, -8, 0}, world::kAir);
    if (hidden_water)
        w.set_block({0, -9, 0}, test::block_id("water"));
    return w;
}

// Full mode with reflections, a sun and sky: without any see-through block the frame traces the
// variant without see-through code, and its image is the full variant's byte for byte (the full
// variant picked by a water block no ray can reach). Then the water's chunk removed, or water made
// opaque: without again. Checked: with remove_chunk or set_registry not updating the renderer's
// set of see-through chunks, the frame after keeps the see-through code.
TEST_F(RendererTest, WithoutSeeThroughBlocksFramesTraceTheVariantWithoutThem) {
    RenderSettings s = test::daylight(4);
    s.max_bounces = 2;
    const Camera cam = Camera::look_at({-6.5, 12.0, 9.5}, {2.0, 4.0, -2.0});
    test::load_meshes(*m_renderer, test::mesh_world(hills_with(false)));
    const RenderImage opaque_only = m_renderer->render(s, cam);
    EXPECT_FALSE(m_renderer->last_stats().see_through_code);
    test::maybe_save(opaque_only, "variant_opaque_only");

    m_renderer->clear_chunks();
    const world::MeshMap with_water = test::mesh_world(hills_with(true));
    test::load_meshes(*m_renderer, with_water);
    const RenderImage full = m_renderer->render(s, cam);
    EXPECT_TRUE(m_renderer->last_stats().see_through_code);
    EXPECT_EQ(test::differing_bytes(opaque_only, full), 0);

    // The water's chunk gone (remove_chunk), or water made opaque (set_registry): none again.
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    world::BlockInfo water = reg.info(test::block_id("water"));
    water.opaque = true;
    ASSERT_TRUE(reg.set(test::block_id("water"), water));
    m_renderer->set_registry(reg);
    m_renderer->render(s, cam);
    EXPECT_FALSE(m_renderer->last_stats().see_through_code) << "water made opaque";
    m_renderer->set_registry(world::BlockRegistry::default_registry());
    m_renderer->render(s, cam);
    EXPECT_TRUE(m_renderer->last_stats().see_through_code) << "water see-through again";
    for (const auto& [c, mesh] : with_water)
        if (c.y < 0)
            m_renderer->remove_chunk(world::LodCoord{0, c});
    m_renderer->render(s, cam);
    EXPECT_FALSE(m_renderer->last_stats().see_through_code) << "the water's chunk removed";
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The eye in water (RenderSettings::eye_block) where no chunk set holds a see-through block (a
// chunk of water all through has no faces): the see-through code is on, and Flat mode shows the
// floor two blocks down tinted by two blocks of water, albedo^2. Checked: with the eye's block
// left out of the choice, the variant without runs and the floor is untinted.
TEST_F(RendererTest, AnEyeInWaterWithNoWaterFacesDrawnTracesTheSeeThroughCode) {
    world::World w;
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    s.eye_block = test::block_id("water");
    const Camera cam = Camera::look_at({0.3, 3.0, 0.2}, {0.3, 0.0, 0.2}, {0, 0, -1});
    const RenderImage img = m_renderer->render(s, cam);
    EXPECT_TRUE(m_renderer->last_stats().see_through_code);
    const world::BlockRegistry& reg = world::BlockRegistry::default_registry();
    const glm::vec3 a = reg.info(test::block_id("water")).albedo;
    EXPECT_TRUE(test::rgb_near(img.at(16, 16), reg.info(test::block_id("stone")).albedo * a * a));
    s.eye_block = test::block_id("stone"); // An opaque block: none.
    m_renderer->render(s, cam);
    EXPECT_FALSE(m_renderer->last_stats().see_through_code);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// Out of memory for the variant without see-through code or its shader binding table (made at the
// first frame without see-through blocks): a one-line error; the next frame renders as a renderer
// that never failed.
TEST_F(RendererTest, NoMemoryForTheOpaqueOnlyPipelineIsAnErrorThenTheNextFrameRenders) {
    const world::MeshMap meshes = test::mesh_world(hills_with(false));
    RenderSettings s = test::daylight(2);
    const Camera cam = Camera::look_at({-6.5, 12.0, 9.5}, {2.0, 4.0, -2.0});
    test::expect_frame_failure_then_recovery(meshes, s, cam,
                                             {"rt pipeline, opaque only", "shader binding table, opaque only"},
                                             "out of GPU memory for the pipeline of this frame's see-through blocks");
}

} // namespace
} // namespace vx::render
