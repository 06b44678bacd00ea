// Levels of detail in the renderer: a level-1 chunk (cells of 2 blocks) drawn with
// set_chunk(LodCoord{1, c}) against the same shapes in blocks (each cell expanded to 2x2x2
// blocks: 8 level-0 chunks). Every path must treat the scaled instance as the blocks it covers:
// primary hits, normals, shadow and reflection ray origins, the raster vertex transform, the
// emitters' reach. Also: entries are keyed by level, and the per-level statistics.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;
using world::BlockPos;
using world::ChunkCoord;
using world::LodCoord;

// A box of cells [lo, hi) of the level-1 chunk, and its block id.
struct CellBox {
    glm::ivec3 lo, hi;
    const char* block;
};

// A floor two cells thick, a pillar, a floating slab, a sand box, a mirror wall, a lamp in each
// quarter: six block ids, faces on every axis, shadows (pillar and slab on the floor, from the
// sun and the area light), a mirror. In blocks the shapes fill all 8 level-0 chunks under the
// level-1 chunk (the slab reaches into the 4 upper ones).
const CellBox kShapes[] = {
    {{0, 0, 0}, {32, 1, 32}, "dirt"},      {{0, 1, 0}, {32, 2, 32}, "grass"},    {{9, 2, 10}, {13, 22, 13}, "stone"},
    {{14, 18, 14}, {20, 19, 20}, "stone"}, {{18, 2, 16}, {26, 5, 24}, "sand"},   {{4, 2, 4}, {28, 8, 5}, "mirror"},
    {{6, 2, 8}, {7, 3, 9}, "lamp"},        {{22, 2, 8}, {23, 3, 9}, "lamp"},     {{6, 2, 20}, {7, 3, 21}, "lamp"},
    {{27, 2, 27}, {28, 3, 28}, "lamp"},
};

// The coarse chunk: the shapes in cells, meshed as level-0 chunk (0,0,0) of a world holding only
// it (the mesher's units are chunk-local cells whatever the level).
world::ChunkMesh coarse_mesh() {
    world::World w;
    for (const CellBox& b : kShapes)
        test::fill_box(w, BlockPos(b.lo), BlockPos(b.hi), test::block_id(b.block));
    return test::mesh_world(w).at(ChunkCoord(0, 0, 0)).mesh;
}

// The same shapes in blocks, at the blocks level-1 chunk `c` covers: each cell (x, y, z) is the
// blocks lod_origin(c) + 2 (x, y, z) + {0, 1}^3.
world::World expanded_world(LodCoord c) {
    const BlockPos o = world::lod_origin(c);
    world::World w;
    for (const CellBox& b : kShapes)
        test::fill_box(w, o + BlockPos(b.lo) * int64_t(2), o + BlockPos(b.hi) * int64_t(2), test::block_id(b.block));
    return w;
}

// A camera above and beside the chunk (64 blocks per edge), looking down at its middle.
Camera camera_for(LodCoord c) {
    const glm::dvec3 o(world::lod_origin(c));
    return Camera::look_at(o + glm::dvec3(71.3, 38.6, 83.9), o + glm::dvec3(27.0, 4.0, 24.0));
}

RenderSettings settings(ShadingMode mode, PipelineKind pipeline, LodCoord c) {
    RenderSettings s;
    s.width = 96;
    s.height = 64;
    s.mode = mode;
    s.pipeline = pipeline;
    s.shadow_samples = 4;
    s.max_bounces = 2;
    s.light.block = world::lod_origin(c) + BlockPos(8, 50, 40);
    s.light.offset = {0.25f, 0.5f, 0.75f};
    return s;
}

// The two scenes of chunk `c`, rendered with `s` by the same renderer (each alone), with their
// G-buffers (ray traced).
struct Pair {
    RenderImage coarse, expanded;
    GBufferImage coarse_g, expanded_g;
};
Pair render_both(Renderer& r, const RenderSettings& s, LodCoord c, const char* name) {
    Pair p;
    const bool rt = s.pipeline == PipelineKind::RayTraced;
    r.clear_chunks();
    r.set_chunk(c, coarse_mesh());
    p.coarse = r.render(s, camera_for(c), rt ? &p.coarse_g : nullptr);
    EXPECT_EQ(r.last_stats().instances, 1u);
    EXPECT_EQ(r.last_stats().level_instances[1], 1u);
    r.clear_chunks();
    const world::MeshMap meshes = test::mesh_world(expanded_world(c));
    EXPECT_EQ(meshes.size(), 8u);
    test::load_meshes(r, meshes);
    p.expanded = r.render(s, camera_for(c), rt ? &p.expanded_g : nullptr);
    EXPECT_EQ(r.last_stats().level_instances[0], 8u);
    EXPECT_EQ(r.last_stats().level_instances[1], 0u);
    test::maybe_save(p.coarse, (std::string(name) + "_coarse").c_str());
    test::maybe_save(p.expanded, (std::string(name) + "_expanded").c_str());
    return p;
}

// Pixels whose colour differs at all, and by more than `tolerance` in some channel.
struct Diff {
    int any = 0, over = 0;
};
Diff pixel_diff(const RenderImage& a, const RenderImage& b, int tolerance) {
    Diff d;
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x) {
            int m = 0;
            for (int i = 0; i < 3; ++i)
                m = std::max(m, std::abs(int(a.at(x, y)[i]) - int(b.at(x, y)[i])));
            d.any += m > 0;
            d.over += m > tolerance;
        }
    return d;
}

// Distinct colours in an image: the scene is really in view (sky, five albedos, shading).
int distinct_colours(const RenderImage& img) {
    std::vector<uint32_t> c;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        c.push_back(uint32_t(img.rgba[i]) | uint32_t(img.rgba[i + 1]) << 8 | uint32_t(img.rgba[i + 2]) << 16);
    std::sort(c.begin(), c.end());
    return int(std::unique(c.begin(), c.end()) - c.begin());
}

const LodCoord kNear{1, ChunkCoord(0, 0, 0)};
// Chunk coordinates near 2^20 (blocks near 2^26): the render origin follows the camera there.
const LodCoord kFar{1, ChunkCoord((1 << 20) - 3, 2, -(1 << 20) + 5)};

// Flat shading: the first opaque hit's albedo. Both scenes have the same surfaces at the same
// world positions; only the triangles differ (the coarse chunk's quads span up to twice as many
// blocks, the expanded ones split at chunk borders), and the ray meets them in different object
// spaces (scaled by 1/2 exactly, but translated by different chunk origins, rounded
// differently). So a pixel may differ only where its ray passes within rounding of an edge
// between two differently coloured surfaces or the sky; the ray tracer's images are equal at
// 96x64. The raster pipeline places a vertex at (chunk origin - eye), rounded once per chunk,
// plus the vertex's chunk-local position: the same world vertex can land an ulp apart in the
// coarse chunk and in the level-0 chunk holding it, and a pixel centre that close to a
// silhouette edge flips (1 pixel here, at a silhouette corner): at most 3 of 6,144 allowed.
TEST_F(RendererTest, LodLevel1FlatMatchesTheExpandedBlocks) {
    for (const LodCoord c : {kNear, kFar})
        for (const PipelineKind pipeline : {PipelineKind::RayTraced, PipelineKind::Raster}) {
            const bool rt = pipeline == PipelineKind::RayTraced;
            const Pair p = render_both(*m_renderer, settings(ShadingMode::Flat, pipeline, c), c,
                                       rt ? "lod_flat_rt" : "lod_flat_raster");
            EXPECT_GE(distinct_colours(p.coarse), 6);
            const Diff d = pixel_diff(p.coarse, p.expanded, 0);
            std::printf("LOD flat %s at chunk %d: %d pixels differ\n", rt ? "ray traced" : "raster", c.chunk.x, d.any);
            EXPECT_LE(d.any, rt ? 0 : 3) << (rt ? "ray traced" : "raster") << " at chunk " << c.chunk.x;
        }
}

// Full shading (sun, sky term, area light with 4 shadow samples, mirror bounces, the lamps): the
// shading points are the same world points but their secondary-ray origins sit kSurfaceOffset
// cells off the face: 1/512 blocks in the coarse chunk against 1/1024 in the blocks, and shadow
// rays sample the same directions (the same pixel seeds), so a shadow ray grazing an edge may
// see it differently. That moves a pixel by a sample's weight at most where that happens (a
// shadow sample is 1/4 of a light's share) and by a few 1/1000ths of a percent elsewhere. Allowed:
// at most 1% of pixels off by more than 2 levels (measured: 0 at the origin, 3 pixels off by 1
// or 2 far away). The G-buffer the denoiser reads (first-hit normal and distance, albedo) is that
// of the same surfaces: equal but where the image may differ (the same pixels as Flat: none),
// save that the distance is the hit's t, which each scene's traversal computes in its own object
// space: equal within float rounding, which may round to a neighbouring half float (seen once on
// the NVIDIA driver; lavapipe's are equal).
// The raster pipeline's Full mode (Phong from the eye-relative vertex positions) likewise. The
// lamps are found by sky rays here: their faces sampled (emitter_sampling), the two scenes' face
// lists differ in order and so do the samples (LodLevel1EmittersReachTheWholeCoarseChunk compares
// those images' means).
// One step of a half float (RGBA16F: 10 mantissa bits) at magnitude v > 0.
float half_step(float v) { return v > 0.f ? std::ldexp(1.f, std::ilogb(v) - 10) : 0.f; }

TEST_F(RendererTest, LodLevel1FullShadingMatchesTheExpandedBlocks) {
    for (const LodCoord c : {kNear, kFar}) {
        RenderSettings full = settings(ShadingMode::Full, PipelineKind::RayTraced, c);
        full.emitter_sampling = false;
        const Pair p = render_both(*m_renderer, full, c, "lod_full");
        EXPECT_GE(distinct_colours(p.coarse), 50);
        const Diff d = pixel_diff(p.coarse, p.expanded, 2);
        std::printf("LOD full at chunk %d: %d pixels differ, %d by more than 2\n", c.chunk.x, d.any, d.over);
        EXPECT_LE(d.over, int(p.coarse.width * p.coarse.height / 100));
        int g_diff = 0, depth_steps = 0;
        for (size_t i = 0; i < p.coarse_g.normal_depth.size(); ++i) {
            const glm::vec4 a = p.coarse_g.normal_depth[i], b = p.expanded_g.normal_depth[i];
            g_diff += glm::vec3(a) != glm::vec3(b) || p.coarse_g.albedo[i] != p.expanded_g.albedo[i] ||
                      std::abs(a.w - b.w) > half_step(std::max(a.w, b.w));
            depth_steps += a.w != b.w;
        }
        std::printf("LOD full at chunk %d: %d G-buffer pixels differ, %d distances by one half-float step\n",
                    c.chunk.x, g_diff, depth_steps);
        EXPECT_EQ(g_diff, 0);

        const Pair raster = render_both(*m_renderer, settings(ShadingMode::Full, PipelineKind::Raster, c), c, "lod_full_raster");
        const Diff dr = pixel_diff(raster.coarse, raster.expanded, 2);
        std::printf("LOD raster full at chunk %d: %d pixels differ, %d by more than 2\n", c.chunk.x, dr.any, dr.over);
        EXPECT_LE(dr.over, 3); // As Flat: silhouette pixels.
    }
}

// Without sky access, sky rays run only within the emitters' reach (kEmitterRange cells of an
// emissive chunk's box). The coarse chunk's box is 64 blocks and its reach 32 blocks: points in
// its far half (x or z beyond 48) are lit by the lamps as they are in the blocks, where each of
// the 4 lower level-0 chunks holds a lamp and reaches 16 blocks beyond its 32-block box (the
// whole scene but y >= 48, where nothing is). Allowed difference as above. Sky rays find the lamps
// here (emitter_sampling off: the path of emissive chunks whose faces are not in the frame's list);
// with their faces sampled, the two lists (one coarse chunk's faces, four chunks' faces) differ in
// length and order, so the samples differ: the images agree in their mean within 2%.
TEST_F(RendererTest, LodLevel1EmittersReachTheWholeCoarseChunk) {
    RenderSettings s = settings(ShadingMode::Full, PipelineKind::RayTraced, kNear);
    s.sky_access = false;
    s.sun.irradiance = glm::vec3(0.f);
    s.light.emission = glm::vec3(0.f);
    s.shadow_samples = 16; // Sky rays that find the small lamps.
    s.emitter_sampling = false;
    const Pair p = render_both(*m_renderer, s, kNear, "lod_lamp");
    const Diff d = pixel_diff(p.coarse, p.expanded, 2);
    std::printf("LOD lamp only: %d pixels differ, %d by more than 2\n", d.any, d.over);
    EXPECT_GE(distinct_colours(p.coarse), 20);
    EXPECT_LE(d.over, int(p.coarse.width * p.coarse.height / 100));

    s.emitter_sampling = true;
    const Pair faces = render_both(*m_renderer, s, kNear, "lod_lamp_faces");
    using test::mean_byte;
    std::printf("LOD lamp faces sampled: mean byte %.3f coarse, %.3f blocks (sky rays: %.3f, %.3f)\n",
                mean_byte(faces.coarse), mean_byte(faces.expanded), mean_byte(p.coarse), mean_byte(p.expanded));
    EXPECT_GE(distinct_colours(faces.coarse), 20);
    EXPECT_NEAR(mean_byte(faces.coarse) / mean_byte(faces.expanded), 1.0, 0.02);
}

// The raster pipeline skips chunks whose box is outside the view: a level-1 chunk's box is 64
// blocks, not 32. Looking straight down at its far corner (x, z in 48..64, a 30 degree view from
// 26 blocks above the floor top), the first 32 blocks of the chunk are out of view and the
// coarse chunk must still be drawn, as the blocks are.
TEST_F(RendererTest, LodRasterCullsByTheWholeCoarseBox) {
    const glm::dvec3 o(world::lod_origin(kNear));
    const Camera cam = Camera::look_at(o + glm::dvec3(56.2, 30.1, 56.3), o + glm::dvec3(56.2, 0.0, 56.3), {0, 0, -1}, 30.f);
    RenderSettings s = settings(ShadingMode::Flat, PipelineKind::Raster, kNear);
    Renderer& r = *m_renderer;
    r.set_chunk(kNear, coarse_mesh());
    const RenderImage coarse = r.render(s, cam);
    EXPECT_EQ(r.last_stats().raster_chunks, 1u);
    r.clear_chunks();
    test::load_meshes(r, test::mesh_world(expanded_world(kNear)));
    const RenderImage expanded = r.render(s, cam);
    test::maybe_save(coarse, "lod_cull_coarse");
    EXPECT_LT(r.last_stats().raster_chunks, 8u); // The view holds only some of the level-0 chunks.
    EXPECT_GE(distinct_colours(coarse), 2);     // Grass and the lamp at cells (27, 2, 27).
    EXPECT_LE(pixel_diff(coarse, expanded, 0).any, 3);
}

// A level-0 and a level-1 entry with the same chunk coordinates are different chunks (level-1
// chunk (1,0,0) covers blocks x 64..127, level-0 chunk (1,0,0) x 32..63): removing one leaves
// the other, drawn exactly as when it was alone.
TEST_F(RendererTest, LodRemoveChunkRemovesOnlyThatLevel) {
    Renderer& r = *m_renderer;
    const ChunkCoord c(1, 0, 0);
    const world::ChunkMesh mesh = coarse_mesh();
    RenderSettings s = settings(ShadingMode::Flat, PipelineKind::RayTraced, kNear);
    const Camera cam = Camera::look_at({96.5, 70.3, 150.2}, {64.0, 4.0, 30.0});
    r.set_chunk(c, mesh); // Level 0 through the ChunkCoord overload.
    const RenderImage alone = r.render(s, cam);
    r.set_chunk(LodCoord{1, c}, mesh);
    const RenderImage both = r.render(s, cam);
    EXPECT_EQ(r.last_stats().instances, 2u);
    EXPECT_GT(test::differing_bytes(alone, both), 500); // The coarse chunk is in view.
    r.remove_chunk(LodCoord{1, c});
    r.remove_chunk(LodCoord{2, c}); // Absent: nothing happens.
    const RenderImage after = r.render(s, cam);
    EXPECT_EQ(r.last_stats().instances, 1u);
    EXPECT_EQ(r.last_stats().level_instances[0], 1u);
    EXPECT_EQ(r.last_stats().level_instances[1], 0u);
    EXPECT_TRUE(after.rgba == alone.rgba);
    // And the other way round: the level-0 entry goes, a level-1 one stays.
    r.set_chunk(LodCoord{1, c}, mesh);
    r.remove_chunk(c);
    r.render(s, cam);
    EXPECT_EQ(r.last_stats().level_instances[0], 0u);
    EXPECT_EQ(r.last_stats().level_instances[1], 1u);
}

// The per-level counts: instances and device bytes by level, summing to the totals, kept as
// chunks are set (also as an edit: hot, vertices kept), removed, and replaced by a Scene.
TEST_F(RendererTest, LodStatsCountEachLevel) {
    Renderer& r = *m_renderer;
    const world::ChunkMesh mesh = coarse_mesh();
    auto check_sums = [&](const char* when) {
        const RenderStats& st = r.last_stats();
        EXPECT_EQ(std::accumulate(st.level_instances.begin(), st.level_instances.end(), 0u), st.instances) << when;
        EXPECT_EQ(std::accumulate(st.level_gpu_bytes.begin(), st.level_gpu_bytes.end(), uint64_t(0)),
                  st.memory.blas + st.memory.vertices + st.memory.quads)
            << when;
        for (int k = 0; k <= world::kMaxLodLevel; ++k)
            EXPECT_EQ(st.level_instances[size_t(k)] == 0, st.level_gpu_bytes[size_t(k)] == 0) << when << " level " << k;
    };
    RenderSettings s = settings(ShadingMode::Flat, PipelineKind::RayTraced, kNear);
    const Camera cam = camera_for(kNear);
    for (int x = 0; x < 3; ++x)
        r.set_chunk(ChunkCoord(x, 0, 0), mesh);
    r.set_chunk(LodCoord{1, ChunkCoord(0, 0, 0)}, mesh);
    r.set_chunk(LodCoord{1, ChunkCoord(1, 0, 0)}, mesh);
    r.set_chunk(LodCoord{world::kMaxLodLevel, ChunkCoord(0, -1, 0)}, mesh);
    // Three frames: the cold BLASes of the first are compacted in the third (kFramesInFlight
    // frames later), after which the bytes stay put.
    for (int i = 0; i < 3; ++i)
        r.render(s, cam);
    const RenderStats first = r.last_stats();
    EXPECT_EQ(first.level_instances[0], 3u);
    EXPECT_EQ(first.level_instances[1], 2u);
    EXPECT_EQ(first.level_instances[2], 0u);
    EXPECT_EQ(first.level_instances[world::kMaxLodLevel], 1u);
    check_sums("loaded");
    // The same mesh everywhere, cold: every chunk holds the same bytes (2 level-1 chunks: twice one).
    EXPECT_EQ(first.level_gpu_bytes[1], 2 * first.level_gpu_bytes[world::kMaxLodLevel]);

    // An edit of a level-1 chunk: rebuilt hot (spare slots, vertices kept): its level grows.
    std::vector<int> all(world::kSliceCount);
    std::iota(all.begin(), all.end(), 0);
    world::World w;
    test::fill_box(w, {3, 3, 3}, {5, 5, 5}, test::block_id("stone"));
    const world::ChunkMesh edited = test::mesh_world(w).at(ChunkCoord(0, 0, 0)).mesh;
    r.set_chunk(LodCoord{1, ChunkCoord(1, 0, 0)}, edited, all);
    r.render(s, cam);
    EXPECT_EQ(r.last_stats().hot_chunks, 1u);
    EXPECT_GT(r.last_stats().memory.vertices, 0u);
    EXPECT_EQ(r.last_stats().level_gpu_bytes[0], first.level_gpu_bytes[0]);
    check_sums("edited");

    r.remove_chunk(LodCoord{1, ChunkCoord(0, 0, 0)});
    r.remove_chunk(LodCoord{1, ChunkCoord(1, 0, 0)});
    r.render(s, cam);
    EXPECT_EQ(r.last_stats().level_instances[1], 0u);
    EXPECT_EQ(r.last_stats().level_gpu_bytes[1], 0u);
    EXPECT_EQ(r.last_stats().level_gpu_bytes[0], first.level_gpu_bytes[0]);
    check_sums("removed");

    // The one-call API: lod_chunks beside chunks; what the scene lacks is dropped, any level.
    Scene scene;
    scene.chunks.emplace_back(ChunkCoord(0, 0, 0), &mesh);
    scene.lod_chunks.emplace_back(LodCoord{2, ChunkCoord(0, 0, 0)}, &mesh);
    scene.lod_chunks.emplace_back(LodCoord{2, ChunkCoord(0, 1, 0)}, &mesh);
    r.render(s, cam, scene);
    EXPECT_EQ(r.last_stats().instances, 3u);
    EXPECT_EQ(r.last_stats().level_instances[0], 1u);
    EXPECT_EQ(r.last_stats().level_instances[2], 2u);
    EXPECT_EQ(r.last_stats().level_instances[world::kMaxLodLevel], 0u);
    check_sums("scene");

    r.clear_chunks();
    r.render(s, cam);
    for (int k = 0; k <= world::kMaxLodLevel; ++k) {
        EXPECT_EQ(r.last_stats().level_instances[size_t(k)], 0u);
        EXPECT_EQ(r.last_stats().level_gpu_bytes[size_t(k)], 0u);
    }
}

// Out of GPU memory (a one-byte budget): a coarse chunk that cannot be allocated is not drawn,
// counted as failed, and holds no bytes in its level (the log line names the level).
TEST(LodAllocationFailure, AFailedCoarseChunkCountsNothingInItsLevel) {
    RendererCreateInfo ci;
    ci.gpu_memory_budget_bytes = 1;
    std::unique_ptr<Renderer> r = test::make_renderer(ci);
    ASSERT_NE(r, nullptr);
    const world::ChunkMesh mesh = coarse_mesh();
    r->set_chunk(LodCoord{2, ChunkCoord(0, 0, 0)}, mesh);
    const RenderSettings s = settings(ShadingMode::Flat, PipelineKind::RayTraced, kNear);
    r->render(s, camera_for(kNear));
    EXPECT_EQ(r->last_stats().failed_chunks, 1u);
    EXPECT_EQ(r->last_stats().instances, 0u);
    EXPECT_EQ(r->last_stats().level_instances[2], 0u);
    EXPECT_EQ(r->last_stats().level_gpu_bytes[2], 0u);
    EXPECT_EQ(r->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
