// Incremental = scratch: random edits applied through the edit mesher and Renderer::set_chunk
// with the slices each edit changed (those slices uploaded and the BLAS refitted when the slots
// fit, rebuilds otherwise) render the same bytes as the same world loaded from scratch.
#include <random>
#include <string>

#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

using test::hills;

RenderSettings settings() {
    RenderSettings s;
    s.mode = ShadingMode::Full;
    s.shadow_samples = 4;
    s.max_bounces = 2;
    s.light.block = {-20, 40, -10};
    return s;
}

TEST_F(RendererTest, IncrementalEditsRenderLikeScratch) {
    world::World w = hills();
    world::EditMesher em;
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*m_renderer, meshes);
    const Camera cam = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});
    std::mt19937 rng(11);
    const world::BlockId palette[] = {world::kAir, test::block_id("stone"), test::block_id("mirror"),
                                      test::block_id("lamp"), test::block_id("sand")};
    uint32_t refits = 0, rebuilds = 0;
    for (int round = 0; round < 4; ++round) {
        for (int batch = 0; batch < 3; ++batch) {
            std::vector<world::SliceUpdate> touched;
            // Single-block edits (mostly refits), and in the last batch of a round a solid box
            // that overflows slot capacity (rebuilds) and may create a new chunk above.
            const int edits = batch == 2 ? 1 : 12;
            for (int e = 0; e < edits; ++e) {
                const world::BlockPos p(int64_t(rng() % 64) - 32, int64_t(rng() % 16), int64_t(rng() % 64) - 32);
                const int size = batch == 2 ? 9 : 1;
                const world::BlockId id = palette[rng() % 5];
                for (int64_t dz = 0; dz < size; ++dz)
                    for (int64_t dy = 0; dy < size; ++dy)
                        for (int64_t dx = 0; dx < size; ++dx)
                            for (const world::SliceUpdate& u :
                                 em.apply(w, p + world::BlockPos(dx, 20 * (size > 1) + dy, dz), id, meshes).updates)
                                touched.push_back(u);
            }
            // Every edit's slices, each with the chunk's final mesh: a pending refit uploads the union.
            for (const world::SliceUpdate& u : touched)
                m_renderer->set_chunk(u.chunk, meshes[u.chunk].mesh, test::changed_slices(u));
            m_renderer->render(settings(), cam); // Applies this batch's refits and rebuilds.
            refits += m_renderer->last_stats().blas_refits;
            rebuilds += m_renderer->last_stats().blas_builds;
        }
        const RenderImage incremental = m_renderer->render(settings(), cam);
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(w));
        const RenderImage scratch = m_renderer->render(settings(), cam);
        test::maybe_save(incremental, "incremental");
        int diff = 0;
        for (size_t i = 0; i < scratch.rgba.size(); ++i)
            diff += scratch.rgba[i] != incremental.rgba[i];
        EXPECT_EQ(diff, 0) << "round " << round;
    }
    EXPECT_GT(refits, 10u);
    EXPECT_GT(rebuilds, 2u);
}

// The same path (edits refitted and rebuilt, then denoised frames reprojecting their history)
// under the validation layer's synchronization checks: no hazard between the uploads, the
// builds, the trace and the denoiser's passes. The renderer once dropped the request, so
// VX_SYNC_VALIDATION checked nothing; sync_validation_enabled() says the layer got it.
TEST(RendererSync, EditsAndDenoisedFramesHaveNoHazards) {
    RendererCreateInfo ci;
    ci.sync_validation = true;
    std::unique_ptr<Renderer> r = test::make_renderer(ci);
    ASSERT_NE(r, nullptr);
    ASSERT_TRUE(r->context().sync_validation_enabled());
    world::World w = hills();
    world::EditMesher em;
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*r, meshes);
    RenderSettings s = settings();
    s.denoise = true;
    s.accumulate = 4;
    std::mt19937 rng(3);
    uint32_t refits = 0, rebuilds = 0;
    for (int frame = 0; frame < 4; ++frame) {
        const int size = frame == 2 ? 9 : 1; // A box that overflows its slots: a rebuild.
        const world::BlockPos p(int64_t(rng() % 64) - 32, int64_t(rng() % 16), int64_t(rng() % 64) - 32);
        for (int64_t dz = 0; dz < size; ++dz)
            for (int64_t dy = 0; dy < size; ++dy)
                for (int64_t dx = 0; dx < size; ++dx)
                    for (const world::SliceUpdate& u :
                         em.apply(w, p + world::BlockPos(dx, dy, dz), test::block_id("stone"), meshes).updates)
                        r->set_chunk(u.chunk, meshes[u.chunk].mesh, test::changed_slices(u));
        // Moving: the history is reprojected.
        r->render(s, Camera::look_at({30.3 + 0.25 * frame, 24.6, 29.1}, {-4.0, 4.0, -6.0}));
        refits += r->last_stats().blas_refits;
        rebuilds += r->last_stats().blas_builds;
    }
    EXPECT_GT(refits, 0u);
    EXPECT_GT(rebuilds, 0u);
    EXPECT_EQ(r->validation_errors(), 0u);
}

// A chunk edited over and over: its first edit rebuilds it hot (it was loaded cold: exact size,
// no ALLOW_UPDATE), then it is refitted 16 times, then rebuilt (its boxes would loosen), and the
// count starts again.
// Edits of one chunk, each rendered: 'r' for a refit, 'b' for a build, per edit.
std::string edit_kinds(Renderer& r, int edits) {
    world::World w = hills();
    world::EditMesher em;
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(r, meshes);
    RenderSettings flat;
    flat.mode = ShadingMode::Flat;
    const Camera cam = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});
    r.render(flat, cam);
    std::string kinds;
    for (int i = 0; i < edits; ++i) {
        // Place and remove one block on the ground inside chunk (0,0,0) (the surface there is at
        // y = 9): the first edit (place) sets the hot layout, and both states fit it.
        const world::EditResult e = em.apply(w, {10, 9, 10}, i % 2 ? world::kAir : test::block_id("stone"), meshes);
        EXPECT_EQ(e.updates.size(), 1u);
        r.set_chunk(world::ChunkCoord(0), meshes[world::ChunkCoord(0)].mesh, test::changed_slices(e.updates[0]));
        r.render(flat, cam);
        const auto& st = r.last_stats();
        EXPECT_EQ(st.blas_refits + st.blas_builds, 1u) << "edit " << i;
        kinds.push_back(st.blas_builds ? 'b' : 'r');
    }
    return kinds;
}

// RendererCreateInfo::max_refits: 0 rebuilds on every edit; 3 refits three times in a row.
// The TLAS's instances are kept across frames in the order chunks arrived (a removal moves the
// last into its place), not sorted: the image must not depend on that order. The same chunks
// loaded in reverse, and shuffled by removals and re-adds, render the same bytes. A still frame
// writes no instance once every frame slot has caught up.
TEST_F(RendererTest, InstanceOrderDoesNotChangeTheImage) {
    const world::MeshMap meshes = test::mesh_world(hills());
    std::vector<std::pair<world::ChunkCoord, const world::ChunkMesh*>> order;
    for (const auto& [c, mc] : meshes)
        order.emplace_back(c, &mc.mesh);
    ASSERT_GE(order.size(), 4u);
    const Camera cam = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});
    Renderer& r = *m_renderer;
    for (const auto& [c, mesh] : order)
        r.set_chunk(c, *mesh);
    const RenderImage ref = r.render(settings(), cam);
    // Compactions swap every BLAS two frames after the build; two frames later both frame slots
    // have their new addresses.
    for (int i = 0; i < 6; ++i)
        r.render(settings(), cam);
    EXPECT_EQ(r.last_stats().instance_writes, 0u);
    EXPECT_TRUE(r.render(settings(), cam).rgba == ref.rgba);

    r.clear_chunks();
    for (auto it = order.rbegin(); it != order.rend(); ++it)
        r.set_chunk(it->first, *it->second);
    EXPECT_TRUE(r.render(settings(), cam).rgba == ref.rgba);
    for (size_t i = 0; i < order.size(); i += 2) // Every other out, then back in.
        r.remove_chunk(order[i].first);
    r.render(settings(), cam);
    for (size_t i = 0; i < order.size(); i += 2)
        r.set_chunk(order[i].first, *order[i].second);
    const RenderImage shuffled = r.render(settings(), cam);
    EXPECT_EQ(r.last_stats().instances, order.size());
    EXPECT_TRUE(shuffled.rgba == ref.rgba);
}

TEST(RendererMaxRefits, BoundsTheRefitsInARow) {
    for (uint32_t max_refits : {0u, 3u}) {
        auto r = test::make_renderer({.max_refits = max_refits});
        ASSERT_NE(r, nullptr);
        const std::string kinds = edit_kinds(*r, 9);
        EXPECT_EQ(kinds, max_refits == 0 ? std::string(9, 'b') : "brrrbrrrb") << "max_refits " << max_refits;
        EXPECT_EQ(r->validation_errors(), 0u);
    }
}

TEST_F(RendererTest, RepeatedRefitsEndInARebuild) {
    // Default max_refits (8): a rebuild after every 8 refits in a row.
    std::string expect; // (operator+ here trips a GCC 12 -Wrestrict false positive)
    for (int i = 0; i < 2; ++i)
        expect.append(1, 'b').append(8, 'r');
    EXPECT_EQ(edit_kinds(*m_renderer, 18), expect);
}

} // namespace
} // namespace vx::render
