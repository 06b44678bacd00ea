// The ray tracer's see-through blocks (trace_through in shaders/shared/raygen_common.glsl): one
// albedo per transparent block crossed, sqrt(albedo) per face, also where two different
// transparent blocks touch. There each block has its own face on the same plane and the traversal
// reports only one of the two; the walk's probe (coincident_tint) must find the other.
#include <vector>

#include "scene_util.h"

#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::RendererTest;

glm::vec3 albedo_of(world::BlockId id) { return world::BlockRegistry::default_registry().info(id).albedo; }

// A stone wall filling [0, 1) along `axis` (17 blocks square across it) and `row` in front of it,
// at 2, 3, ... along the axis (or 2, 4, ... when `apart`: air between the blocks), on the axis
// through the centre of block (0, 0, 0)'s cross-section.
world::World row_before_wall(int axis, const std::vector<world::BlockId>& row, bool apart) {
    world::World w;
    glm::ivec3 lo(-8), hi(9);
    lo[axis] = 0;
    hi[axis] = 1;
    test::fill_box(w, {lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}, test::block_id("stone"));
    for (size_t i = 0; i < row.size(); ++i) {
        glm::ivec3 p(0);
        p[axis] = 2 + int(i) * (apart ? 2 : 1);
        w.set_block({p.x, p.y, p.z}, row[i]);
    }
    return w;
}

// Looking down `axis` at the wall, through the row, from 12.5 blocks out.
Camera looking_down_axis(int axis) {
    glm::dvec3 eye(0.5), target(0.5);
    eye[axis] = 12.5;
    target[axis] = 0.0;
    const glm::vec3 up = axis == 1 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    return Camera::look_at(eye, target, up, 20.f);
}

// Flat mode: the centre pixel sees the stone through the whole row, tinted by every block's
// albedo once, whether the blocks touch or stand apart; along each axis (the faces' winding
// differs by axis) and in both orders (which of two coincident faces the traversal reports
// depends on the order). Before the probe, touching glass and water tinted by one face of the
// pair: sqrt of one block's albedo short.
TEST_F(RendererTest, TouchingTransparentBlocksTintAsBlocksApart) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const std::vector<std::vector<world::BlockId>> rows = {{glass, water}, {water, glass}, {glass, water, glass}};
    const glm::vec3 stone = albedo_of(test::block_id("stone"));
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    for (int axis = 0; axis < 3; ++axis)
        for (size_t r = 0; r < rows.size(); ++r)
            for (bool apart : {false, true}) {
                test::load_meshes(*m_renderer, test::mesh_world(row_before_wall(axis, rows[r], apart)));
                const RenderImage img = m_renderer->render(s, looking_down_axis(axis));
                glm::vec3 expected = stone;
                for (world::BlockId b : rows[r])
                    expected *= albedo_of(b);
                // Each face's sqrt rounds in the shader's float math only: the 8-bit output's 1.
                EXPECT_TRUE(test::rgb_near(img.at(16, 16), expected))
                    << "axis " << axis << ", row " << r << (apart ? ", apart" : ", touching");
                // The corner sees the wall alone.
                EXPECT_TRUE(test::rgb_near(img.at(0, 0), stone)) << "axis " << axis << ", row " << r;
            }
}

} // namespace
} // namespace vx::render
