// A see-through block's surface mirrors (vx_fresnel in shaders/shared/rt_common.glsl): each face
// of water or glass passes 1 - F of the light crossing it, F from the Fresnel equations at the
// ray's angle with the block's reflectivity as its reflectance at normal incidence, and the eye's
// path follows the share F from the first such face it enters from air (raygen.rgen, go_on()), as
// it follows a mirror block. Checked against the Fresnel equations in their angle form
// (test::fresnel), pixel by pixel.
#include <cmath>
#include <cstdio>

#include "scene_util.h"
#include "shaders/shared/render_types.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::eye_of;
using test::full_output;
using test::linear_of;
using test::RendererTest;

constexpr float kPi = 3.14159265f;

// Full mode at 48x40, `samples` per pixel, no haze, no sky term (the sky colour is only what rays
// that miss see), the sky colour `sky`, the given reflection depth.
RenderSettings pool_settings(uint32_t samples, glm::vec3 sky, uint32_t bounces) {
    RenderSettings s = test::daylight(samples);
    s.width = 48;
    s.height = 40;
    s.haze.enabled = false;
    s.sky_light = 0.f;
    s.sky = sky;
    s.max_bounces = bounces;
    return s;
}

// Where the ray from `eye` along `d` meets the plane y = `plane` going down (false: it does not).
bool down_to(glm::dvec3 eye, glm::dvec3 d, double plane, glm::dvec3& at) {
    if (d.y >= 0.0)
        return false;
    at = eye + d * ((plane - eye.y) / d.y);
    return true;
}

// A stone floor at y in [0, 1) and water over it at y in [1, 2), both x, z in [-40, 40); lit by the
// sun alone (no sky term: the sky colour is only what rays that miss see), no haze. The eye looks
// across the pool from 0.6 above it, from steep to grazing angles and over the horizon. Each water
// pixel is the floor through the surface plus the sky in it:
//   stone * a^(1 / cos_t + 1 / cos_sun_t) * (1 - F_eye) / n^2 * (1 - F_sun) * E cos_sun / pi
//   + F_eye * sky,
// the floor's light crossing the surface once each way and the one block of water on each way's
// slant (Beer-Lambert: see_through_body_test.cpp), the view bent into the water (cos_t: Snell's
// law, n the water's index) and its radiance spread by n^2 on its way out, the sun's light bent too
// (cos_sun_t; a flat surface passes the floor E cos_sun all the same: sun_under_water_test.cpp),
// F_eye at the view ray's angle and F_sun at the sun's. Without reflections (max_bounces 0) the sky
// term goes, as a mirror block's; water of reflectivity 0 only tints, and 0.3 mirrors more. Each
// way's path in the water absorbs: the sun's by its walk (sun_through, stop 54; before, by the
// shadow ray's any-hit optical depth, shadow.rahit). Checked at stops 52-53, of 1,104 water pixels
// off (reflectivity 0.02 with and without reflections, 0.3): the walk's 1 - F left out, 1,095,
// 1,104 and 949; Schlick's approximation in place of the equations, 608, 386 and 868; the any-hit's
// optical depth left out, 968 (the first); the view unbent, 1,104, 1,104 and 70; without the n^2
// law, all three times; the reflected ray from the floor in place of the surface, all (stop 52).
TEST_F(RendererTest, APoolsSurfacePassesAndMirrorsLightAsFresnelSays) {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    const world::BlockId stone = test::block_id("stone"), water = test::block_id("water");
    RenderSettings s = pool_settings(4, {0.5f, 0.6f, 0.8f}, 1);
    s.sun.direction = glm::normalize(glm::vec3(0.3f, 1.f, 0.5f));
    const Camera cam = Camera::look_at({0.3, 2.6, 6.2}, {0.3, 1.2, -4.0}, {0, 1, 0}, 70.f);
    struct Case {
        float reflectivity;
        uint32_t bounces;
    };
    for (const Case c : {Case{0.02f, 1}, Case{0.02f, 0}, Case{0.f, 1}, Case{0.3f, 2}}) {
        world::BlockInfo info = reg.info(water);
        info.reflectivity = c.reflectivity;
        ASSERT_TRUE(reg.set(water, info));
        m_renderer->set_registry(reg);
        world::World w;
        w.registry() = reg;
        test::fill_box(w, {-40, 0, -40}, {40, 1, 40}, stone);
        test::fill_box(w, {-40, 1, -40}, {40, 2, 40}, water);
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(w));
        s.max_bounces = c.bounces;
        const RenderImage img = m_renderer->render(s, cam);
        test::maybe_save(img, c.reflectivity > 0.f && c.bounces > 0 ? "pool_fresnel" : "pool_fresnel_off");
        const glm::vec3 a = info.albedo;
        const double sun_cos = s.sun.direction.y; // The floor's normal is +y.
        const double sun_pass = 1.0 - test::fresnel(c.reflectivity, sun_cos);
        const glm::vec3 sun_light = reg.info(stone).albedo * s.sun.irradiance * float(sun_cos * sun_pass) / kPi;
        int checked = 0, off = 0, grazing = 0;
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height);
                glm::dvec3 top, bottom;
                const bool water_hit = down_to(eye_of(cam), d, 2.0, top) && down_to(eye_of(cam), d, 1.0, bottom);
                if (water_hit && (std::abs(bottom.x) > 38.0 || std::abs(bottom.z) > 38.0))
                    continue; // Near the pool's sides.
                glm::vec3 expected = s.sky;
                if (water_hit) {
                    const double f = test::fresnel(c.reflectivity, -d.y), n = test::index_of(c.reflectivity);
                    const double cos_t = test::refracted_cos(c.reflectivity, -d.y);
                    const double sun_t = test::refracted_cos(c.reflectivity, sun_cos);
                    const glm::vec3 floor_light = sun_light * test::absorbed(a, 1.0 / cos_t + 1.0 / sun_t);
                    const glm::vec3 mirrored = c.bounces > 0 ? s.sky * float(f) : glm::vec3(0.f);
                    expected = floor_light * float((1.0 - f) / (n * n)) + mirrored;
                    grazing += -d.y < 0.3 ? 1 : 0;
                }
                ++checked;
                const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), full_output(expected));
                if (!near && off++ < 4)
                    ADD_FAILURE() << "reflectivity " << c.reflectivity << ", bounces " << c.bounces << ", pixel (" << x
                                  << ", " << y << "), view cos " << -d.y << ": " << near.message();
            }
        EXPECT_EQ(off, 0) << "of " << checked << " pixels (reflectivity " << c.reflectivity << ")";
        EXPECT_GT(grazing, 100) << "the view has too few grazing pixels to tell";
    }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// A glass pane (x in [-40, 40), y in [2, 8), z in [2, 3)) stands on the pool of the test above, across
// the view; the sun nearly overhead (its light, bent in the water, keeps its z). A view ray through
// the pane to the water meets two mirroring surfaces: the pane's (F_pane, 4%) and the water's behind it, at a
// grazing angle half a mirror. The walk keeps the one that weighs more in the pixel (the water's:
// the others' shares are dropped), so the lake mirrors the sky behind a window as without it, seen
// through the pane: pass_pane (a_glass^(1 / cos_t) (1 - F_pane)^2, cos_t the bent view's in the
// glass; the n^2 of the way in and out cancel) times the pool's pixel of the test above, the view
// leaving the pane parallel to itself and shifted (Snell's law at both faces).
// In front of the pane the water mirrors the pane (the sky through it) or the sky over it; above
// the water the pane mirrors the sky behind the eye. Pixels within 0.15 blocks of an edge (the
// pane's foot and top, in view or in the mirror, and the floor whose sunlight crosses the pane) are
// left out. Checked: with the first surface kept in place of the heavier, all 192 pixels of water
// behind the pane are off.
TEST_F(RendererTest, ALakeBehindAWindowMirrorsTheSkyAsWithoutIt) {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    m_renderer->set_registry(reg);
    const world::BlockId stone = test::block_id("stone"), water = test::block_id("water");
    const world::BlockId glass = test::block_id("glass");
    world::World w;
    test::fill_box(w, {-40, 0, -40}, {40, 1, 40}, stone);
    test::fill_box(w, {-40, 1, -40}, {40, 2, 40}, water);
    test::fill_box(w, {-40, 2, 2}, {40, 8, 3}, glass);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = pool_settings(4, {0.5f, 0.6f, 0.8f}, 1);
    s.sun.direction = glm::normalize(glm::vec3(0.3f, 1.f, 0.f));
    const Camera cam = Camera::look_at({0.3, 2.6, 6.2}, {0.3, 1.8, -4.0}, {0, 1, 0}, 70.f);
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "lake_behind_window");
    const world::BlockInfo& g = reg.info(glass);
    const world::BlockInfo& wat = reg.info(water);
    const double sun_cos = s.sun.direction.y;
    const glm::vec3 sun_light = reg.info(stone).albedo * s.sun.irradiance *
                                float(sun_cos * (1.0 - test::fresnel(wat.reflectivity, sun_cos))) / kPi;
    auto pane_pass = [&](double cos_z) { // One block of glass along z on the bent slant.
        const double f = test::fresnel(g.reflectivity, cos_z);
        const double path = 1.0 / test::refracted_cos(g.reflectivity, cos_z);
        return test::absorbed(g.albedo, path) * float((1.0 - f) * (1.0 - f));
    };
    // Where the view from `eye` along d goes on past the pane (z = 3 to 2), if it crosses it below
    // y = 8: bent into the glass (its tangential part over n), out again parallel to d.
    auto past_pane = [&](glm::dvec3 eye, glm::dvec3 d) {
        if (d.z >= 0.0 || eye.z <= 3.0)
            return eye;
        const glm::dvec3 in = eye + d * ((eye.z - 3.0) / -d.z);
        if (in.y >= 8.0)
            return eye;
        const double n = test::index_of(g.reflectivity), cos_t = test::refracted_cos(g.reflectivity, -d.z);
        const glm::dvec3 dt(d.x / n, d.y / n, -cos_t);
        return in + dt / cos_t; // On z = 2: the ray goes on from here along d.
    };
    int behind = 0, in_front = 0, sky = 0, off = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height), eye0 = eye_of(cam);
            const glm::dvec3 eye = past_pane(eye0, d); // Where the view goes on along d.
            const double f_pane = test::fresnel(g.reflectivity, -d.z);
            const double pane_y = eye0.y + d.y * (eye0.z - 3.0) / -d.z; // Where the view meets z = 3.
            glm::vec3 expected;
            glm::dvec3 top, bottom;
            const bool water_hit = down_to(eye, d, 2.0, top);
            if (water_hit) { // The floor under the bent view: its tangential part over n, a block down.
                const double n = test::index_of(wat.reflectivity);
                const double cos_t = test::refracted_cos(wat.reflectivity, -d.y);
                bottom = top + glm::dvec3(d.x / n, -cos_t, d.z / n) / cos_t;
            }
            if (!water_hit) { // The sky, through the pane or over it.
                if (std::abs(pane_y - 8.0) < 0.15)
                    continue;
                expected = pane_y < 8.0 ? s.sky * (pane_pass(-d.z) + glm::vec3(float(f_pane))) : s.sky;
                ++sky;
            } else {
                const auto at_foot = [](double z) { return z > 1.5 && z < 3.5; };
                if (std::abs(bottom.x) > 38.0 || std::abs(bottom.z) > 38.0 || at_foot(top.z) || at_foot(bottom.z))
                    continue; // Near the pool's sides; the pane's foot (the floor's sunlight through it).
                const double f = test::fresnel(wat.reflectivity, -d.y);
                glm::vec3 mirrored = s.sky * float(f);
                if (top.z > 3.0) { // The reflection meets the pane's plane at this height.
                    const double y_r = 2.0 - d.y * (top.z - 3.0) / -d.z;
                    if (std::abs(y_r - 8.0) < 0.15)
                        continue;
                    if (y_r < 8.0)
                        mirrored *= pane_pass(-d.z);
                }
                const double n = test::index_of(wat.reflectivity);
                const double cos_t = test::refracted_cos(wat.reflectivity, -d.y);
                const double sun_t = test::refracted_cos(wat.reflectivity, sun_cos);
                const glm::vec3 floor_light =
                    sun_light * test::absorbed(wat.albedo, 1.0 / cos_t + 1.0 / sun_t);
                expected = floor_light * float((1.0 - f) / (n * n)) + mirrored;
                if (top.z < 2.0) { // Seen through the pane; the water's reflection weighs more.
                    const glm::vec3 pass = pane_pass(-d.z);
                    if (0.2126 * pass.r + 0.7152 * pass.g + 0.0722 * pass.b < f_pane / f)
                        continue;
                    expected *= pass;
                    ++behind;
                } else {
                    ++in_front;
                }
            }
            const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), full_output(expected));
            if (!near && off++ < 4)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "), view " << d.x << ", " << d.y << ", " << d.z << ": "
                              << near.message();
        }
    EXPECT_EQ(off, 0) << "of " << behind << " behind the pane, " << in_front << " in front, " << sky << " sky";
    std::printf("%d pixels behind the pane, %d in front, %d sky\n", behind, in_front, sky);
    EXPECT_GT(behind, 50);
    EXPECT_GT(in_front, 50);
    EXPECT_GT(sky, 50);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The default registry and a black block (albedo 0: it sends back no light of its own), named
// `name`, opaque, of reflectivity `reflectivity`.
world::BlockRegistry with_black(const char* name, float reflectivity, world::BlockId& id) {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    world::BlockInfo info;
    info.name = name;
    info.albedo = glm::vec3(0.f);
    info.reflectivity = reflectivity;
    const Result<world::BlockId> added = reg.add(info);
    EXPECT_TRUE(added);
    id = added ? *added : world::kAir;
    return reg;
}

// A wall of lamps (x in [-40, 40), y in [2, 6), its face at z = -18) beyond a pool on a black floor
// (the water at y in [1, 2), z > -18), nothing else lit: the sky black, no sun. Where the view ray
// meets the water its reflection, (d.x, -d.y, d.z) from the surface, finds the wall at its mirror
// image or the black sky; through the water the floor is black. So a water pixel is F_eye times
// the lamp's emission or black, as the geometry says pixel by pixel (pixels within 0.15 blocks of
// the wall's edge in the mirror are left out). Checked: the reflection's weight without F (the
// tint up to the surface alone) puts all 288 pixels that mirror the wall off.
TEST_F(RendererTest, ALampWallIsSeenInAPoolAtItsMirrorImage) {
    world::BlockId soot = 0;
    const world::BlockRegistry reg = with_black("soot", 0.f, soot);
    m_renderer->set_registry(reg);
    const world::BlockId water = test::block_id("water"), lamp = test::block_id("lamp");
    world::World w;
    w.registry() = reg;
    test::fill_box(w, {-40, 0, -40}, {40, 1, 40}, soot);
    test::fill_box(w, {-40, 1, -40}, {40, 2, -18}, soot);
    test::fill_box(w, {-40, 1, -18}, {40, 2, 40}, water);
    test::fill_box(w, {-40, 2, -19}, {40, 6, -18}, lamp);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = pool_settings(4, glm::vec3(0.f), 1);
    s.sun.irradiance = glm::vec3(0.f);
    const Camera cam = Camera::look_at({0.3, 3.0, 6.2}, {0.3, 1.5, -18.0}, {0, 1, 0}, 60.f);
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "lamp_wall_in_pool");
    const glm::vec3 emission = reg.info(lamp).emission;
    const double reflectivity = reg.info(water).reflectivity;
    int mirrored = 0, dark = 0, off = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height);
            glm::dvec3 top;
            if (!down_to(eye_of(cam), d, 2.0, top) || top.z <= -17.9)
                continue; // Not on the water.
            const double to_wall = (top.z + 18.0) / -d.z; // Along the reflected ray.
            const glm::dvec3 at = top + glm::dvec3(d.x, -d.y, d.z) * to_wall;
            const bool sees_wall = d.z < 0.0 && at.y < 6.0 && std::abs(at.x) < 40.0;
            if (d.z < 0.0 && std::abs(at.y - 6.0) < 0.15)
                continue; // The wall's top edge in the mirror.
            const double f = test::fresnel(reflectivity, -d.y);
            const glm::vec3 expected = sees_wall ? emission * float(f) : glm::vec3(0.f);
            (sees_wall ? mirrored : dark) += 1;
            const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), full_output(expected));
            if (!near && off++ < 4)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "), view cos " << -d.y << ": " << near.message();
        }
    EXPECT_EQ(off, 0) << "of " << mirrored << " mirroring the wall and " << dark << " the sky";
    EXPECT_GT(mirrored, 100);
    EXPECT_GT(dark, 50);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// A mirror floor (albedo 0, reflectivity 1) under a pool: the path can go on along the surface's
// reflection (weight F_eye) or the floor's (a^(2 / cos_t) (1 - F_eye)^2 on the bent slant down
// and back up through the surface, which bends it back: the n^2 of the way in and the way out
// cancel, and Fresnel's share from inside at the bent angle equals that from outside), and takes
// one of them by the luminance of its weight, divided by that chance. The mean of 64 frames (each with its own choices) is then, channel by channel over the image,
//   (F_eye + a^(2 / cos_t) (1 - F_eye)^2) * sky,
// within 2% (measured: 0.1%); a single frame's pixels are one or the other. Checked: without the
// division by the chance, the mean is 0.43 / 0.71 / 0.81 of that (red / green / blue).
TEST_F(RendererTest, AMirrorUnderWaterAndTheSurfaceShareThePathByWeight) {
    world::BlockId steel = 0;
    const world::BlockRegistry reg = with_black("black mirror", 1.f, steel);
    m_renderer->set_registry(reg);
    const world::BlockId water = test::block_id("water");
    world::World w;
    w.registry() = reg;
    test::fill_box(w, {-40, 0, -40}, {40, 1, 40}, steel);
    test::fill_box(w, {-40, 1, -40}, {40, 2, 40}, water);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = pool_settings(1, {0.5f, 0.6f, 0.8f}, 2);
    s.sun.irradiance = glm::vec3(0.f);
    // Looking down at 50 degrees: every pixel sees the pool.
    const Camera cam = Camera::look_at({0.3, 6.0, 4.2}, {0.3, 1.5, 0.2}, {0, 1, 0}, 40.f);
    const glm::vec3 a = reg.info(water).albedo;
    const double reflectivity = reg.info(water).reflectivity;
    const RenderImage one = m_renderer->render(s, cam);
    const RenderImage mean = test::accumulated(*m_renderer, s, cam, 64, 1);
    test::maybe_save(mean, "mirror_under_water");
    glm::dvec3 got(0.0), want(0.0);
    int surface_picks = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height);
            const double f = test::fresnel(reflectivity, -d.y);
            const double cos_t = test::refracted_cos(reflectivity, -d.y);
            const double n = test::index_of(reflectivity);
            const glm::vec3 down = test::absorbed(a, 1.0 / cos_t) * float((1.0 - f) / (n * n)); // To the floor.
            const glm::vec3 mirrored = s.sky * float(f);
            const glm::vec3 floor = s.sky * test::absorbed(a, 2.0 / cos_t) * float((1.0 - f) * (1.0 - f));
            const glm::vec3 e = mirrored + floor;
            // One frame: each pixel is one branch's weight over its chance, the share of the
            // surface's weight F and the floor's (down: its way in) by luminance (go_on); blue
            // tells them apart (the floor's branch brings the sky up through the water, brighter).
            const float ls = float(f), lo = gpu::vx_luminance(down);
            const int b_surface = test::unorm8(full_output(mirrored * ((ls + lo) / ls)).b);
            const int b_floor = test::unorm8(full_output(floor * ((ls + lo) / lo)).b);
            const int b = int(one.at(x, y).b);
            surface_picks += std::abs(b - b_surface) < std::abs(b - b_floor) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                got[c] += linear_of(mean.at(x, y)[c]);
                want[c] += e[c];
            }
        }
    std::printf("mean of 64 frames / expected: %.4f %.4f %.4f; %d of %d pixels took the surface in one frame\n",
                got.r / want.r, got.g / want.g, got.b / want.b, surface_picks, int(s.width * s.height));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c] / want[c], 1.0, 0.02) << "channel " << c;
    const int pixels = int(s.width * s.height);
    EXPECT_GT(surface_picks, pixels / 50) << "no pixel took the surface's reflection";
    EXPECT_LT(surface_picks, pixels / 2) << "the surface's reflection was taken too often";
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The eye under water looks up (RenderSettings::eye_block): a pool 4 deep (water y in [1, 5)) on a
// floor of black glowing blocks (albedo 0, emission `glow`), the eye 2 under the surface, the sky
// black but for its colour, nothing else lit. Within Snell's window (the view's angle to the
// vertical under the critical angle, asin(1 / n) = 48.8 degrees for water) the view leaves through
// the surface, bent, and sees the sky n^2 (1 - F) brighter than itself (radiance's n^2 law), plus
// the surface's share F mirroring the floor; past it the surface mirrors all (total internal
// reflection) and the walk goes on down to the floor:
//   inside:  n^2 (1 - F) a^(2 / cos) sky  +  F a^(6 / cos) glow,      outside:  a^(6 / cos) glow,
// cos the view's to the vertical, F Fresnel's share from inside (the angle form at the bent angle
// in air: the same by reciprocity). Pixels within 1.5 degrees of the critical angle are left out.
// Checked: the walk ended at total internal reflection (no light: black) puts all 1,432 pixels past
// it off; without the n^2 law, all 716 inside. (The bend itself does not show here: the sky is
// even, and a straight view past the critical angle mirrors all the same, by Fresnel's 1 there;
// the pool tests above check it.)
TEST_F(RendererTest, AnEyeUnderWaterSeesTheSkyInSnellsWindowAndTheFloorMirroredBeyond) {
    world::BlockId glow = 0;
    world::BlockRegistry reg = with_black("glow", 0.f, glow);
    world::BlockInfo info = reg.info(glow);
    info.emission = {1.f, 0.5f, 0.25f};
    ASSERT_TRUE(reg.set(glow, info));
    m_renderer->set_registry(reg);
    const world::BlockId water = test::block_id("water");
    world::World w;
    w.registry() = reg;
    test::fill_box(w, {-40, 0, -40}, {40, 1, 40}, glow);
    test::fill_box(w, {-40, 1, -40}, {40, 5, 40}, water);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s = pool_settings(1, {0.5f, 0.6f, 0.8f}, 1);
    s.width = s.height = 48;
    s.sun.irradiance = glm::vec3(0.f);
    s.eye_block = water;
    const Camera cam = Camera::look_at({0.3, 3.0, 0.2}, {0.3, 9.0, 0.2}, {0, 0, -1}, 120.f);
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "snells_window");
    const world::BlockInfo& wat = reg.info(water);
    const double n = test::index_of(wat.reflectivity), critical = std::asin(1.0 / n);
    int inside = 0, beyond = 0, off = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height);
            const double angle = std::acos(d.y), sin_air = n * std::sin(angle);
            if (std::abs(angle - critical) < glm::radians(1.5))
                continue;
            const glm::vec3 floor = test::absorbed(wat.albedo, 6.0 / d.y) * info.emission;
            glm::vec3 expected = floor;
            if (sin_air < 1.0) {
                const double f = test::fresnel(wat.reflectivity, std::sqrt(1.0 - sin_air * sin_air));
                const glm::vec3 up = s.sky * test::absorbed(wat.albedo, 2.0 / d.y) * float(n * n * (1.0 - f));
                expected = up + floor * float(f);
                ++inside;
            } else {
                ++beyond;
            }
            const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), full_output(expected));
            if (!near && off++ < 4)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "), " << glm::degrees(angle)
                              << " degrees: " << near.message();
        }
    EXPECT_EQ(off, 0) << "of " << inside << " in the window and " << beyond << " beyond";
    std::printf("%d pixels in Snell's window, %d beyond\n", inside, beyond);
    EXPECT_GT(inside, 500);
    EXPECT_GT(beyond, 500);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// Light trapped in glass: the eye inside a solid glass box [0, 10)^3 looks along (1, 1, 1), so
// every face meets the view 54.7 degrees off its normal, past glass's critical angle (41.8): the
// walk reflects at each face, never leaves, and after kMaxTransparentLayers reflections stops on
// the next face and shades it as a surface (Flat: the glass's albedo), absorbed along the whole
// path (Beer-Lambert). Each pixel is glass x glass^(path to that face), the path traced here by
// the same reflections (a direction component flips at each face), within one 8-bit step: the
// walk's bound holds, and the path's length is summed right through its bounces. Checked: the walk
// ended at total internal reflection, or the reflection begun on the face's far side (out of the
// glass), puts all 256 pixels off.
TEST_F(RendererTest, AViewTrappedInGlassStopsAfterItsLayersAbsorbedAllTheWay) {
    const world::BlockId glass = test::block_id("glass");
    world::World w;
    test::fill_box(w, {0, 0, 0}, {10, 10, 10}, glass);
    test::load_meshes(*m_renderer, test::mesh_world(w));
    RenderSettings s;
    s.width = s.height = 16;
    s.mode = ShadingMode::Flat;
    s.eye_block = glass;
    const glm::dvec3 eye(5.2, 5.3, 5.1);
    const Camera cam = Camera::look_at(eye, eye + glm::dvec3(1.0), {0, 1, 0}, 5.f);
    const RenderImage img = m_renderer->render(s, cam);
    const world::BlockInfo& g = world::BlockRegistry::default_registry().info(glass);
    const double n = test::index_of(g.reflectivity), critical_cos = std::sqrt(1.0 - 1.0 / (n * n));
    int off = 0;
    for (uint32_t y = 0; y < s.height; ++y)
        for (uint32_t x = 0; x < s.width; ++x) {
            glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height), p = eye;
            double path = 0.0;
            for (uint32_t face = 0; face <= gpu::kMaxTransparentLayers; ++face) {
                double t = 1e30;
                int k = 0;
                for (int a = 0; a < 3; ++a) {
                    const double ta = ((d[a] > 0.0 ? 10.0 : 0.0) - p[a]) / d[a];
                    if (ta < t) {
                        t = ta;
                        k = a;
                    }
                }
                path += t;
                p += d * t;
                ASSERT_LT(std::abs(d[k]), critical_cos) << "the view would leave the glass at pixel " << x << ", " << y;
                d[k] = -d[k];
            }
            const glm::vec3 expected = g.albedo * test::absorbed(g.albedo, path);
            const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), expected);
            if (!near && off++ < 3)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "), path " << path << ": " << near.message();
        }
    EXPECT_EQ(off, 0);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
