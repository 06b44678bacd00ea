// Naive, culled and greedy meshes of one world show the same surfaces: the ray tracer's and the
// raster pipeline's Flat images agree between meshers (they differ in triangles, not in what a
// pixel sees). The naive mesh also holds every hidden face between two blocks, which the raster
// pipeline's back-face and depth tests must keep out of sight.
#include <cstdio>

#include "scene_util.h"

#include "world/mesh/apron.h"
#include "world/mesh/reference_meshers.h"

namespace vx::render {
namespace {

using test::RendererTest;

world::MeshMap mesh_world_with(const world::World& w, world::MesherKind kind) {
    world::MeshMap meshes;
    world::GreedyMesher greedy;
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk& chunk) {
        const world::Apron apron = world::make_apron(w, c);
        const world::MesherInput in{chunk, apron, w.registry()};
        world::ChunkMesh& mesh = meshes[c].mesh;
        if (kind == world::MesherKind::Naive)
            world::mesh_naive(in, mesh);
        else if (kind == world::MesherKind::Culled)
            world::mesh_culled(in, mesh);
        else
            greedy.mesh(in, mesh);
    });
    return meshes;
}

uint64_t quads_of(const world::MeshMap& meshes) {
    uint64_t n = 0;
    for (const auto& [c, mc] : meshes)
        n += mc.mesh.quad_count();
    return n;
}

// Pixels whose RGB differ.
uint32_t differing_pixels(const RenderImage& a, const RenderImage& b) {
    uint32_t n = 0;
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x)
            n += glm::u8vec3(a.at(x, y)) != glm::u8vec3(b.at(x, y));
    return n;
}

TEST_F(RendererTest, NaiveCulledAndGreedyMeshesRenderTheSameFlatImage) {
    const world::World w = test::hills();
    RenderSettings s;
    s.width = 96;
    s.height = 64;
    s.mode = ShadingMode::Flat;
    const Camera cam = Camera::look_at({-45.3, 22.2, -40.7}, {0.0, 6.0, 0.0});
    RenderImage greedy_rt, greedy_raster;
    uint64_t greedy_quads = 0;
    for (world::MesherKind kind : {world::MesherKind::Greedy, world::MesherKind::Culled, world::MesherKind::Naive}) {
        const world::MeshMap meshes = mesh_world_with(w, kind);
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, meshes);
        s.pipeline = PipelineKind::RayTraced;
        const RenderImage rt = m_renderer->render(s, cam);
        s.pipeline = PipelineKind::Raster;
        const RenderImage raster = m_renderer->render(s, cam);
        const uint64_t quads = quads_of(meshes);
        if (kind == world::MesherKind::Greedy) {
            greedy_rt = rt;
            greedy_raster = raster;
            greedy_quads = quads;
            continue;
        }
        const uint32_t rt_diff = differing_pixels(rt, greedy_rt), raster_diff = differing_pixels(raster, greedy_raster);
        std::printf("%s: %llu quads (greedy %llu); differ from greedy: RT %u, raster %u pixels\n",
                    world::mesher_name(kind), (unsigned long long)quads, (unsigned long long)greedy_quads, rt_diff,
                    raster_diff);
        // Culled has more quads than greedy (merging), naive far more (hidden faces too).
        EXPECT_GT(quads, greedy_quads + greedy_quads / 2) << world::mesher_name(kind);
        // The same surfaces: only pixel centres on a triangle edge may resolve differently (a
        // greedy quad's edge runs where the per-face meshes have none), a handful at most.
        EXPECT_LE(rt_diff, s.width * s.height / 200) << world::mesher_name(kind);
        EXPECT_LE(raster_diff, s.width * s.height / 200) << world::mesher_name(kind);
    }
}

} // namespace
} // namespace vx::render
