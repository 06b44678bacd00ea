// GPU memory running out for chunks (forced with RendererCreateInfo::gpu_memory_budget_bytes):
// the chunks that do not fit are not drawn and are counted, the frame still renders, the
// validation layer stays silent, and the renderer recovers once memory is free again.
#include "scene_util.h"

namespace vx::render {
namespace {

const Camera kCamera = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});

RenderSettings flat() {
    RenderSettings s;
    s.mode = ShadingMode::Flat;
    return s;
}

// A budget of one byte: every chunk allocation fails, so the image is the empty scene's (sky).
TEST(AllocationFailure, ChunksThatDoNotFitAreNotDrawnAndCounted) {
    RendererCreateInfo ci;
    ci.gpu_memory_budget_bytes = 1;
    std::unique_ptr<Renderer> r = test::make_renderer(ci);
    ASSERT_NE(r, nullptr);
    const RenderImage empty = r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().instances, 0u);

    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*r, meshes);
    const RenderImage img = r->render(flat(), kCamera);
    const RenderStats& st = r->last_stats();
    EXPECT_EQ(st.failed_chunks, meshes.size());
    EXPECT_EQ(st.instances, 0u);
    EXPECT_EQ(st.blas_builds, 0u);
    EXPECT_EQ(st.memory.blas + st.memory.quads + st.memory.vertices, 0u);
    EXPECT_EQ(test::differing_bytes(img, empty), 0);
    // Still failed (and still counted) on the next frame; no retry until the chunk is sent again.
    r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().failed_chunks, meshes.size());
    EXPECT_EQ(r->validation_errors(), 0u);
}

// A budget for about half the scene: some chunks are drawn, the rest counted; every chunk is
// one or the other. Freeing the scene and loading one chunk draws it.
TEST(AllocationFailure, PartOfTheSceneFitsAndTheRendererRecovers) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    uint64_t need = 0; // Peak scene bytes: the first frame holds uncompacted BLASes + vertices.
    {
        std::unique_ptr<Renderer> probe = test::make_renderer();
        ASSERT_NE(probe, nullptr);
        test::load_meshes(*probe, meshes);
        probe->render(flat(), kCamera);
        probe->context().wait_idle();
        const GpuMemoryStats m = probe->last_stats().memory;
        need = m.blas + m.quads + m.quad_count * 48; // Vertices are dropped once built.
        EXPECT_EQ(probe->validation_errors(), 0u);
    }
    RendererCreateInfo ci;
    ci.gpu_memory_budget_bytes = need / 2;
    std::unique_ptr<Renderer> r = test::make_renderer(ci);
    ASSERT_NE(r, nullptr);
    test::load_meshes(*r, meshes);
    r->render(flat(), kCamera);
    const RenderStats st = r->last_stats();
    EXPECT_GT(st.failed_chunks, 0u);
    EXPECT_GT(st.instances, 0u);
    EXPECT_EQ(st.failed_chunks + st.instances, meshes.size());
    for (int i = 0; i < 3; ++i) // Compaction of the drawn chunks runs within the budget too.
        r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().failed_chunks + r->last_stats().instances, meshes.size());

    r->clear_chunks();
    r->render(flat(), kCamera); // Retires the freed chunks' memory with this frame.
    r->context().wait_idle();
    const auto& [c, mc] = *meshes.begin();
    r->set_chunk(c, mc.mesh);
    r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().failed_chunks, 0u);
    EXPECT_EQ(r->last_stats().instances, 1u);
    EXPECT_EQ(r->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
