// The ray tracer's see-through blocks (trace_through in shaders/shared/raygen_common.glsl): one
// albedo per transparent block crossed, sqrt(albedo) per face, also where two different
// transparent blocks touch. There each block has its own face on the same plane and the traversal
// reports only one of the two; the walk's probe (coincident_tint) must find the other.
#include <algorithm>
#include <string>
#include <vector>

#include "scene_util.h"

#include "render/scene_accel.h"
#include "world/mesh/edit_mesher.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::RendererTest;

glm::vec3 albedo_of(world::BlockId id) { return world::BlockRegistry::default_registry().info(id).albedo; }

// A stone wall filling [0, 1) along `axis` (17 blocks square across it) and `row` in front of it,
// at `start`, start + 1, ... along the axis (or start, start + 2, ... when `apart`: air between
// the blocks), on the axis through the centre of block (0, 0, 0)'s cross-section.
world::World row_before_wall(int axis, const std::vector<world::BlockId>& row, int start, bool apart) {
    world::World w;
    glm::ivec3 lo(-8), hi(9);
    lo[axis] = 0;
    hi[axis] = 1;
    test::fill_box(w, {lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}, test::block_id("stone"));
    for (size_t i = 0; i < row.size(); ++i) {
        glm::ivec3 p(0);
        p[axis] = start + int(i) * (apart ? 2 : 1);
        w.set_block({p.x, p.y, p.z}, row[i]);
    }
    return w;
}

// Looking down `axis` at the wall, through the row, from `distance` blocks out.
Camera looking_down_axis(int axis, double distance) {
    glm::dvec3 eye(0.5), target(0.5);
    eye[axis] = distance;
    target[axis] = 0.0;
    const glm::vec3 up = axis == 1 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    return Camera::look_at(eye, target, up, 20.f);
}

// Flat mode: the centre pixel sees the stone through the whole row, tinted by every block's
// albedo once, whether the blocks touch or stand apart; along each axis (the faces' winding
// differs by axis), in both orders (which of two coincident faces the traversal reports depends
// on the order), within one chunk (start 2: two transparent ids there) and across a chunk border
// (start 31: glass in one chunk, water in the next, each chunk with one transparent id and its
// face on the border). Before the probe, touching glass and water tinted by one face of the
// pair: sqrt of one block's albedo short.
TEST_F(RendererTest, TouchingTransparentBlocksTintAsBlocksApart) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const std::vector<std::vector<world::BlockId>> rows = {
        {glass, water}, {water, glass}, {glass, water, glass}};
    const glm::vec3 stone = albedo_of(test::block_id("stone"));
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    for (int start : {2, 31})
        for (int axis = 0; axis < 3; ++axis)
            for (size_t r = 0; r < rows.size(); ++r)
                for (bool apart : {false, true}) {
                    const world::World w = row_before_wall(axis, rows[r], start, apart);
                    test::load_meshes(*m_renderer, test::mesh_world(w));
                    const RenderImage img = m_renderer->render(s, looking_down_axis(axis, start + 10.5));
                    glm::vec3 expected = stone;
                    for (world::BlockId b : rows[r])
                        expected *= albedo_of(b);
                    const std::string where = "start " + std::to_string(start) + ", axis " +
                                              std::to_string(axis) + ", row " + std::to_string(r) +
                                              (apart ? ", apart" : ", touching");
                    // Each face's sqrt rounds in the shader's float math only: the 8-bit output's 1.
                    EXPECT_TRUE(test::rgb_near(img.at(16, 16), expected)) << where;
                }
}

// Glass placed against a pond's water by an edit (the chunk's second transparent id): the next
// frame tints by both, so the edit's update carries the chunk's new traits to its table entry.
TEST_F(RendererTest, GlassPlacedAgainstWaterByAnEditTintsByBoth) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const glm::vec3 stone = albedo_of(test::block_id("stone"));
    world::World w = row_before_wall(2, {water}, 3, false);
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*m_renderer, meshes);
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    const Camera cam = looking_down_axis(2, 13.5);
    world::EditMesher em;
    const auto edit = [&](world::BlockPos p, world::BlockId id) {
        for (const world::SliceUpdate& u : em.apply(w, p, id, meshes).updates)
            m_renderer->set_chunk(u.chunk, meshes[u.chunk].mesh, test::changed_slices(u));
        return m_renderer->render(s, cam);
    };
    // A first edit off the view makes the chunk hot (rebuilt with spare slots), so the second is
    // a refit: the path on which the BLAS and the quad buffer stay and only the traits change.
    EXPECT_TRUE(test::rgb_near(edit({6, 6, 6}, test::block_id("stone")).at(16, 16), stone * albedo_of(water)));
    const RenderImage img = edit({0, 0, 2}, glass);
    EXPECT_EQ(m_renderer->last_stats().blas_refits, 1u);
    EXPECT_TRUE(test::rgb_near(img.at(16, 16), stone * albedo_of(water) * albedo_of(glass)));
}

// Which chunks the ray tracer probes for coincident transparent faces in (ChunkTraits): those
// with two transparent ids, or one on a face of the chunk's border; not a lake's chunk.
TEST(ChunkTraitsTest, OnlyChunksWhereTransparentBlocksMayTouchAreProbed) {
    const world::BlockRegistry& reg = world::BlockRegistry::default_registry();
    const world::BlockId stone = test::block_id("stone"), glass = test::block_id("glass"),
                         water = test::block_id("water");
    const auto traits = [&](const std::vector<std::pair<world::BlockPos, world::BlockId>>& blocks) {
        world::World w;
        for (const auto& [p, id] : blocks)
            w.set_block(p, id);
        const auto meshes = test::mesh_world(w);
        EXPECT_EQ(meshes.count(world::ChunkCoord(0, 0, 0)), 1u);
        const world::ChunkMesh& mesh = meshes.at(world::ChunkCoord(0, 0, 0)).mesh;
        std::vector<world::BlockId> ids;
        mesh.for_each_quad([&](const world::Quad& q) {
            if (std::find(ids.begin(), ids.end(), q.block) == ids.end())
                ids.push_back(q.block);
        });
        return chunk_traits(mesh, ids, reg);
    };
    const ChunkTraits rock = traits({{{5, 5, 5}, stone}});
    EXPECT_TRUE(rock.opaque);
    EXPECT_FALSE(rock.may_touch);
    const ChunkTraits pond = traits({{{5, 5, 5}, water}, {{6, 5, 5}, water}, {{5, 4, 5}, stone}});
    EXPECT_FALSE(pond.opaque);
    EXPECT_FALSE(pond.may_touch);
    EXPECT_TRUE(traits({{{5, 5, 5}, water}, {{9, 5, 5}, glass}}).may_touch); // Two ids, apart: a bound.
    EXPECT_TRUE(traits({{{0, 5, 5}, water}}).may_touch);                     // On the -x border.
    EXPECT_TRUE(traits({{{5, 31, 5}, water}}).may_touch);                    // On the +y border.
}

} // namespace
} // namespace vx::render
