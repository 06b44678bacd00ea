// Shadow robustness: a sealed room stays dark under a light outside, and a floor lit at a
// grazing 0.5 degrees has no falsely shadowed pixel (secondary-ray origins are robust).
#include <random>

#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// A closed box of mixed blocks around the origin (it spans eight chunks): outer [-6, 7)^3,
// inner air [-5, 6)^3. Random blocks make greedy quads of many sizes (T-junctions).
world::World sealed_box() {
    world::World w;
    const world::BlockId ids[] = {test::block_id("stone"), test::block_id("dirt"), test::block_id("wood")};
    std::mt19937 rng(3);
    for (int64_t z = -6; z < 7; ++z)
        for (int64_t y = -6; y < 7; ++y)
            for (int64_t x = -6; x < 7; ++x) {
                const bool inner = x > -6 && x < 6 && y > -6 && y < 6 && z > -6 && z < 6;
                if (!inner)
                    w.set_block({x, y, z}, ids[rng() % 3]);
            }
    return w;
}

RenderSettings box_settings() {
    RenderSettings s;
    s.mode = ShadingMode::Full;
    s.shadow_samples = 16;
    s.max_bounces = 0;
    s.light.block = {-30, 20, -30}; // A 60 x 60 light above the box, outside it.
    s.light.edge_u = {60, 0, 0};
    s.light.edge_v = {0, 0, 60};
    s.light.emission = glm::vec3(100.f);
    // The defaults also turn on the sun and the sky term (issue 10): neither may leak in either.
    return s;
}

int lit_pixels(const RenderImage& img) {
    int lit = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        lit += img.rgba[i] | img.rgba[i + 1] | img.rgba[i + 2] ? 1 : 0;
    return lit;
}

TEST_F(RendererTest, SealedBoxGetsNoLightFromOutside) {
    world::World w = sealed_box();
    test::load_meshes(*m_renderer, test::mesh_world(w));
    const glm::dvec3 eye(0.3, 0.4, 0.2);
    const glm::dvec3 dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0.01}, {0, -1, 0.01}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::dvec3& d : dirs) {
        const RenderImage img = m_renderer->render(box_settings(), Camera::look_at(eye, eye + d, {0, 1, 0}, 100.f));
        EXPECT_EQ(lit_pixels(img), 0) << "looking along " << d.x << "," << d.y << "," << d.z;
    }
    // Control: with a hole in the ceiling the same room does get light.
    world::EditMesher em;
    world::MeshMap meshes = test::mesh_world(w);
    for (int64_t x = -2; x < 2; ++x)
        for (const world::SliceUpdate& u : em.apply(w, {x, 6, 0}, world::kAir, meshes).updates)
            m_renderer->set_chunk(u.chunk, meshes[u.chunk].mesh);
    const RenderImage img = m_renderer->render(box_settings(), Camera::look_at(eye, eye + glm::dvec3(0, -1, 0.01)));
    test::maybe_save(img, "sealed_box_hole");
    EXPECT_GT(lit_pixels(img), 100);
}

constexpr int64_t kFloor = 40; // The floor covers x, z in [-40, 40), y in [0, 1).

RenderSettings grazing_settings(double elevation_degrees) {
    RenderSettings s;
    s.mode = ShadingMode::Visibility;
    s.shadow_samples = 16;
    // A 2 x 2 light 1000 blocks away at `elevation` above the floor top (y = 1), facing it.
    const double e = glm::radians(elevation_degrees);
    const glm::dvec3 centre(1000.0 * std::cos(e), 1.0 + 1000.0 * std::sin(e), 0.0);
    const glm::dvec3 corner = centre - glm::dvec3(0, 1, 1);
    s.light.block = world::BlockPos(glm::floor(corner));
    s.light.offset = glm::vec3(corner - glm::floor(corner));
    s.light.edge_u = {0, 0, 2};
    s.light.edge_v = {0, 2, 0};
    return s;
}

TEST_F(RendererTest, GrazingLightLeavesNoFalseShadow) {
    world::World w;
    const world::BlockId ids[] = {test::block_id("stone"), test::block_id("sand"), test::block_id("snow")};
    std::mt19937 rng(5);
    test::fill_box(w, {-kFloor, 0, -kFloor}, {kFloor, 1, kFloor}, ids[0]);
    for (int i = 0; i < 200; ++i) {
        const int64_t x = int64_t(rng() % 80) - kFloor, z = int64_t(rng() % 80) - kFloor;
        test::fill_box(w, {x, 0, z}, {std::min<int64_t>(x + 1 + rng() % 9, kFloor), 1, std::min<int64_t>(z + 1 + rng() % 9, kFloor)},
                       ids[rng() % 3]);
    }
    test::load_meshes(*m_renderer, test::mesh_world(w));
    const Camera cam = Camera::look_at({0.3, 30.0, 0.7}, {0.0, 1.0, 0.0}, {0, 0, -1}, 90.f);
    const RenderImage img = m_renderer->render(grazing_settings(0.5), cam);
    test::maybe_save(img, "grazing");
    // The camera looks straight down: with tan(45) * 29 = 29 > 0.3, every pixel sees the floor top.
    int shadowed = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        shadowed += img.rgba[i] != 255 ? 1 : 0;
    EXPECT_EQ(shadowed, 0);
    // Control: a light just below the floor's plane lights nothing.
    const RenderImage below = m_renderer->render(grazing_settings(-0.5), cam);
    EXPECT_EQ(lit_pixels(below), 0);
}

// The area light alone over a floor (no sun, sky term or bounces): the radiance of a 16 x 16
// pixel view, 2 degrees wide, of the point 4 blocks below the centre of a 16 x 16 light (the
// view's spread moves irradiance by < 1e-4). Its mean over the pixels, over albedo / pi, is the
// irradiance the light's samples estimate: within 1.5% of the analytic value (2.61075 L: the
// square's form factor, tests/render/sampling_test.cpp) for 1, 4 and 25 samples per pixel and
// two seeds; sampling_test.cpp holds the same points on the CPU to 0.55%, the rest is half-float
// radiance. Control: 0 samples put the light's whole area at its centre, (256 / 16) L = 16 L.
TEST_F(RendererTest, AreaLightMeanMatchesAnalyticIrradiance) {
    world::World w;
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
    test::load_meshes(*m_renderer, test::mesh_world(w));
    const glm::dvec3 point(0.3, 1.0, 0.2); // On the floor's top face.
    RenderSettings s;
    s.width = s.height = 16;
    s.mode = ShadingMode::Full;
    s.max_bounces = 0;
    s.sun.irradiance = glm::vec3(0.f);
    s.sky_light = 0.f;
    const glm::dvec3 corner = point + glm::dvec3(-8.0, 4.0, -8.0);
    s.light.block = world::BlockPos(glm::floor(corner));
    s.light.offset = glm::vec3(corner - glm::floor(corner));
    s.light.edge_u = {16, 0, 0};
    s.light.edge_v = {0, 0, 16};
    s.light.emission = glm::vec3(0.5f);
    const Camera cam = Camera::look_at(point + glm::dvec3(0, 2, 0), point, {0, 0, -1}, 2.f);
    const double albedo = world::BlockRegistry::default_registry().info(test::block_id("stone")).albedo.g;
    const double expected = 2.61075 * 0.5;
    auto mean_irradiance = [&](uint32_t samples, uint32_t seed) {
        s.shadow_samples = samples;
        s.seed = seed;
        GBufferImage g;
        m_renderer->render(s, cam, &g);
        double sum = 0.0;
        for (const glm::vec4& r : g.radiance)
            sum += double(r.g);
        return sum / double(g.radiance.size()) * glm::pi<double>() / albedo;
    };
    for (uint32_t samples : {1u, 4u, 25u})
        for (uint32_t seed : {1u, 2u})
            EXPECT_NEAR(mean_irradiance(samples, seed), expected, 0.015 * expected)
                << samples << " spp, seed " << seed;
    EXPECT_NEAR(mean_irradiance(0, 1), 16.0 * 0.5, 0.02 * 16.0 * 0.5);
}

} // namespace
} // namespace vx::render
