// The ray tracer's see-through blocks (trace_through in shaders/shared/raygen_common.glsl): each
// absorbs along the path in it (albedo^d over d blocks; straight through, one albedo per block),
// also where two different transparent blocks touch. There each block has its own face on the same
// plane and the traversal reports only one of the two; the walk's probe (coincident_pass) must find
// the other, to know which block the ray goes on in.
#include <algorithm>
#include <memory>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include "scene_util.h"

#include "render/touching_faces.h"
#include "shaders/shared/render_types.h"
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
// frame tints by both, so the edit's update marks the water's face it touches (a quad that did
// not change but for its mark, in one of the edit's slices).
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
    // a refit: the path on which only the edit's slices are uploaded.
    EXPECT_TRUE(test::rgb_near(edit({6, 6, 6}, test::block_id("stone")).at(16, 16), stone * albedo_of(water)));
    const RenderImage img = edit({0, 0, 2}, glass);
    EXPECT_EQ(m_renderer->last_stats().blas_refits, 1u);
    EXPECT_TRUE(test::rgb_near(img.at(16, 16), stone * albedo_of(water) * albedo_of(glass)));
}

// A block type turned see-through after its chunks were set: set_registry names exactly the
// chunks holding it (their BLAS was built OPAQUE and their mesh hid the wall's face behind it), and
// those alone, meshed again and set, draw as a renderer made with the new registry does: the
// wall behind tinted by the block (without setting them again: untinted). A change of colour
// names none (it applies at once).
TEST_F(RendererTest, ABlockTurnedSeeThroughNamesTheChunksToSetAgain) {
    world::BlockRegistry before = world::BlockRegistry::default_registry();
    world::BlockInfo crystal;
    crystal.name = "crystal";
    crystal.albedo = glm::vec3(0.9f, 0.5f, 0.3f);
    const Result<world::BlockId> id = before.add(crystal);
    ASSERT_TRUE(id);
    world::World w = row_before_wall(2, {*id}, 1, false); // The wall's four chunks; the crystal on it, in (0, 0, 0).
    w.registry() = before;
    test::load_meshes(*m_renderer, test::mesh_world(w));
    EXPECT_TRUE(m_renderer->set_registry(before).empty());
    world::BlockRegistry recoloured = before;
    crystal.albedo = glm::vec3(0.3f, 0.5f, 0.9f);
    ASSERT_TRUE(recoloured.set(*id, crystal));
    EXPECT_TRUE(m_renderer->set_registry(recoloured).empty());
    world::BlockRegistry after = before;
    crystal.albedo = glm::vec3(0.9f, 0.5f, 0.3f);
    crystal.opaque = false;
    ASSERT_TRUE(after.set(*id, crystal));
    const std::vector<world::LodCoord> stale = m_renderer->set_registry(after);
    ASSERT_EQ(stale.size(), 1u);
    EXPECT_EQ(stale[0], (world::LodCoord{0, world::ChunkCoord(0, 0, 0)}));
    w.registry() = after;
    const world::MeshMap meshes = test::mesh_world(w);
    for (world::LodCoord c : stale)
        m_renderer->set_chunk(c, meshes.at(c.chunk).mesh);
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    const Camera cam = looking_down_axis(2, 12.5);
    std::unique_ptr<Renderer> fresh = test::make_renderer();
    ASSERT_NE(fresh, nullptr);
    fresh->set_registry(after);
    test::load_meshes(*fresh, meshes);
    // The raster baseline's see-through pass skips chunks built as opaque: it shows a stale one.
    for (PipelineKind pipeline : {PipelineKind::RayTraced, PipelineKind::Raster}) {
        s.pipeline = pipeline;
        const RenderImage img = m_renderer->render(s, cam);
        // The crystal's face on the wall is hidden by the stone (not meshed); the wall is tinted by
        // the crystal's whole albedo all the same (see_through_body_test.cpp).
        EXPECT_TRUE(test::rgb_near(img.at(16, 16), albedo_of(test::block_id("stone")) * crystal.albedo, 2));
        EXPECT_EQ(test::differing_bytes(fresh->render(s, cam), img), 0);
    }
    EXPECT_EQ(fresh->validation_errors(), 0u);
}

// Frames trace with the pipeline variant that probes only while two different transparent blocks
// touch somewhere (its code alone cost every ray 7% on the NVIDIA driver; render/touching_pairs.h):
// not for a pond, nor for water alone on chunk borders (marked, but nothing else is see-through),
// nor for glass and water on the borders of neighbouring chunks apart (marked: the bound before);
// yes once glass touches the water (and it tints by both), inside a chunk or across a border; not
// again once the glass is gone. Both variants draw the pond alike.
TEST_F(RendererTest, OnlyScenesWithMarkedFacesTraceTheProbingPipeline) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const world::BlockId stone_id = test::block_id("stone");
    const glm::vec3 stone = albedo_of(stone_id);
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    // Off the chunk's border planes (a transparent face there is always marked).
    const Camera cam = Camera::look_at({5.5, 5.5, 13.5}, {5.5, 5.5, 0.0}, {0, 1, 0}, 20.f);
    const auto scene = [&](const std::vector<std::pair<world::BlockPos, world::BlockId>>& blocks) {
        world::World w;
        test::fill_box(w, {-3, -3, 1}, {14, 14, 2}, stone_id);
        for (const auto& [p, id] : blocks)
            w.set_block(p, id);
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(w));
        return m_renderer->render(s, cam);
    };
    const RenderImage pond = scene({{{5, 5, 3}, water}});
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
    EXPECT_TRUE(test::rgb_near(pond.at(16, 16), stone * albedo_of(water)));
    scene({{{5, 5, 3}, water}, {{0, 9, 9}, water}, {{31, 9, 9}, water}}); // Water on two border planes.
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
    scene({{{5, 5, 3}, water}, {{0, 9, 9}, glass}}); // Glass on a border, the water inside: no pair.
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
    scene({{{5, 5, 3}, water}, {{0, 9, 9}, glass}, {{31, 9, 9}, water}}); // Both on borders, apart.
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
    // Across the border planes of (0, 0, 0): glass in it, water beside in (-1, 0, 0) and (1, 0, 0),
    // diagonally (no shared face), then face to face.
    scene({{{5, 5, 3}, water}, {{0, 9, 9}, glass}, {{-1, 10, 9}, water}, {{31, 9, 9}, glass}, {{32, 9, 10}, water}});
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
    scene({{{5, 5, 3}, water}, {{0, 9, 9}, glass}, {{-1, 9, 9}, water}});
    EXPECT_TRUE(m_renderer->last_stats().touching_probes);
    scene({{{5, 5, 3}, water}, {{31, 9, 9}, glass}, {{32, 9, 9}, water}});
    EXPECT_TRUE(m_renderer->last_stats().touching_probes);
    const RenderImage both = scene({{{5, 5, 3}, water}, {{5, 5, 4}, glass}});
    EXPECT_TRUE(m_renderer->last_stats().touching_probes);
    EXPECT_TRUE(test::rgb_near(both.at(16, 16), stone * albedo_of(water) * albedo_of(glass)));
    // The same pond through the probing variant (glass touching water out of view).
    const RenderImage pond_probed = scene({{{5, 5, 3}, water}, {{10, 10, 10}, glass}, {{11, 10, 10}, water}});
    EXPECT_TRUE(m_renderer->last_stats().touching_probes);
    EXPECT_EQ(pond_probed.rgba, pond.rgba);
    scene({{{5, 5, 3}, water}});
    EXPECT_FALSE(m_renderer->last_stats().touching_probes);
}

// Glass in a level-0 chunk against water in the level-1 chunk beside it (a level boundary of the
// engine's levels of detail): the glass at block (63, 9, 9) on level-0 chunk (1, 0, 0)'s +x plane,
// x = 64, which is level-1 chunk (1, 0, 0)'s -x plane; the water there a 2-block cell, a stone
// wall of cells a cell behind it. Face to face they touch: the probing variant, and the ray through both
// tints by both (the probe across the coarse chunk's scaled faces), the water's cell by its two
// blocks of path (albedo^2: a coarse cell absorbs as the blocks it stands for). The water a cell
// higher: no pair, no probe, and the ray tints by the glass alone.
TEST_F(RendererTest, GlassAgainstWaterOfACoarserLevelTintsByBoth) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const world::BlockId stone = test::block_id("stone");
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    const Camera cam = Camera::look_at({50.5, 9.5, 9.5}, {80.0, 9.5, 9.5}, {0, 1, 0}, 10.f);
    for (bool touching : {true, false}) {
        world::World fine;
        fine.set_block({63, 9, 9}, glass);
        world::World coarse; // Its chunk (0, 0, 0) in cells: drawn as level-1 chunk (1, 0, 0).
        coarse.set_block({0, touching ? 4 : 5, 4}, water);
        for (int y = 0; y < 10; ++y)
            for (int z = 0; z < 10; ++z)
                coarse.set_block({2, y, z}, stone); // A cell of air between: the water's far face is drawn.
        const world::MeshMap fine_meshes = test::mesh_world(fine);
        const world::MeshMap coarse_meshes = test::mesh_world(coarse);
        m_renderer->clear_chunks();
        m_renderer->set_chunk(world::LodCoord{0, world::ChunkCoord(1, 0, 0)},
                              fine_meshes.at(world::ChunkCoord(1, 0, 0)).mesh);
        m_renderer->set_chunk(world::LodCoord{1, world::ChunkCoord(1, 0, 0)},
                              coarse_meshes.at(world::ChunkCoord(0, 0, 0)).mesh);
        const RenderImage img = m_renderer->render(s, cam);
        EXPECT_EQ(m_renderer->last_stats().touching_probes, touching);
        const glm::vec3 expected =
            albedo_of(stone) * albedo_of(glass) * (touching ? test::absorbed(albedo_of(water), 2.0) : glm::vec3(1));
        EXPECT_TRUE(test::rgb_near(img.at(16, 16), expected)) << (touching ? "touching" : "apart");
    }
}

// Out of memory for the probing pipeline or its shader binding table (made at the first frame
// with marked faces): a one-line error; the next frame renders as a renderer that never failed.
TEST_F(RendererTest, NoMemoryForTheProbingPipelineIsAnErrorThenTheNextFrameRenders) {
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const world::MeshMap meshes = test::mesh_world(row_before_wall(2, {glass, water}, 3, false));
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    const Camera cam = looking_down_axis(2, 13.5);
    test::expect_frame_failure_then_recovery(meshes, s, cam, {"rt pipeline, probes", "shader binding table, probes"},
                                             "out of GPU memory for the pipeline of this frame's see-through blocks");
}

// A marked face of chunk (0, 0, 0): its plane, facing and block.
struct Mark {
    int axis, plane;
    bool positive;
    world::BlockId block;
    friend bool operator==(const Mark&, const Mark&) = default;
    friend std::ostream& operator<<(std::ostream& o, const Mark& m) {
        return o << "{axis " << m.axis << ", plane " << m.plane << (m.positive ? ", +" : ", -") << ", block "
                 << m.block << "}";
    }
};

// The faces of chunk (0, 0, 0) of a world holding `blocks` that mark_touching_faces marks (empty
// when it marks none); the marked mesh must hold the same quads as the mesher's.
std::vector<Mark> marked_faces(const std::vector<std::pair<world::BlockPos, world::BlockId>>& blocks) {
    world::World w;
    for (const auto& [p, id] : blocks)
        w.set_block(p, id);
    const auto meshes = test::mesh_world(w);
    EXPECT_EQ(meshes.count(world::ChunkCoord(0, 0, 0)), 1u);
    const world::ChunkMesh& mesh = meshes.at(world::ChunkCoord(0, 0, 0)).mesh;
    mesh.for_each_quad([&](const world::Quad& q) { EXPECT_EQ(q.reserved, 0u) << "the mesher writes no mark"; });
    world::ChunkMesh out;
    const TouchingFaces touching =
        mark_touching_faces(mesh, mesh.block_ids(), world::BlockRegistry::default_registry(), out);
    if (!touching.marked)
        return {};
    EXPECT_TRUE(out == mesh); // Quad equality leaves out the spare field.
    std::vector<Mark> marks;
    out.for_each_quad([&](const world::Quad& q) {
        if (q.reserved & gpu::kQuadMayTouch)
            marks.push_back({q.axis(), q.plane(), q.positive(), q.block});
    });
    EXPECT_FALSE(marks.empty()) << "marked, yet no mark";
    // A mark inside the chunk is a touching pair; one on a border plane is in the border faces.
    const bool inside = std::any_of(marks.begin(), marks.end(), [](const Mark& m) { return m.plane % 32 != 0; });
    EXPECT_EQ(touching.inside, inside);
    for (const Mark& m : marks)
        if (m.plane % 32 == 0) {
            const std::vector<world::BlockId>& cells = touching.border[size_t(m.axis * 2 + (m.plane == 32))];
            EXPECT_EQ(std::count(cells.begin(), cells.end(), m.block) > 0, true) << m;
        }
    const auto key = [](const Mark& m) { return std::tuple(m.axis, m.plane, m.positive, m.block); };
    std::sort(marks.begin(), marks.end(), [&](const Mark& x, const Mark& y) { return key(x) < key(y); });
    return marks;
}

// Which faces the ray tracer probes for a coincident transparent face (render/touching_faces.h):
// inside a chunk exactly the faces between two different transparent blocks; on its border every
// transparent face. Not a lake's faces, nor transparent blocks that do not touch.
TEST(TouchingFacesTest, OnlyFacesThatMayMeetAnotherTransparentBlockAreMarked) {
    const world::BlockId stone = test::block_id("stone"), glass = test::block_id("glass"),
                         water = test::block_id("water");
    using Marks = std::vector<Mark>;
    EXPECT_EQ(marked_faces({{{5, 5, 5}, stone}}), Marks{});
    EXPECT_EQ(marked_faces({{{5, 5, 5}, water}, {{6, 5, 5}, water}, {{5, 4, 5}, stone}}), Marks{}); // A pond.
    EXPECT_EQ(marked_faces({{{5, 5, 5}, water}, {{9, 5, 5}, glass}}), Marks{});                     // Apart.
    EXPECT_EQ(marked_faces({{{5, 5, 5}, glass}, {{6, 6, 5}, water}}), Marks{}); // Edge to edge: no shared face.
    EXPECT_EQ(marked_faces({{{5, 5, 5}, glass}, {{6, 5, 5}, stone}}), Marks{});  // Glass on stone.
    // Touching along x: the two faces between them, nothing else.
    EXPECT_EQ(marked_faces({{{5, 5, 5}, water}, {{6, 5, 5}, glass}}),
              (Marks{{0, 6, false, glass}, {0, 6, true, water}}));
    // A water column (one greedy quad per side) with glass beside its middle block: the column's
    // +x quad is marked whole.
    EXPECT_EQ(marked_faces({{{5, 4, 5}, water}, {{5, 5, 5}, water}, {{5, 6, 5}, water}, {{6, 5, 5}, glass}}),
              (Marks{{0, 6, false, glass}, {0, 6, true, water}}));
    // A water row across the whole chunk (its z faces: quads 32 wide) with glass beside one block:
    // the row's +z quad is marked whole, and its ends lie on the border planes.
    std::vector<std::pair<world::BlockPos, world::BlockId>> row;
    for (int x = 0; x < 32; ++x)
        row.push_back({{x, 5, 5}, water});
    row.push_back({{10, 5, 6}, glass});
    EXPECT_EQ(marked_faces(row), (Marks{{0, 0, false, water}, {0, 32, true, water}, {2, 6, false, glass},
                                        {2, 6, true, water}}));
    // Touching along z, glass above water along y: each axis's planes.
    EXPECT_EQ(marked_faces({{{5, 5, 5}, glass}, {{5, 5, 6}, water}}),
              (Marks{{2, 6, false, water}, {2, 6, true, glass}}));
    EXPECT_EQ(marked_faces({{{5, 5, 5}, water}, {{5, 6, 5}, glass}}),
              (Marks{{1, 6, false, glass}, {1, 6, true, water}}));
    // On the chunk's border the other block would be the neighbour's: the border face only.
    EXPECT_EQ(marked_faces({{{0, 5, 5}, water}}), (Marks{{0, 0, false, water}}));
    EXPECT_EQ(marked_faces({{{5, 31, 5}, water}}), (Marks{{1, 32, true, water}}));
}

} // namespace
} // namespace vx::render
