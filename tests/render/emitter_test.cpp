// Emissive blocks sampled through their faces (render/emitter_quads.h,
// shaders/shared/finite_light.glsl finite_light()): the faces' geometry and the frame's list (no
// GPU), then on lavapipe: the same mean light as sky rays that hit the lamps by chance, far less
// noise, and a material change that leaves the faces stale losing no light.
#include <cstdio>

#include <glm/geometric.hpp>

#include "render/emitter_quads.h"
#include "scene_util.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using test::RendererTest;

// The chunk (0, 0, 0) of a world holding only block `id` at `pos`, meshed.
world::ChunkMesh single_block_mesh(world::BlockPos pos, world::BlockId id) {
    world::World w;
    w.set_block(pos, id);
    world::MeshMap meshes = test::mesh_world(w);
    return meshes.at(world::ChunkCoord{0, 0, 0}).mesh;
}

std::vector<bool> lamp_only() {
    std::vector<bool> emissive(world::BlockRegistry::default_registry().size(), false);
    emissive[test::block_id("lamp")] = true;
    return emissive;
}

TEST(EmitterQuads, AnIsolatedLampHasSixUnitFacesFacingOut) {
    const world::BlockId lamp = test::block_id("lamp");
    std::vector<world::Quad> quads;
    collect_emissive_quads(single_block_mesh({3, 4, 5}, lamp), lamp_only(), quads);
    ASSERT_EQ(quads.size(), 6u);
    const glm::vec3 centre(3.5f, 4.5f, 5.5f);
    glm::vec3 normal_sum(0.f);
    for (const world::Quad& q : quads) {
        // Relative to an origin at (1, 2, 3): positions move by it, nothing else does.
        const gpu::EmitterQuad e = emitter_quad({0, {0, 0, 0}}, q, {1, 2, 3}, {4.f, 3.f, 2.f});
        EXPECT_FLOAT_EQ(e.corner.w, 1.f); // Area.
        const glm::vec3 n = glm::cross(glm::vec3(e.edge_u), glm::vec3(e.edge_v));
        EXPECT_FLOAT_EQ(glm::length(n), 1.f);
        const glm::vec3 face_centre = glm::vec3(e.corner) + 0.5f * glm::vec3(e.edge_u + e.edge_v) + glm::vec3(1, 2, 3);
        // The face's centre is half a block from the block's centre, along its outward normal.
        EXPECT_LT(glm::length(face_centre - (centre + 0.5f * n)), 1e-6f);
        normal_sum += n;
        EXPECT_EQ(glm::vec3(e.emission), glm::vec3(4.f, 3.f, 2.f));
        EXPECT_NEAR(e.emission.w, 0.2126f * 4.f + 0.7152f * 3.f + 0.0722f * 2.f, 1e-5f);
    }
    EXPECT_EQ(normal_sum, glm::vec3(0.f)); // One face each way.
    // Stone emits nothing: no quads.
    quads.clear();
    collect_emissive_quads(single_block_mesh({3, 4, 5}, test::block_id("stone")), lamp_only(), quads);
    EXPECT_TRUE(quads.empty());
}

TEST(EmitterQuads, ACoarseChunksFacesAreScaledByItsCellSize) {
    world::Quad q = world::Quad::make(1, 3, true, 2, 5, 1, 1, test::block_id("lamp")); // +y face at cell y = 3.
    const gpu::EmitterQuad e = emitter_quad({2, {1, 0, -1}}, q, {0, 0, 0}, glm::vec3(1.f));
    // Level 2: cells of 4 blocks, the chunk's origin at (128, 0, -128).
    EXPECT_FLOAT_EQ(e.corner.w, 16.f);
    EXPECT_FLOAT_EQ(e.corner.y, 12.f);
    EXPECT_EQ(glm::cross(glm::vec3(e.edge_u), glm::vec3(e.edge_v)), glm::vec3(0.f, 16.f, 0.f));
    const glm::vec3 lo = glm::min(glm::vec3(e.corner), glm::vec3(e.corner + e.edge_u + e.edge_v));
    EXPECT_EQ(lo, glm::vec3(128.f + 8.f, 12.f, -128.f + 20.f));
}

TEST(EmitterQuads, WholeChunksOnlyNearestFirstAndUnknownFacesStopTheList) {
    const world::BlockId lamp = test::block_id("lamp");
    const std::vector<world::Quad> six = [&] {
        std::vector<world::Quad> q;
        collect_emissive_quads(single_block_mesh({0, 0, 0}, lamp), lamp_only(), q);
        return q;
    }();
    const std::vector<world::LodCoord> chunks = {{0, {0, 0, 0}}, {0, {1, 0, 0}}, {0, {2, 0, 0}}, {0, {3, 0, 0}}};
    auto emission = [](world::BlockId) { return glm::vec3(1.f); };
    std::vector<gpu::EmitterQuad> dst(14);
    std::vector<gpu::EmitterBound> bounds(4);
    auto all_known = [&](world::LodCoord) { return &six; };
    // 14 entries hold two chunks of six faces: the third does not fit whole, so it and the fourth
    // are left to the sky rays.
    EmitterListSize n = write_emitter_quads(chunks, all_known, emission, {0, 0, 0}, dst, bounds);
    EXPECT_EQ(n.quads, 12u);
    EXPECT_EQ(n.covered_chunks, 2u);
    EXPECT_FLOAT_EQ(dst[6].corner.x - dst[0].corner.x, 32.f); // The second chunk's faces, a chunk along x.
    // Each covered chunk's bound: the lamp block's box, six unit faces of luminance 1.
    EXPECT_EQ(glm::vec3(bounds[1].lo), glm::vec3(32.f, 0.f, 0.f));
    EXPECT_EQ(glm::vec3(bounds[1].hi), glm::vec3(33.f, 1.f, 1.f));
    EXPECT_FLOAT_EQ(bounds[1].lo.w, 6.f);
    // The second chunk's faces unknown (meshed before the materials changed): only the first.
    auto second_unknown = [&](world::LodCoord c) { return c.chunk.x == 1 ? nullptr : &six; };
    n = write_emitter_quads(chunks, second_unknown, emission, {0, 0, 0}, dst, bounds);
    EXPECT_EQ(n.quads, 6u);
    EXPECT_EQ(n.covered_chunks, 1u);
    // No room at all: nothing covered; room for one chunk's bound only: one chunk.
    n = write_emitter_quads(chunks, all_known, emission, {0, 0, 0}, std::span(dst.data(), 5), bounds);
    EXPECT_EQ(n.quads, 0u);
    EXPECT_EQ(n.covered_chunks, 0u);
    n = write_emitter_quads(chunks, all_known, emission, {0, 0, 0}, dst, std::span(bounds.data(), 1));
    EXPECT_EQ(n.covered_chunks, 1u);
}

// A closed stone room, inner air [-4, 5)^3, a lamp on its floor at (2, -4, 0) and, with `two`,
// another on the wall at (-4, 0, 3) (10 faces in all: more than kEmitterCandidates, so the
// candidates are drawn at random). The camera inside looks down at the floor.
world::World lamp_room(bool two) {
    world::World w;
    test::fill_box(w, {-5, -5, -5}, {6, 6, 6}, test::block_id("stone"));
    test::fill_box(w, {-4, -4, -4}, {5, 5, 5}, world::kAir);
    w.set_block({2, -4, 0}, test::block_id("lamp"));
    if (two)
        w.set_block({-4, 0, 3}, test::block_id("lamp"));
    return w;
}

const Camera kRoomView = Camera::look_at({0.5, 2.0, 0.5}, {0.5, -4.0, 0.5}, {0, 0, -1}, 90.f);

RenderSettings lamp_light(uint32_t spp, bool faces) {
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.shadow_samples = spp;
    s.max_bounces = 0;
    s.light.emission = glm::vec3(0.f);
    s.sun.irradiance = glm::vec3(0.f);
    s.sky_light = 0.f;
    s.haze.enabled = false;
    s.emitter_sampling = faces;
    return s;
}

// Linear luminance of each pixel: the mean of `frames` independent frames (seeds 1..frames).
std::vector<double> mean_luminance(Renderer& r, RenderSettings s, uint32_t frames) {
    std::vector<double> sum(size_t(s.width) * s.height, 0.0);
    for (uint32_t f = 0; f < frames; ++f) {
        s.seed = 1 + f;
        GBufferImage g;
        r.render(s, kRoomView, &g);
        EXPECT_EQ(g.radiance.size(), sum.size());
        for (size_t i = 0; i < std::min(sum.size(), g.radiance.size()); ++i)
            sum[i] += gpu::vx_luminance(glm::vec3(g.radiance[i])) / frames;
    }
    return sum;
}

double image_mean(const std::vector<double>& v) {
    double m = 0;
    for (double x : v)
        m += x / double(v.size());
    return m;
}

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double e = 0;
    for (size_t i = 0; i < a.size(); ++i)
        e += (a[i] - b[i]) * (a[i] - b[i]) / double(a.size());
    return std::sqrt(e);
}

// The root mean square over four frames (seeds 1-4) of one frame's RMS difference from `mean`.
double one_frame_noise(Renderer& r, RenderSettings s, const std::vector<double>& mean) {
    double e2 = 0;
    for (uint32_t seed = 1; seed <= 4; ++seed) {
        s.seed = seed;
        GBufferImage g;
        r.render(s, kRoomView, &g);
        std::vector<double> frame(g.radiance.size());
        for (size_t i = 0; i < frame.size(); ++i)
            frame[i] = gpu::vx_luminance(glm::vec3(g.radiance[i]));
        const double e = rms_difference(frame, mean);
        e2 += e * e / 4;
    }
    return std::sqrt(e2);
}

// Both estimators of the lamps' light are unbiased: their long means agree, and the faces'
// one frame is far less noisy than the sky rays'.
TEST_F(RendererTest, LampFacesSampledGiveTheSkyRaysMeanWithLessNoise) {
    for (bool two : {false, true}) {
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(lamp_room(two)));
        const std::vector<double> faces = mean_luminance(*m_renderer, lamp_light(16, true), 32);
        const std::vector<double> rays = mean_luminance(*m_renderer, lamp_light(16, false), 64);
        const double mf = image_mean(faces), mr = image_mean(rays);
        // The sky term on (the room is sealed: it adds nothing): the faces are sampled only
        // where the open sky's light could not outshine the lamps, near them; sky rays find them
        // elsewhere. Its noise lies between the two.
        RenderSettings mixed = lamp_light(16, true);
        mixed.sky_light = 1.f;
        const double mm = image_mean(mean_luminance(*m_renderer, mixed, 32));
        mixed.shadow_samples = 4;
        const double noise_faces = one_frame_noise(*m_renderer, lamp_light(4, true), faces);
        const double noise_rays = one_frame_noise(*m_renderer, lamp_light(4, false), faces);
        const double noise_mixed = one_frame_noise(*m_renderer, mixed, faces);
        std::printf("%s lamp%s: mean luminance, faces %.5f, sky rays %.5f, both %.5f; 4 spp one frame RMS error: "
                    "faces %.5f, sky rays %.5f, both %.5f\n",
                    two ? "two" : "one", two ? "s" : "", mf, mr, mm, noise_faces, noise_rays, noise_mixed);
        EXPECT_GT(mf, 0.0);
        EXPECT_NEAR(mf / mr, 1.0, 0.03);
        EXPECT_NEAR(mm / mr, 1.0, 0.03);
        EXPECT_LT(noise_mixed, noise_rays);
        EXPECT_GT(noise_mixed, noise_faces);
        EXPECT_LT(noise_faces, (two ? 0.5 : 0.2) * noise_rays);
    }
}

// A new block that emits changes which ids emit: the faces the renderer kept are stale and are
// dropped, and the lamp, meshed before, is found by sky rays again (its light stays) until its
// chunk is set again. A new block that does not emit changes nothing: the same image.
TEST_F(RendererTest, StaleEmitterFacesLoseNoLight) {
    const world::MeshMap meshes = test::mesh_world(lamp_room(false));
    test::load_meshes(*m_renderer, meshes);
    const double before = image_mean(mean_luminance(*m_renderer, lamp_light(16, true), 16));
    const RenderImage faces = m_renderer->render(lamp_light(4, true), kRoomView);
    world::BlockRegistry registry = world::BlockRegistry::default_registry();
    world::BlockInfo dull;
    dull.name = "dull";
    ASSERT_TRUE(registry.add(dull));
    m_renderer->set_registry(registry);
    EXPECT_EQ(test::differing_bytes(m_renderer->render(lamp_light(4, true), kRoomView), faces), 0);
    world::BlockInfo glow;
    glow.name = "glow";
    glow.emission = glm::vec3(1.f);
    ASSERT_TRUE(registry.add(glow));
    m_renderer->set_registry(registry);
    const double stale = image_mean(mean_luminance(*m_renderer, lamp_light(16, true), 64));
    test::load_meshes(*m_renderer, meshes);
    const double again = image_mean(mean_luminance(*m_renderer, lamp_light(16, true), 16));
    std::printf("mean luminance: faces %.5f, stale faces (sky rays) %.5f, faces again %.5f\n", before, stale, again);
    EXPECT_GT(before, 0.0);
    EXPECT_NEAR(stale / before, 1.0, 0.05);
    EXPECT_NEAR(again / before, 1.0, 0.01);
}

// Out of memory for the pipeline that samples faces (made when a drawn chunk first emits), for
// its shader binding table or the pipeline itself (that one was VK_CHECKed: an abort): a
// one-line error; the next frame renders as a renderer that never failed does.
TEST_F(RendererTest, NoMemoryForTheFacesPipelineIsAnErrorThenTheNextFrameRenders) {
    test::expect_frame_failure_then_recovery(test::mesh_world(lamp_room(false)), lamp_light(4, true), kRoomView,
                                             {"shader binding table, emitter faces", "rt pipeline, emitter faces"},
                                             "out of GPU memory for the emitter faces' pipeline");
}

} // namespace
} // namespace vx::render
