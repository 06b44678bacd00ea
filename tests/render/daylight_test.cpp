// Issue 10's lighting and transparency, on small scenes: the sky term, the sun through glass,
// an emissive block in a sealed room, blocks seen through glass, the tone-mapped output.
#include <cstdio>
#include <string>

#include "scene_util.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using test::full_output;
using test::RendererTest;

const world::BlockRegistry& reg() { return world::BlockRegistry::default_registry(); }

int brightness(glm::u8vec4 px) { return int(px.r) + px.g + px.b; }

// Pixels of `img` with a non-zero colour byte.
int lit_pixels(const RenderImage& img) {
    int lit = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        lit += img.rgba[i] | img.rgba[i + 1] | img.rgba[i + 2] ? 1 : 0;
    return lit;
}

using test::daylight;

// A stone slab in open air, x, z in [-16, 16), y in [0, 1); the camera 4 blocks above it looks
// straight down (a 60 degree view sees |x|, |z| < 2.4: the top face, far from the edges).
TEST_F(RendererTest, SkyLightsAFloorWhenTheSunIsDown) {
    world::World w;
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = daylight();
    s.sun.direction = {0.f, -1.f, 0.3f}; // Below the horizon: nothing of it reaches the top face.
    const Camera cam = Camera::look_at({0.3, 5.0, 0.2}, {0.3, 0.0, 0.2}, {0, 0, -1});
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "sky_floor");
    // Every sky ray from the open top face escapes (nothing above it), so its radiance is
    // exactly albedo x sky (cosine-weighted rays: the 1/pi cancels); stone's albedo 0.45.
    const glm::vec3 expected = full_output(reg().info(test::block_id("stone")).albedo * s.sky);
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x)
            ASSERT_TRUE(test::rgb_near(img.at(x, y), expected)) << x << "," << y;
    // Controls: no sky term, or the caller saying the view is sealed off: black.
    RenderSettings off = s;
    off.sky_light = 0.f;
    EXPECT_EQ(lit_pixels(m_renderer->render(off, cam)), 0);
    off = s;
    off.sky_access = false;
    EXPECT_EQ(lit_pixels(m_renderer->render(off, cam)), 0);
}

// A closed stone room, inner air [-4, 5)^3 (walls one block thick), optionally a lamp on its
// floor at (2, -4, 0); the camera inside looks down at the floor around the lamp.
world::World stone_room(bool lamp) {
    world::World w;
    test::fill_box(w, {-5, -5, -5}, {6, 6, 6}, test::block_id("stone"));
    for (int64_t z = -4; z < 5; ++z)
        for (int64_t y = -4; y < 5; ++y)
            for (int64_t x = -4; x < 5; ++x)
                w.set_block({x, y, z}, world::kAir);
    if (lamp)
        w.set_block({2, -4, 0}, test::block_id("lamp"));
    return w;
}

TEST_F(RendererTest, LampLightsASealedRoom) {
    const Camera cam = Camera::look_at({0.5, 2.0, 0.5}, {0.5, -4.0, 0.5}, {0, 0, -1}, 90.f);
    RenderSettings s = daylight(16); // Sun and sky on: they must not leak in.
    // No haze: it lights the air with the sky wherever sky_access is true (the engine's is false
    // in a sealed pocket; then the haze only absorbs: haze_test.cpp).
    s.haze.enabled = false;
    test::load_meshes(*m_renderer, test::mesh_world(stone_room(false)));
    EXPECT_EQ(lit_pixels(m_renderer->render(s, cam)), 0) << "light leaks into the sealed room";

    m_renderer->clear_chunks();
    test::load_meshes(*m_renderer, test::mesh_world(stone_room(true)));
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "lamp_room");
    // The camera at y = 2 looks down with a 90 degree view, 6 blocks above the floor top (y = -4),
    // +x to the right, -z up in the image: a floor point at x, z is pixel column
    // 16 + (x - 0.5) / 6 * 16, row 16 + (z - 0.5) / 6 * 16. The floor beside the lamp, (1.5, 0.5):
    // column 18.7, row 16: lit by the lamp (its emission 4 is far above the knee).
    EXPECT_GT(brightness(img.at(18, 16)), 30);
    EXPECT_GT(lit_pixels(img), 100);
    // The far corner of the floor (-3.5, -3.5), pixel (5, 5), sees the lamp at a grazing angle
    // from 6 blocks away: lit less than the floor beside the lamp.
    EXPECT_LT(brightness(img.at(5, 5)), brightness(img.at(18, 16)));
    // Sealed off from the sky (sky_access false): sky rays still run to find the lamp (its faces
    // not sampled: the same image to the byte).
    RenderSettings rays = s, no_sky = s;
    rays.emitter_sampling = no_sky.emitter_sampling = false;
    no_sky.sky_access = false;
    const RenderImage by_rays = m_renderer->render(rays, cam);
    EXPECT_EQ(test::differing_bytes(m_renderer->render(no_sky, cam), by_rays), 0);
    // With its faces sampled they are sampled wherever the sky cannot outshine the lamp, here
    // everywhere without sky access and near the lamp with it (the rest is left to sky rays): the
    // same light, less noise. Mean byte within 2% of the sky rays' image.
    no_sky.emitter_sampling = true;
    const double sampled = test::mean_byte(m_renderer->render(no_sky, cam)), open = test::mean_byte(img),
                 found = test::mean_byte(by_rays);
    std::printf("lamp room mean byte: faces sampled, sealed %.3f, open %.3f; sky rays %.3f\n", sampled, open, found);
    EXPECT_NEAR(sampled / found, 1.0, 0.02);
    EXPECT_NEAR(open / found, 1.0, 0.02);
}

// A red block at z in [0, 1) behind a glass block at z in [3, 4); the camera at z = 8 looks at
// both along -z through the glass.
world::World red_behind_glass(world::BlockId red) {
    world::World w;
    w.set_block({0, 0, 0}, red);
    w.set_block({0, 0, 3}, test::block_id("glass"));
    return w;
}

TEST_F(RendererTest, RedBlockIsSeenThroughGlass) {
    world::BlockRegistry registry = reg();
    world::BlockInfo red_info;
    red_info.name = "red";
    red_info.albedo = {0.9f, 0.05f, 0.05f};
    const world::BlockId red = registry.add(red_info).value();
    m_renderer->set_registry(registry);
    // Meshing with the default registry is the same here: an id it does not know is opaque.
    test::load_meshes(*m_renderer, test::mesh_world(red_behind_glass(red)));
    const Camera cam = Camera::look_at({0.5, 0.5, 8.5}, {0.5, 0.5, 0.0}, {0, 1, 0}, 20.f);
    RenderSettings s = daylight();
    s.mode = ShadingMode::Flat;
    const RenderImage flat = m_renderer->render(s, cam);
    test::maybe_save(flat, "glass_flat");
    // The centre ray crosses one block of glass straight through (one glass albedo: Beer-Lambert
    // over one block) and hits the red block: red x glass, linear (Flat mode).
    const glm::vec3 glass = reg().info(test::block_id("glass")).albedo;
    EXPECT_TRUE(test::rgb_near(flat.at(16, 16), red_info.albedo * glass));

    s.mode = ShadingMode::Full;
    s.sun.direction = {0.f, 0.3f, 1.f}; // Behind the camera: the red block's +z face is sunlit.
    const RenderImage full = m_renderer->render(s, cam);
    test::maybe_save(full, "glass_full");
    const glm::u8vec4 px = full.at(16, 16);
    EXPECT_GT(int(px.r), 100);
    EXPECT_GT(int(px.r), 3 * int(px.g));
    EXPECT_GT(int(px.r), 3 * int(px.b));
}

// A stone floor x, z in [-16, 16), y in [0, 1) under a roof at y in [5, 6) of `roof` blocks; the
// camera under the roof looks down at the floor; the sun straight above, no sky term.
TEST_F(RendererTest, GlassRoofLetsSunlightThrough) {
    auto render_under = [&](const char* roof) {
        world::World w;
        test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
        test::fill_box(w, {-16, 5, -16}, {16, 6, 16}, test::block_id(roof));
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(w));
        RenderSettings s = daylight();
        s.sky_light = 0.f;
        s.sun.direction = {0.f, 1.f, 0.f};
        return m_renderer->render(s, Camera::look_at({0.3, 3.0, 0.2}, {0.3, 0.0, 0.2}, {0, 0, -1}));
    };
    EXPECT_EQ(lit_pixels(render_under("stone")), 0); // Control: an opaque roof shades the floor.
    const RenderImage img = render_under("glass");
    test::maybe_save(img, "glass_roof");
    // Radiance of the floor: albedo x E x T / pi with T = glass albedo (two faces) times what each
    // face does not mirror (at normal incidence: 1 - reflectivity), E the sun's irradiance times
    // cos of the disc samples (>= cos 0.27 degrees, so within 2e-5 of E, and of T's Fresnel).
    const RenderSettings s = daylight();
    const world::BlockInfo& glass = reg().info(test::block_id("glass"));
    const float pass = float(1.0 - test::fresnel(glass.reflectivity, 1.0));
    const glm::vec3 radiance =
        reg().info(test::block_id("stone")).albedo * s.sun.irradiance * glass.albedo * pass * pass / 3.14159265f;
    EXPECT_TRUE(test::rgb_near(img.at(16, 16), full_output(radiance)));
}

// bounce_shadow_samples applies to reflection bounces only. A mirror wall (x in [-1, 0), facing
// +x) under a stone roof (y in [3, 4), x in [0, 16)) over a stone floor; the sun straight above.
// The camera looks at the mirror, which shows the floor under the roof: in shadow.
TEST_F(RendererTest, BounceShadowSamplesApplyToBouncesOnly) {
    world::World w;
    test::fill_box(w, {-1, 0, -8}, {16, 1, 8}, test::block_id("stone"));
    test::fill_box(w, {0, 3, -8}, {16, 4, 8}, test::block_id("stone"));
    test::fill_box(w, {-1, 1, -8}, {0, 3, 8}, test::block_id("mirror"));
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = daylight(4);
    s.sky_light = 0.f;
    s.sun.direction = {0.f, 1.f, 0.f};
    s.max_bounces = 1;
    // Eye (8, 2.5, 0.5) towards (-1, 1.5, 0.5): the centre ray meets the mirror at y = 1.61 and
    // reflects down onto the floor top (y = 1) at x = 5.5, under the roof.
    const Camera mirror_view = Camera::look_at({8.0, 2.5, 0.5}, {-1.0, 1.5, 0.5}, {0, 1, 0}, 20.f);
    s.bounce_shadow_samples = 4;
    const glm::u8vec4 shadowed = m_renderer->render(s, mirror_view).at(16, 16);
    EXPECT_LT(brightness(shadowed), 6);
    // Zero samples on bounces: shadows off there, the floor in the mirror is sunlit (0.9 x
    // 0.45 x 3 / pi ~ 0.39 linear).
    s.bounce_shadow_samples = 0;
    const RenderImage unshadowed = m_renderer->render(s, mirror_view);
    test::maybe_save(unshadowed, "bounce_spp");
    EXPECT_GT(brightness(unshadowed.at(16, 16)), 3 * 100);
    // The first hit does not depend on it: the floor seen directly is the same image.
    const Camera floor_view = Camera::look_at({8.0, 2.5, 0.5}, {6.0, 1.0, 0.5}, {0, 1, 0}, 20.f);
    s.bounce_shadow_samples = 4;
    const RenderImage a4 = m_renderer->render(s, floor_view);
    s.bounce_shadow_samples = 0;
    EXPECT_EQ(test::differing_bytes(a4, m_renderer->render(s, floor_view)), 0);
}

// Sky rays past the first hit (occlusion rays: shared/raygen_emitters.glsl's sky_and_emitters()) see the open
// sky, a stone roof's shade and the sky through a glass roof, as first-hit sky rays do. A
// perfect mirror wall (reflectivity 1: no light of its own) at x in [-1, 0), y in [1, 3),
// z in [-2, 2) over a stone slab x, z in [-16, 16), y in [0, 1); sky light only. The centre ray
// meets the mirror at (0, 2.8, 0.5) and reflects down onto the slab's top at x = 12, where a
// roof at y in [4, 5), x in [8, 16) may shade it.
TEST_F(RendererTest, SkyRaysPastTheFirstHitSeeTheSkyAndWhatCoversIt) {
    const world::BlockId mirror = test::set_perfect_mirror(*m_renderer);
    auto centre_seen_in_mirror = [&](const char* roof) {
        world::World w;
        test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
        test::fill_box(w, {-1, 1, -2}, {0, 3, 2}, mirror);
        if (roof)
            test::fill_box(w, {8, 4, -16}, {16, 5, 16}, test::block_id(roof));
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(w));
        RenderSettings s = daylight(16);
        s.sun.direction = {0.f, -1.f, 0.3f}; // Below the horizon.
        s.max_bounces = 1;
        const Camera cam = Camera::look_at({1.0, 2.95, 0.5}, {0.0, 2.8, 0.5}, {0, 1, 0}, 20.f);
        const RenderImage img = m_renderer->render(s, cam);
        test::maybe_save(img, roof ? (std::string("mirror_sky_") + roof).c_str() : "mirror_sky_open");
        return img.at(16, 16);
    };
    // Open: the wall covers about 0.2% of the cosine-weighted sky of that point, low over its
    // horizon, so the floor's radiance is albedo x sky, and the perfect mirror passes all of it.
    const glm::u8vec4 open = centre_seen_in_mirror(nullptr);
    const glm::vec3 floor = reg().info(test::block_id("stone")).albedo * daylight().sky;
    EXPECT_TRUE(test::rgb_near(open, full_output(floor), 2));
    // A stone roof leaves only low strips of sky in +-x; a glass one passes the sky, tinted.
    const glm::u8vec4 stone = centre_seen_in_mirror("stone");
    const glm::u8vec4 glass = centre_seen_in_mirror("glass");
    EXPECT_LT(brightness(stone), brightness(open) * 3 / 4);
    EXPECT_GT(brightness(glass), brightness(stone) + 30);
    EXPECT_LT(brightness(glass), brightness(open));
}

// The G-buffer (render/gbuffer.h) of a floor seen from above with sky in the top rows: the
// camera at y = 5 over a stone slab (top y = 1) looks down 30 degrees below the horizon along -z.
TEST_F(RendererTest, GBufferHoldsFirstHitAlbedoNormalDepthAndRadiance) {
    world::World w;
    test::fill_box(w, {-16, 0, -32}, {16, 1, 16}, test::block_id("stone"));
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = daylight();
    const glm::dvec3 eye(0.5, 5.0, 10.5);
    const glm::dvec3 dir(0.0, -std::sin(glm::radians(30.0)), -std::cos(glm::radians(30.0)));
    GBufferImage g;
    const RenderImage img = m_renderer->render(s, Camera::look_at(eye, eye + dir), &g);
    ASSERT_EQ(g.width, s.width);
    ASSERT_EQ(g.normal_depth.size(), size_t(s.width) * s.height);
    // Centre ray (pixel 16, 16 is half a pixel off the axis): along dir, it meets the top face
    // y = 1 after 4 / sin 30 = 8 blocks.
    const glm::vec4 nd = g.at(g.normal_depth, 16, 16);
    EXPECT_NEAR(nd.x, 0.f, 1e-3f);
    EXPECT_NEAR(nd.y, 1.f, 1e-3f);
    EXPECT_NEAR(nd.z, 0.f, 1e-3f);
    EXPECT_NEAR(nd.w, 8.f, 0.25f); // Half a pixel of 60/32 degrees moves the hit by < 0.25.
    const glm::vec3 stone = reg().info(test::block_id("stone")).albedo;
    const glm::vec4 al = g.at(g.albedo, 16, 16);
    EXPECT_NEAR(al.r, stone.r, 1.f / 255.f);
    EXPECT_NEAR(al.b, stone.b, 1.f / 255.f);
    EXPECT_EQ(al.a, 1.f);
    // The top row looks up to 30 - 30 = 0 degrees below the horizon, over a floor ending 26
    // blocks ahead, whose top it would meet only after 4 / tan(0.9 deg) > 250 blocks: a miss.
    EXPECT_EQ(g.at(g.normal_depth, 16, 0), glm::vec4(0.f));
    EXPECT_EQ(g.at(g.albedo, 16, 0).a, 0.f);
    // The output is the tone-mapped radiance, pixel by pixel (half floats: +-1 byte).
    for (uint32_t y = 0; y < s.height; y += 5)
        for (uint32_t x = 0; x < s.width; x += 5)
            EXPECT_TRUE(test::rgb_near(img.at(x, y), full_output(glm::vec3(g.at(g.radiance, x, y)))));
}

// Exposed values above 1 are rolled off below 255 in distinct steps (the empty scene shows the
// sky: every pixel is the sky's radiance). An EV100 of log2(kNitsPerUnit / 1.2) makes the
// exposure scale 1, so the sky's radiance is the tone curve's input: 1 -> 0.804 -> byte 232,
// 1.25 -> 0.847 -> 237, 0.5 -> 0.616 -> 206 (tonemap.h).
TEST_F(RendererTest, ToneMappingKeepsBrightSkiesBelowWhite) {
    RenderSettings s = daylight();
    s.sky = {1.0f, 1.25f, 0.5f};
    s.exposure.ev100 = std::log2(gpu::kNitsPerUnit / 1.2f);
    ASSERT_NEAR(gpu::vx_exposure_scale(s.exposure.ev100), 1.f, 1e-5f);
    const RenderImage img = m_renderer->render(s, Camera{});
    const glm::u8vec4 px = img.at(5, 5);
    EXPECT_TRUE(test::rgb_near(px, gpu::vx_display(s.sky, 1.f)));
    EXPECT_LT(px.r, px.g);
    EXPECT_LT(px.g, 255);
    EXPECT_NEAR(int(px.r), 232, 1);
    EXPECT_NEAR(int(px.g), 237, 1);
    EXPECT_NEAR(int(px.b), 206, 1);
}

} // namespace
} // namespace vx::render
