// Where two different see-through blocks touch (glass against water), light crossing from one into
// the other loses the share their interface mirrors, once: Fresnel's at the relative index
// n_high / n_low (vx_interface_pass in shaders/shared/rt_common.glsl; glass against water 0.4%
// head-on), not each block's face against air (4% and 2%). Each block has its own face on the
// plane. Shadow rays meet both in their any-hit and pair them there (shaders/shadow.rahit); the
// sky rays' walk finds the other by its probe (coincident_partner in
// shaders/shared/raygen_common.glsl). Shadow and sky rays go straight (unbent), so the interface
// takes the ray's angle on its lower index's side, as a face against air takes it on the air's.
#include <cmath>
#include <cstdio>
#include <string>

#include "scene_util.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::full_output;
using test::RendererTest;

constexpr double kPi = 3.14159265358979;

// The share an interface between media of indices n_a and n_b mirrors, met at cosine cos_i on
// the lower index's side.
double interface_fresnel(double n_a, double n_b, double cos_i) {
    return test::fresnel_eta(std::max(n_a, n_b) / std::min(n_a, n_b), cos_i);
}

// A slab x, z in [-8, 8): block `lower` at y in [plane - 1, plane) and `upper` at [plane, plane + 1),
// touching on the plane y = `plane`; a stone floor, x, z in [-16, 16), with its top 2 blocks under
// the slab. With `pair`, also glass touching water in a corner away from the slab's shadow, so
// that the frame traces the variant that pairs faces (render/touching_pairs.h) whatever the slab.
world::World slab(world::BlockRegistry reg, world::BlockId lower, world::BlockId upper, int64_t plane,
                  bool pair = false) {
    world::World w(std::move(reg));
    test::fill_box(w, {-16, plane - 4, -16}, {16, plane - 3, 16}, test::block_id("stone"));
    test::fill_box(w, {-8, plane - 1, -8}, {8, plane, 8}, lower);
    test::fill_box(w, {-8, plane, -8}, {8, plane + 1, 8}, upper);
    if (pair) {
        w.set_block({-14, plane - 3, -14}, test::block_id("glass"));
        w.set_block({-13, plane - 3, -14}, test::block_id("water"));
    }
    return w;
}

// The eye 1.5 blocks over the floor, under the slab, looking straight down (90 degrees): every
// pixel sees floor that the slab shades.
Camera under_slab(int64_t plane) {
    const double y = double(plane) - 1.5;
    return Camera::look_at({0.3, y, 0.3}, {0.3, y - 1.0, 0.3}, {0, 0, -1}, 90.f);
}

// Full mode lit by the sun alone (test::sun_alone), a nearly sharp disc.
RenderSettings sun_only(glm::vec3 sun) {
    RenderSettings s = test::sun_alone(sun);
    s.sun.angular_radius_degrees = 0.05f;
    return s;
}

// The sun 48 degrees up shades the floor through glass on water and water on glass, their plane
// inside a chunk (y = 5) and on a chunk border (y = 32: each block's face in its own chunk's
// mesh), and through a crystal of index 3 touching glass and water; last through glass alone, its
// top on the border (marked, as every see-through face there, with no face to pair: it passes
// its own share after the trace, trace_shadow in raygen.rgen). Each floor pixel is stone
// E l_y / pi times what the slab passes along the straight ray: (1 - F) at its bottom face
// against air, at the interface and at its top face against air, and each block's
// albedo^(1 / l_y). Checked, of 2,304 pixels each time: with both faces of the pair passing their
// share against air (the code before), all, in each of the six touching slabs; with the
// interface passing all light, all, in the crystal's two (glass against water's 0.5% is under a
// step of 8 bits here); with unpaired faces passing all light, all, glass alone.
TEST_F(RendererTest, GlassAndWaterTouchingShadeTheFloorByOneInterface) {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    world::BlockInfo info;
    info.name = "crystal";
    info.albedo = {0.9f, 0.85f, 0.8f};
    info.reflectivity = 0.25f; // Index 3: against glass it mirrors 11% head-on.
    info.opaque = false;
    const world::BlockId crystal = reg.add(info).value();
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.5, 1.0, 0.3));
    const RenderSettings s = sun_only(glm::vec3(l));
    struct Case {
        world::BlockId lower, upper;
        int64_t plane;
    };
    const Case cases[] = {{glass, water, 5},  {water, glass, 5},    {glass, water, 32},
                          {water, glass, 32}, {crystal, glass, 5}, {water, crystal, 32},
                          {glass, world::kAir, 32}};
    for (const Case c : cases) {
        m_renderer = test::make_renderer();
        ASSERT_NE(m_renderer, nullptr);
        m_renderer->set_registry(reg);
        test::load_meshes(*m_renderer, test::mesh_world(slab(reg, c.lower, c.upper, c.plane, true)));
        const Camera cam = under_slab(c.plane);
        const RenderImage img = m_renderer->render(s, cam);
        const std::string name = "interface_" + reg.info(c.lower).name + "_under_" + reg.info(c.upper).name;
        test::maybe_save(img, name.c_str());
        world::BlockInfo lo = reg.info(c.lower), hi = reg.info(c.upper);
        if (c.upper == world::kAir)
            hi.albedo = glm::vec3(1.f);
        const double n_lo = test::index_of(lo.reflectivity), n_hi = test::index_of(hi.reflectivity);
        const double f_lo = test::fresnel(lo.reflectivity, l.y), f_hi = test::fresnel(hi.reflectivity, l.y);
        const double pass = (1.0 - f_lo) * (1.0 - interface_fresnel(n_lo, n_hi, l.y)) * (1.0 - f_hi);
        const glm::vec3 through = test::absorbed(lo.albedo, 1.0 / l.y) * test::absorbed(hi.albedo, 1.0 / l.y);
        const glm::vec3 stone = reg.info(test::block_id("stone")).albedo;
        const glm::vec3 expected = stone * through * s.sun.irradiance * float(pass * l.y / kPi);
        int off = 0;
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const glm::u8vec4 px = img.at(x, y);
                const ::testing::AssertionResult near = test::rgb_near(px, full_output(expected), 1);
                if (!near && off++ < 4)
                    ADD_FAILURE() << "plane " << c.plane << ", pixel (" << x << ", " << y << "): "
                                  << near.message();
            }
        EXPECT_EQ(off, 0) << "of " << s.width * s.height << " floor pixels, plane y = " << c.plane << ", "
                          << name;
        EXPECT_EQ(m_renderer->validation_errors(), 0u);
    }
}

// Two see-through blocks of one index (a quarter of the light mirrored head-on against air) and
// one albedo, touching, pass light as one block twice as thick: their interface mirrors nothing.
// The floor under a slab of the two, lit by the sun (shadow rays) and the sky (the primary hit's
// sky rays: walks), draws as under a slab of one of them. Checked, of 2,304 pixels: with both
// faces of the pair passing their share against air in the shadow rays' any-hit, all with the sun
// on (the sun off: none, as no shadow ray is traced); in the sky rays' walk, all both times.
TEST_F(RendererTest, TouchingBlocksOfOneIndexPassLightAsOneBlock) {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    world::BlockInfo info;
    info.albedo = {0.9f, 0.8f, 0.7f};
    info.reflectivity = 0.25f;
    info.opaque = false;
    info.name = "crystal a";
    const world::BlockId a = reg.add(info).value();
    info.name = "crystal b";
    const world::BlockId b = reg.add(info).value();
    m_renderer->set_registry(reg);
    RenderSettings s = sun_only(glm::vec3(glm::normalize(glm::dvec3(0.5, 1.0, 0.3))));
    s.sky_light = 1.f;
    const Camera cam = under_slab(5);
    for (const float sun : {1.f, 0.f}) {
        s.sun.irradiance = sun * RenderSettings{}.sun.irradiance;
        test::load_meshes(*m_renderer, test::mesh_world(slab(reg, 0, 0, 5)));
        const RenderImage open = m_renderer->render(s, cam);
        test::load_meshes(*m_renderer, test::mesh_world(slab(reg, a, b, 5)));
        const RenderImage two = m_renderer->render(s, cam);
        test::load_meshes(*m_renderer, test::mesh_world(slab(reg, a, a, 5)));
        const RenderImage one = m_renderer->render(s, cam);
        test::maybe_save(two, sun > 0.f ? "interface_one_index_two" : "interface_one_index_two_sky");
        test::maybe_save(one, sun > 0.f ? "interface_one_index_one" : "interface_one_index_one_sky");
        // The slab shades: the floor under it is darker than in the open, and not black.
        EXPECT_LT(test::mean_byte(one), test::mean_byte(open) - 10.0) << "sun " << sun;
        EXPECT_GT(test::mean_byte(one), 64.0 + 10.0) << "sun " << sun; // Alpha alone: 63.75.
        int off = 0;
        for (uint32_t y = 0; y < s.height; ++y)
            for (uint32_t x = 0; x < s.width; ++x) {
                const glm::u8vec4 p = one.at(x, y);
                const ::testing::AssertionResult near = test::rgb_near(two.at(x, y), glm::vec3(p) / 255.f, 1);
                if (!near && off++ < 4)
                    ADD_FAILURE() << "sun " << sun << ", pixel (" << x << ", " << y << "): "
                                  << near.message();
            }
        EXPECT_EQ(off, 0) << "of " << s.width * s.height << " floor pixels, sun " << sun;
    }
}

} // namespace
} // namespace vx::render
