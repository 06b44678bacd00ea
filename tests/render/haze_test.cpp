// Aerial perspective (issue 16, "the horizon"; shaders/shared/haze.glsl): Full shading sees
// surfaces through haze with distance, towards the sky colour. Scenes are lit by the sky alone
// with shadows off (the unoccluded sky: no rays, no noise), so a surface of albedo a has radiance
// exactly a * sky and the expected pixel is T * a * sky + (1 - T) * sky, T = exp(-optical depth).
// The optical depth is integrated numerically here (midpoint rule), not with the shader's closed
// form. Radiance is read from the G-buffer (half floats, before tone mapping).
#include <cmath>
#include <limits>

#include "scene_util.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using test::RendererTest;

const world::BlockRegistry& reg() { return world::BlockRegistry::default_registry(); }
glm::vec3 albedo(const char* name) { return reg().info(test::block_id(name)).albedo; }

// Sky light only, shadows off, no bounces; haze on with `visibility` and no height falloff.
RenderSettings sky_lit(float visibility) {
    RenderSettings s;
    s.width = 24;
    s.height = 24;
    s.mode = ShadingMode::Full;
    s.shadow_samples = 0;
    s.max_bounces = 0;
    s.sun.irradiance = glm::vec3(0.f);
    s.light.emission = glm::vec3(0.f);
    s.haze.visibility = visibility;
    s.haze.height_falloff = 0.f;
    return s;
}

// Koschmieder: the extinction at which contrast falls to 2% over `visibility`.
double extinction(float visibility) { return std::log(50.0) / double(visibility); }

// Optical depth of the straight segment from height h0 to h1 (above the base height) of length
// len: the density sigma at and below the base, sigma * exp(-falloff * h) above, integrated with
// 20,000 midpoints.
double optical_depth(double sigma, double falloff, double h0, double h1, double len) {
    constexpr int kSteps = 20000;
    double sum = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const double h = h0 + (h1 - h0) * (i + 0.5) / kSteps;
        sum += std::exp(-falloff * std::max(h, 0.0));
    }
    return sigma * sum * len / kSteps;
}

glm::dvec3 hazed(glm::dvec3 surface, glm::dvec3 sky, double transmittance) {
    return transmittance * surface + (1.0 - transmittance) * sky;
}

// The primary ray's unit direction through pixel (x, y), as shaders/shared/raygen_common.glsl
// makes it.
glm::dvec3 pixel_dir(const RenderSettings& s, const Camera& cam, uint32_t x, uint32_t y) {
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(cam.forward));
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(cam.up)));
    const glm::dvec3 up = glm::cross(right, fwd);
    const double th = std::tan(glm::radians(double(cam.fov_y_degrees)) * 0.5), aspect = double(s.width) / s.height;
    const double nx = (x + 0.5) / s.width * 2.0 - 1.0, ny = (y + 0.5) / s.height * 2.0 - 1.0;
    return glm::normalize(fwd + nx * th * aspect * right - ny * th * up);
}

// Whether radiance `got` is `want` within half-float rounding and the depth's (relative 2e-3).
::testing::AssertionResult radiance_near(glm::vec4 got, glm::dvec3 want) {
    for (int c = 0; c < 3; ++c)
        if (std::abs(double(got[c]) - want[c]) > 2e-3 * want[c] + 1e-4)
            return ::testing::AssertionFailure() << "radiance (" << got.r << ", " << got.g << ", " << got.b
                                                 << ") expected (" << want.r << ", " << want.g << ", " << want.b << ")";
    return ::testing::AssertionSuccess();
}

// A 64 x 64 wall of `block` whose front face is the plane z = 0, facing +z.
void load_wall(Renderer& r, const char* block) {
    world::World w;
    test::fill_box(w, {-32, -32, -1}, {32, 32, 0}, test::block_id(block));
    test::load_meshes(r, test::mesh_world(w));
}

// The camera at distance `d` in front of the wall, looking at it; the view (half-angle
// atan(20 / d), diagonal 28 blocks at the wall) stays on the wall.
Camera wall_view(double d) {
    const double fov = 2.0 * glm::degrees(std::atan(20.0 / d));
    return Camera::look_at({0.5, 0.5, d}, {0.5, 0.5, 0.0}, {0, 1, 0}, float(fov));
}

// Every pixel of the wall at two distances is the blend of the formula, by its own distance (the
// G-buffer's depth). 20 km visibility: 9.3% haze at 500 blocks, 44% at 3,000.
TEST_F(RendererTest, HazeBlendsAFarWallTowardsTheSkyByDistance) {
    load_wall(*m_renderer, "stone");
    const RenderSettings s = sky_lit(20000.f);
    const glm::dvec3 sky(s.sky), wall = glm::dvec3(albedo("stone")) * sky;
    for (double d : {500.0, 3000.0}) {
        const Camera cam = wall_view(d);
        GBufferImage g;
        m_renderer->render(s, cam, &g);
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const double t = g.at(g.normal_depth, x, y).w;
                ASSERT_NEAR(t, d / -pixel_dir(s, cam, x, y).z, 2e-3 * d) << x << "," << y; // On the wall.
                const double tr = std::exp(-optical_depth(extinction(s.haze.visibility), 0.0, 0.0, 0.0, t));
                ASSERT_TRUE(radiance_near(g.at(g.radiance, x, y), hazed(wall, sky, tr))) << d << ": " << x << "," << y;
            }
        // The centre's share of sky colour (green: stone and sky differ most there) is
        // 1 - exp(-3.912 d / 20000): 0.093 at 500, 0.444 at 3,000.
        const double share = (double(g.at(g.radiance, 12, 12).g) - wall.g) / (sky.g - wall.g);
        EXPECT_NEAR(share, d < 1000 ? 0.093 : 0.444, 0.002);
    }
}

// Haze off is the picture without haze: radiance exactly albedo x sky, and an infinite
// visibility gives the same bytes and radiance.
TEST_F(RendererTest, HazeOffAndInfiniteVisibilityAreTheUnhazedPicture) {
    load_wall(*m_renderer, "stone");
    RenderSettings off = sky_lit(20000.f);
    off.haze.enabled = false;
    RenderSettings clear = sky_lit(std::numeric_limits<float>::infinity());
    const Camera cam = wall_view(3000.0);
    GBufferImage g_off, g_clear;
    const RenderImage a = m_renderer->render(off, cam, &g_off), b = m_renderer->render(clear, cam, &g_clear);
    EXPECT_EQ(test::differing_bytes(a, b), 0);
    EXPECT_EQ(g_off.radiance, g_clear.radiance);
    const glm::dvec3 wall = glm::dvec3(albedo("stone")) * glm::dvec3(off.sky);
    for (uint32_t y = 0; y < off.height; ++y)
        for (uint32_t x = 0; x < off.width; ++x)
            ASSERT_TRUE(radiance_near(g_off.at(g_off.radiance, x, y), wall)) << x << "," << y;
}

// The defaults (the facade's too) leave near terrain alone and veil far terrain: under 2% of
// sky colour within 100 blocks, about half (55% at the base height) at 4,096 blocks.
TEST_F(RendererTest, DefaultHazeSparesNearTerrainAndVeilsTheHorizon) {
    load_wall(*m_renderer, "grass");
    RenderSettings s = sky_lit(1.f);
    s.haze = Haze{};
    const glm::dvec3 sky(s.sky), wall = glm::dvec3(albedo("grass")) * sky;
    for (double d : {100.0, 4096.0}) {
        GBufferImage g;
        m_renderer->render(s, wall_view(d), &g);
        const glm::vec4 c = g.at(g.radiance, s.width / 2, s.height / 2);
        const double share = (double(c.g) - wall.g) / (sky.g - wall.g); // Green: grass and sky differ most.
        if (d < 1000)
            EXPECT_LT(share, 0.02) << share;
        else
            EXPECT_TRUE(share > 0.5 && share < 0.7) << share;
    }
}

// Density falls off with height above the base height: a floor seen from 1,500 blocks above,
// with the base height above the camera (uniform haze), between (the ray crosses it) and at the
// floor (thinning all the way up). Falloff 1/300 per block: a fifth of the density 500 above.
TEST_F(RendererTest, HazeFollowsTheHeightFalloffIntegral) {
    world::World w;
    test::fill_box(w, {-32, -1, -32}, {32, 0, 32}, test::block_id("stone")); // Top face y = 0.
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = sky_lit(4000.f);
    s.haze.height_falloff = 1.f / 300.f;
    const double eye_y = 1500.5;
    const Camera cam = Camera::look_at({0.5, eye_y, 0.5}, {0.5, 0.0, 0.5}, {0, 0, -1},
                                       float(2.0 * glm::degrees(std::atan(20.0 / eye_y))));
    const glm::dvec3 sky(s.sky), floor = glm::dvec3(albedo("stone")) * sky;
    double centre[3];
    int i = 0;
    for (double base : {2000.0, 1000.0, 0.0}) {
        s.haze.base_height = base;
        GBufferImage g;
        m_renderer->render(s, cam, &g);
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const double t = g.at(g.normal_depth, x, y).w;
                ASSERT_NEAR(t, eye_y / -pixel_dir(s, cam, x, y).y, 2e-3 * eye_y) << x << "," << y;
                const double tau = optical_depth(extinction(s.haze.visibility), s.haze.height_falloff, eye_y - base,
                                                 0.0 - base, t);
                ASSERT_TRUE(radiance_near(g.at(g.radiance, x, y), hazed(floor, sky, std::exp(-tau))))
                    << base << ": " << x << "," << y;
            }
        centre[i++] = g.at(g.radiance, s.width / 2, s.height / 2).g;
    }
    // Less haze, so darker (the floor is darker than the sky), as more of the ray thins out.
    EXPECT_GT(centre[0], centre[1]);
    EXPECT_GT(centre[1], centre[2]);
}

// Mirror bounces are hazed on their own segment too: a mirror wall 1,000 blocks ahead reflects a
// stone wall 500 blocks behind the camera (the reflected ray runs 1,500 blocks). A mirror of
// reflectivity r and albedo m shows T1 (0.1 m sky + r (T2 stone + (1 - T2) sky)) + (1 - T1) sky.
TEST_F(RendererTest, HazeAppliesToMirrorBounces) {
    world::World w;
    test::fill_box(w, {-32, -32, -1}, {32, 32, 0}, test::block_id("mirror"));     // Faces +z at z = 0.
    test::fill_box(w, {-32, -32, 1500}, {32, 32, 1501}, test::block_id("stone")); // Faces -z at z = 1,500.
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = sky_lit(4000.f);
    s.max_bounces = 1;
    const double d = 1000.0;
    // The reflected view spans 2,500 blocks to the stone wall: keep it within 20 blocks there.
    const Camera cam = Camera::look_at({0.5, 0.5, d}, {0.5, 0.5, 0.0}, {0, 1, 0},
                                       float(2.0 * glm::degrees(std::atan(20.0 / 2500.0))));
    const world::BlockInfo& mirror = reg().info(test::block_id("mirror"));
    const glm::dvec3 sky(s.sky), stone = glm::dvec3(albedo("stone")) * sky;
    const double sigma = extinction(s.haze.visibility), r = mirror.reflectivity;
    GBufferImage g;
    m_renderer->render(s, cam, &g);
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const double t1 = g.at(g.normal_depth, x, y).w, t2 = t1 * 1500.0 / d; // Same |dz| both ways.
            const double tr1 = std::exp(-sigma * t1), tr2 = std::exp(-sigma * t2);
            const glm::dvec3 at_mirror = (1.0 - r) * glm::dvec3(mirror.albedo) * sky + r * hazed(stone, sky, tr2);
            ASSERT_TRUE(radiance_near(g.at(g.radiance, x, y), hazed(at_mirror, sky, tr1))) << x << "," << y;
        }
}

// The haze is lit by the sky term's light. Sealed off from the sky (a cave: sky_access false) or
// without sky light (sky_light 0) nothing lights it: it only absorbs. A lamp wall 2,000 blocks
// away then shows T * emission (its albedo gets no light); with half the sky light, it shows
// T * (emission + 0.5 lamp sky) + (1 - T) 0.5 sky.
TEST_F(RendererTest, HazeIsLitByTheSkyTermOnly) {
    load_wall(*m_renderer, "lamp");
    const Camera cam = wall_view(2000.0);
    const glm::dvec3 emission(reg().info(test::block_id("lamp")).emission);
    for (int lit = 0; lit < 3; ++lit) {
        RenderSettings s = sky_lit(4000.f);
        s.sky_access = lit != 0;
        s.sky_light = lit == 1 ? 0.f : 0.5f;
        const glm::dvec3 sky = glm::dvec3(s.sky) * (lit == 2 ? 0.5 : 0.0);
        GBufferImage g;
        m_renderer->render(s, cam, &g);
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const double tr = std::exp(-extinction(s.haze.visibility) * g.at(g.normal_depth, x, y).w);
                const glm::dvec3 wall = emission + glm::dvec3(albedo("lamp")) * sky;
                ASSERT_TRUE(radiance_near(g.at(g.radiance, x, y), hazed(wall, sky, tr)))
                    << lit << ": " << x << "," << y;
            }
    }
}

// Flat shading is block albedo and sky colour, haze or not (tests compare coverage with it).
TEST_F(RendererTest, FlatShadingHasNoHaze) {
    load_wall(*m_renderer, "grass");
    RenderSettings thick = sky_lit(10.f), off = sky_lit(10.f);
    thick.mode = off.mode = ShadingMode::Flat;
    off.haze.enabled = false;
    const Camera cam = wall_view(500.0);
    const RenderImage a = m_renderer->render(thick, cam), b = m_renderer->render(off, cam);
    EXPECT_EQ(test::differing_bytes(a, b), 0);
    EXPECT_TRUE(test::rgb_near(a.at(12, 12), albedo("grass")));
}

// The haze is part of the radiance before the tone map: the denoiser keeps it (its in-scattered
// light is in the reflected part, added back unfiltered), and auto exposure meters the hazed
// radiance: a frame of one radiance L meters to log2(L) + log2(10^4 / (1.2 * kMidGreyInput)).
TEST_F(RendererTest, DenoiserAndExposureMeterSeeTheHazedRadiance) {
    load_wall(*m_renderer, "stone");
    RenderSettings s = sky_lit(20000.f);
    s.shadow_samples = 4; // The denoiser filters sampled light; every sky ray escapes here.
    const Camera cam = wall_view(3000.0);
    const RenderImage plain = m_renderer->render(s, cam);
    RenderSettings denoised = s;
    denoised.denoise = true;
    const RenderImage filtered = m_renderer->render(denoised, cam);
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(int(filtered.at(x, y)[c]), int(plain.at(x, y)[c]), 1) << x << "," << y;
    RenderSettings metered = s;
    metered.exposure.automatic = true;
    GBufferImage g;
    m_renderer->render(metered, cam, &g);
    const glm::vec4 c = g.at(g.radiance, s.width / 2, s.height / 2);
    const double luminance = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    const double expected_ev = std::log2(luminance) + std::log2(gpu::kNitsPerUnit / (1.2 * gpu::kMidGreyInput));
    EXPECT_NEAR(m_renderer->last_stats().ev100, expected_ev, 0.05);
    // Against the unhazed wall's exposure, the haze lifts the meter (sky brighter than stone).
    EXPECT_GT(luminance, 0.2126 * 0.45 * s.sky.r + 0.7152 * 0.45 * s.sky.g + 0.0722 * 0.47 * s.sky.b);
}

} // namespace
} // namespace vx::render
