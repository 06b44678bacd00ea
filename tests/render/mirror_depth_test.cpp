// The mirror reflection depth (RenderSettings::max_bounces) between two facing mirror walls,
// where a path looking straight at one bounces until the depth ends it: each level up to
// kMaxMirrorBounces shows, and a deeper setting counts as that limit (2^32 bounces would hang the
// GPU; the facade and `vx render` refuse such values).
#include <cstdint>

#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Mirror walls at z = -4 and z = 4 (x, y in [-8, 8)), a stone floor under them, open above.
world::World corridor() {
    world::World w;
    const world::BlockId mirror = test::block_id("mirror");
    test::fill_box(w, {-8, -1, -4}, {8, 0, 5}, test::block_id("stone"));
    test::fill_box(w, {-8, 0, -4}, {8, 8, -3}, mirror);
    test::fill_box(w, {-8, 0, 4}, {8, 8, 5}, mirror);
    return w;
}

// Between the walls, looking along +z: the centre pixels' paths meet the walls head-on.
const Camera kView = Camera::look_at({0.5, 3.5, 0.0}, {0.5, 3.5, 4.0});

RenderSettings corridor_settings(uint32_t depth) {
    RenderSettings s;
    s.width = 32;
    s.height = 24;
    s.mode = ShadingMode::Full;
    s.shadow_samples = 1;
    s.max_bounces = depth;
    return s;
}

TEST_F(RendererTest, MirrorDepthStopsAtItsLimit) {
    test::load_meshes(*m_renderer, test::mesh_world(corridor()));
    const RenderImage limit = m_renderer->render(corridor_settings(kMaxMirrorBounces), kView);
    // The last level still adds light: the test can tell a depth from the next.
    EXPECT_NE(m_renderer->render(corridor_settings(kMaxMirrorBounces - 1), kView).rgba, limit.rgba);
    for (uint32_t depth : {kMaxMirrorBounces + 1, 1000u, UINT32_MAX})
        EXPECT_EQ(m_renderer->render(corridor_settings(depth), kView).rgba, limit.rgba) << depth;
}

} // namespace
} // namespace vx::render
