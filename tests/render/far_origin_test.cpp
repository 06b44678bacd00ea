// Camera-relative transforms: the same scene at 0, 2^20 and 2^24 blocks (and negative) renders
// to the same bytes. Exact equality holds: the GPU sees only positions relative to the camera's
// block (64-bit integer differences, exact), which are the same numbers at every offset, so every
// float operation, the ulp push-off of secondary rays included, repeats bit for bit.
#include <optional>

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

// `load`: clear the renderer and load the scene at `o` first (else it is loaded already).
RenderImage render_at(Renderer& r, world::BlockPos o, bool load = true) {
    if (load) {
        r.clear_chunks();
        test::load_meshes(r, test::mesh_world(scene_at(o)));
    }
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

// The render origin (TlasInstances) follows the camera only in steps of more than
// kRebaseDistance blocks (or for free, when every drawn chunk is new). A camera that flies past
// one to the same scene 6,016 blocks away renders the same bytes: the origin moved to its block.
// Short of a re-base the origin stays, and the image differs only by the rounding of positions
// ~1,000 blocks from the origin (an ulp is 2^-13 blocks there). Each scene comes with an anchor
// chunk 608 blocks below its floor's middle, kept until the next scene has been drawn, so the instance
// array is never empty (an empty one lets the origin move for free); the floor hides it from
// every ray.
TEST_F(RendererTest, CrossingARebaseRendersIdentically) {
    Renderer& r = *m_renderer;
    r.clear_chunks();
    world::World anchor;
    anchor.set_block({0, 0, 0}, test::block_id("stone"));
    const world::MeshMap anchor_meshes = test::mesh_world(anchor);
    const world::ChunkMesh& anchor_mesh = anchor_meshes.at(world::ChunkCoord(0, 0, 0)).mesh;
    // Its block lands at o + (0, -608, 0): under the floor's middle.
    auto anchor_chunk = [](world::BlockPos o) { return world::chunk_of(o + world::BlockPos(0, -608, 0)); };
    // Loads the scene at `o` and its anchor, then unloads the scene at `old` (its anchor after a frame).
    auto move = [&](world::BlockPos o, std::optional<world::BlockPos> old) {
        test::load_meshes(r, test::mesh_world(scene_at(o)));
        r.set_chunk(anchor_chunk(o), anchor_mesh);
        if (old) {
            for (const auto& [c, mesh] : test::mesh_world(scene_at(*old)))
                r.remove_chunk(c);
            render_at(r, o, false); // The old anchor keeps the array from emptying.
            r.remove_chunk(anchor_chunk(*old));
        }
        return render_at(r, o, false);
    };
    const RenderImage ref = move({0, 0, 0}, std::nullopt);
    EXPECT_EQ(r.last_stats().rebases, 0u);

    const world::BlockPos far(6016, 0, -6016); // Chunk-aligned, beyond kRebaseDistance (4,096).
    const RenderImage moved = move(far, world::BlockPos(0, 0, 0));
    EXPECT_EQ(r.last_stats().rebases, 1u);
    EXPECT_TRUE(moved.rgba == ref.rgba);

    const world::BlockPos near = far + world::BlockPos(1024, 0, 512); // Within reach: no re-base.
    const RenderImage shifted = move(near, far);
    EXPECT_EQ(r.last_stats().rebases, 1u);
    const int differing = test::differing_bytes(shifted, ref);
    EXPECT_LT(differing, int(ref.rgba.size() / 100)) << differing << " bytes differ";
}

} // namespace
} // namespace vx::render
