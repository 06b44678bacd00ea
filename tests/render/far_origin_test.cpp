// Camera-relative transforms: the same scene at 0, 2^20 and 2^24 blocks (and negative) renders
// to the same bytes. Exact equality holds: the GPU sees only positions relative to the camera's
// block (64-bit integer differences, exact), which are the same numbers at every offset, so every
// float operation, the ulp push-off of secondary rays included, repeats bit for bit.
#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// A small scene around `o` (chunk-aligned): a floor across four chunks, a pillar, a mirror wall.
world::World scene_at(world::BlockPos o) {
    world::World w;
    test::fill_box(w, o + world::BlockPos(-20, 0, -20), o + world::BlockPos(20, 2, 20), test::block_id("grass"));
    test::fill_box(w, o + world::BlockPos(-3, 2, -3), o + world::BlockPos(1, 9, 0), test::block_id("stone"));
    test::fill_box(w, o + world::BlockPos(-12, 2, -12), o + world::BlockPos(12, 7, -11), test::block_id("mirror"));
    test::fill_box(w, o + world::BlockPos(6, 2, 2), o + world::BlockPos(8, 4, 4), test::block_id("lamp"));
    return w;
}

RenderImage render_at(Renderer& r, world::BlockPos o) {
    r.clear_chunks();
    test::load_meshes(r, test::mesh_world(scene_at(o)));
    RenderSettings s;
    s.mode = ShadingMode::Full;
    s.shadow_samples = 4;
    s.max_bounces = 2;
    s.light.block = o + world::BlockPos(-10, 25, 5);
    s.light.offset = {0.25f, 0.5f, 0.75f};
    s.haze.height_falloff = 0.f; // The same haze at every altitude (else it thins higher up).
    const glm::dvec3 od(o);
    return r.render(s, Camera::look_at(od + glm::dvec3(9.3, 8.7, 14.1), od + glm::dvec3(-2.0, 3.0, -6.0)));
}

TEST_F(RendererTest, FarFromOriginRendersIdentically) {
    const RenderImage ref = render_at(*m_renderer, {0, 0, 0});
    test::maybe_save(ref, "far_0");
    // Not all one colour: the scene is really there.
    int distinct = 0;
    for (size_t i = 4; i < ref.rgba.size(); i += 4)
        distinct += std::memcmp(&ref.rgba[i], &ref.rgba[0], 3) != 0;
    EXPECT_GT(distinct, 1000);

    const int64_t k20 = int64_t(1) << 20, k24 = int64_t(1) << 24;
    const world::BlockPos offsets[] = {{k20, 0, k20}, {k24, k24, k24}, {-k24, 64, k24 + 32}, {k24 * 8, -k24, -k20}};
    for (const world::BlockPos& o : offsets) {
        const RenderImage img = render_at(*m_renderer, o);
        EXPECT_TRUE(img.rgba == ref.rgba) << "offset " << o.x << "," << o.y << "," << o.z;
    }
}

} // namespace
} // namespace vx::render
