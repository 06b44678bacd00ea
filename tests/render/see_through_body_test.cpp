// The bodies of see-through blocks absorb light along the path in them (Beer-Lambert: a block's
// albedo is what one block's length passes, so d blocks of path pass albedo^d; vx_absorb in
// shaders/shared/rt_common.glsl). A see-through block against an opaque one (trace_through's
// g_inside in shaders/shared/raygen_common.glsl): the mesher writes no face between them, so a ray
// that enters the block and meets the opaque face behind it crosses one of the block's faces, not
// two; the walk knows it ended inside the block, and the rays the hit sends out start inside it.
// Also here: the raster pass's tint, the eye under water (RenderSettings::eye_block) and the
// denoiser's albedo guide as seen through the blocks.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "scene_util.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

using test::full_output;
using test::linear_of;
using test::RendererTest;

glm::vec3 albedo_of(const world::BlockRegistry& reg, world::BlockId id) { return reg.info(id).albedo; }

// The default registry with a dark see-through block (its albedo^0.5 far from its albedo, so
// half a block's path short is plain to see) and, when `bright_lamp`, the lamp ten times as bright. Its water
// and glass only tint (reflectivity 0): this file is about tints; what their surfaces mirror is
// water_surface_test.cpp's.
struct TintRegistry {
    world::BlockRegistry reg = world::BlockRegistry::default_registry();
    world::BlockId smoke = 0;
    static constexpr glm::vec3 kSmoke{0.25f, 0.49f, 0.81f};
};

TintRegistry tint_registry(bool bright_lamp = false) {
    TintRegistry t;
    world::BlockInfo info;
    info.name = "smoked glass";
    info.albedo = TintRegistry::kSmoke;
    info.opaque = false;
    const Result<world::BlockId> id = t.reg.add(info);
    EXPECT_TRUE(id);
    t.smoke = id ? *id : world::kAir;
    for (const char* name : {"water", "glass"}) {
        world::BlockInfo b = t.reg.info(test::block_id(name));
        b.reflectivity = 0.f;
        EXPECT_TRUE(t.reg.set(test::block_id(name), b));
    }
    if (bright_lamp) {
        world::BlockInfo lamp = t.reg.info(test::block_id("lamp"));
        lamp.emission *= 10.f;
        EXPECT_TRUE(t.reg.set(test::block_id("lamp"), lamp));
    }
    return t;
}

// A stone wall across `axis` at cell `wall` (17 blocks square) and `row` beside it on the side
// `side` (+1 or -1), the first block touching the wall or, when `gap`, one cell of air away.
world::World row_on_wall(int axis, int side, int wall, const std::vector<world::BlockId>& row, bool gap) {
    world::World w;
    glm::ivec3 lo(-8), hi(9);
    lo[axis] = wall;
    hi[axis] = wall + 1;
    test::fill_box(w, {lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}, test::block_id("stone"));
    for (size_t i = 0; i < row.size(); ++i) {
        glm::ivec3 p(0);
        p[axis] = wall + side * (int(i) + 1 + (gap ? 1 : 0));
        w.set_block({p.x, p.y, p.z}, row[i]);
    }
    return w;
}

// Looking along -side * axis at the wall's face on `side`, through the row, from 10 blocks out.
Camera looking_at_wall(int axis, int side, int wall) {
    glm::dvec3 eye(0.5), target(0.5);
    const double face = side > 0 ? wall + 1 : wall;
    eye[axis] = face + side * 10.0;
    target[axis] = face;
    const glm::vec3 up = axis == 1 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    return Camera::look_at(eye, target, up, 20.f);
}

// A stone floor (x, z in [-16, 16), y in [0, 1)) and a pool of the smoked block filling [lo, hi).
world::World floor_with_pool(const TintRegistry& t, world::BlockPos lo, world::BlockPos hi) {
    world::World w;
    w.registry() = t.reg;
    test::fill_box(w, {-16, 0, -16}, {16, 1, 16}, test::block_id("stone"));
    test::fill_box(w, lo, hi, t.smoke);
    return w;
}

// test::daylight without haze. `sky`: lit by the sky alone (the sun below the horizon: exact
// where every sky ray escapes); else by nothing but emissive blocks.
RenderSettings lit_by(bool sky, uint32_t samples) {
    RenderSettings s = test::daylight(samples);
    s.haze.enabled = false;
    s.sun.direction = {0.f, -1.f, 0.3f};
    if (!sky) {
        s.sun.irradiance = glm::vec3(0.f);
        s.sky_light = 0.f;
    }
    return s;
}

// Flat mode: the wall seen through a row of see-through blocks touching it is tinted by every
// block's albedo once (one block straight through), as with an air gap: along each axis, from both
// sides (the walk tells entering from leaving by the face's normal), a row of one block or two
// touching each other (glass into water: the probe's partner is the block the ray ends inside), the
// wall and the row in neighbouring chunks or in one; ray traced and raster (its transparent pass
// tints where the view enters a block, raster.frag). Checked: with the hidden face ignored (the
// stop-51 model), every touching case was one sqrt(albedo) short; raster's sqrt per face of both
// sides was too.
TEST_F(RendererTest, AWallBehindASeeThroughBlockTintsByTheWholeBlock) {
    const TintRegistry t = tint_registry();
    m_renderer->set_registry(t.reg);
    const world::BlockId glass = test::block_id("glass"), water = test::block_id("water");
    const std::vector<std::vector<world::BlockId>> rows = {
        {t.smoke}, {water}, {glass, water}, {water, t.smoke}};
    const glm::vec3 stone = albedo_of(t.reg, test::block_id("stone"));
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    const struct {
        int side, wall;
    } places[] = {{+1, 0}, {-1, 0}, {+1, 31}, {-1, 32}};
    for (const auto& place : places)
        for (int axis = 0; axis < 3; ++axis)
            for (size_t r = 0; r < rows.size(); ++r)
                for (bool gap : {false, true}) {
                    m_renderer->clear_chunks();
                    world::World w = row_on_wall(axis, place.side, place.wall, rows[r], gap);
                    w.registry() = t.reg;
                    test::load_meshes(*m_renderer, test::mesh_world(w));
                    const Camera cam = looking_at_wall(axis, place.side, place.wall);
                    s.pipeline = PipelineKind::RayTraced;
                    const RenderImage img = m_renderer->render(s, cam);
                    s.pipeline = PipelineKind::Raster;
                    const RenderImage raster = m_renderer->render(s, cam);
                    glm::vec3 expected = stone;
                    for (world::BlockId b : rows[r])
                        expected *= albedo_of(t.reg, b);
                    const std::string where = "wall " + std::to_string(place.wall) + ", side " +
                                              std::to_string(place.side) + ", axis " + std::to_string(axis) +
                                              ", row " + std::to_string(r) + (gap ? ", a gap" : ", touching");
                    EXPECT_TRUE(test::rgb_near(img.at(16, 16), expected)) << where;
                    // Raster: each block's entry face blends once into an 8-bit target.
                    EXPECT_TRUE(test::rgb_near(raster.at(16, 16), expected, int(rows[r].size()) + 1))
                        << where << ", raster";
                }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The pixels of `img` more than `tolerance` 8-bit steps from expected(x, y); the first few named.
template <class Expected>
int pixels_off(const RenderImage& img, Expected expected, int tolerance, const char* what) {
    int off = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const ::testing::AssertionResult near = test::rgb_near(img.at(x, y), expected(x, y), tolerance);
            if (!near && off++ < 3)
                ADD_FAILURE() << what << ", pixel (" << x << ", " << y << "): " << near.message();
        }
    return off;
}

// A floor pixel under a pool of the smoked block [lo, hi) (floor_with_pool), seen from `cam` and
// lit by the sky alone: the floor's light is albedo x sky x what the pool passes of the sky
// (test::sky_through_box: each sky ray's path in the pool to its side), seen down the view's path
// in the pool from the eye at `eye_y` (inside the pool or above it) to the floor.
glm::vec3 pool_floor_pixel(const Camera& cam, const RenderSettings& s, uint32_t x, uint32_t y, glm::dvec3 lo,
                           glm::dvec3 hi, double eye_y) {
    const TintRegistry t;
    const glm::dvec3 eye = test::eye_of(cam);
    const glm::dvec3 d = test::primary_dir(cam, x, y, s.width, s.height);
    const glm::dvec3 floor = eye + d * ((1.0 - eye.y) / d.y);
    const glm::vec3 stone = world::BlockRegistry::default_registry().info(test::block_id("stone")).albedo;
    const glm::vec3 sky = test::sky_through_box(floor, lo, hi, TintRegistry::kSmoke, 100);
    const double view_path = (std::min(eye_y, hi.y) - 1.0) / -d.y;
    return full_output(stone * s.sky * sky * test::absorbed(TintRegistry::kSmoke, view_path));
}

// Full mode under an open sky (the sun below the horizon, no area light): a pool of the smoked
// block one deep on a stone floor, seen from straight above. Every sky ray from the floor leaves
// through one of the pool's faces and the view ray enters through one, and the floor's faces
// under the pool are not meshed: the floor is albedo x sky, times what the pool passes on the
// light's way up (each ray its path to the pool's side: a^(1 / cos) through the top, less through
// a side) and on the view's way down (a^(1 / cos_eye)); 64 sky rays a pixel, within two 8-bit
// steps. Checked: with the sky rays from the floor begun outside the block, every pixel is off,
// and with each segment's path taken as one block at most (about the model before Beer-Lambert:
// one albedo per block crossed), every pixel too.
TEST_F(RendererTest, APoolsFloorIsTintedByTheWholeBlockOnTheLightsWayInAndOut) {
    const TintRegistry t = tint_registry();
    m_renderer->set_registry(t.reg);
    const glm::dvec3 lo(-3, 1, -3), hi(4, 2, 4);
    test::load_meshes(*m_renderer, test::mesh_world(floor_with_pool(t, {-3, 1, -3}, {4, 2, 4})));
    const RenderSettings s = lit_by(true, 64);
    // The camera 4 blocks above the floor sees |x|, |z| < 2.4 of it (a 60 degree view): all under
    // the pool, whose edges are 2.5 blocks out at least.
    const Camera cam = Camera::look_at({0.3, 5.0, 0.2}, {0.3, 0.0, 0.2}, {0, 0, -1});
    const RenderImage img = m_renderer->render(s, cam);
    test::maybe_save(img, "pool_floor");
    const auto expected = [&](uint32_t x, uint32_t y) { return pool_floor_pixel(cam, s, x, y, lo, hi, 5.0); };
    EXPECT_EQ(pixels_off(img, expected, 2, "pool floor"), 0);
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// A closed stone room (inner air x, z in [-4, 5), y in [-4, 0)) with a lamp in its ceiling at
// (0, 0, 0), at the top of a shaft two blocks deep and one wide walled with stone: only the lamp's
// face downwards lights the room, through the shaft. The blocks `under` fill the shaft from the
// top, so all the lamp's light crosses their bodies. The camera below the shaft looks down at the
// floor.
world::World lamp_room(const TintRegistry& t, const std::vector<world::BlockId>& under) {
    world::World w;
    w.registry() = t.reg;
    test::fill_box(w, {-5, -5, -5}, {6, 1, 6}, test::block_id("stone"));
    test::fill_box(w, {-4, -4, -4}, {5, 0, 5}, world::kAir);
    w.set_block({0, 0, 0}, test::block_id("lamp"));
    for (int64_t y : {-1, -2})
        for (world::BlockPos side : {world::BlockPos{1, y, 0}, {-1, y, 0}, {0, y, 1}, {0, y, -1}})
            w.set_block(side, test::block_id("stone"));
    for (size_t i = 0; i < under.size(); ++i)
        w.set_block({0, -1 - int64_t(i), 0}, under[i]);
    return w;
}

// What the blocks under the lamp pass of its light on lamp_room's floor, over the image from
// `cam`: the lamp's light at each pixel's floor point without them (the lamp's face y = 0, x, z in
// [0, 1), as n x n points; a ray to it through the shaft's 1 x 1 opening at y = -2) and with them
// (each ray's slant through the blocks: `tint`^(1 / cos), every block one deep), summed over the
// pixels; with over without.
glm::dvec3 shaft_ratio(const Camera& cam, uint32_t w, uint32_t h, glm::vec3 tint, int n = 48) {
    const glm::dvec3 eye = test::eye_of(cam);
    glm::dvec3 open(0.0), covered(0.0);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, w, h);
            const glm::dvec3 p = eye + d * ((-4.0 - eye.y) / d.y);
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const glm::dvec3 q((i + 0.5) / n, 0.0, (j + 0.5) / n), l = q - p;
                    const glm::dvec3 at_opening = p + l * ((-2.0 - p.y) / l.y);
                    if (at_opening.x < 0.0 || at_opening.x > 1.0 || at_opening.z < 0.0 || at_opening.z > 1.0)
                        continue;
                    const double r2 = glm::dot(l, l), cos_y = l.y / std::sqrt(r2); // Both faces' cosine.
                    const double e = cos_y * cos_y / r2;
                    open += glm::dvec3(e);
                    covered += e * glm::dvec3(test::absorbed(tint, 1.0 / cos_y));
                }
        }
    return covered / open;
}

// The floor of lamp_room lit through the block is the floor lit without it, times what the block
// passes on each ray's slant (shaft_ratio), channel by channel: where the lamp's faces are sampled
// (a shadow ray that ends on the lamp's face inside the block: trace_shadow) and where sky rays find
// the lamp (a walk that ends inside it). With glass under the smoked block, the shadow ray meets
// the glass's face and the smoked block's on one plane, in any order and maybe a rounding apart: it
// ends in the smoked block all the same (shadow.rahit), and both blocks absorb. Within 3% (the two
// renders' samples differ in what they pass). Checked: one face short, the ratio is sqrt(albedo)
// (0.5 where 0.25 is wanted) in both ways; with the glass's face kept on the plane's tie, 0.42
// where 0.21 is wanted; without the any-hit's optical depth (shadow.rahit), (0.00, 0.05, 0.42)
// where (0.24, 0.48, 0.80) is wanted.
TEST_F(RendererTest, ALampBehindASeeThroughBlockShinesThroughTheWholeBlock) {
    const TintRegistry t = tint_registry(true);
    m_renderer->set_registry(t.reg);
    RenderSettings s = lit_by(false, 16);
    s.sky_access = false;
    const Camera cam = Camera::look_at({0.5, -2.5, 0.5}, {0.5, -4.0, 0.5}, {0, 0, -1}, 90.f);
    const world::BlockId glass = test::block_id("glass");
    const struct {
        bool glazed, sampled;
    } cases[] = {{false, true}, {false, false}, {true, true}, {true, false}};
    for (const auto [glazed, sampled] : cases) {
        s.emitter_sampling = sampled;
        const glm::dvec3 expected = shaft_ratio(
            cam, s.width, s.height, TintRegistry::kSmoke * (glazed ? albedo_of(t.reg, glass) : glm::vec3(1.f)));
        const std::vector<world::BlockId> under = glazed ? std::vector{t.smoke, glass} : std::vector{t.smoke};
        RenderImage img[2];
        for (bool cover : {false, true}) {
            m_renderer->clear_chunks();
            const world::World w = lamp_room(t, cover ? under : std::vector<world::BlockId>{});
            test::load_meshes(*m_renderer, test::mesh_world(w));
            img[cover] = m_renderer->render(s, cam);
        }
        test::maybe_save(img[1], sampled ? "lamp_behind_smoke_sampled" : "lamp_behind_smoke_rays");
        glm::dvec3 open(0.0), covered(0.0);
        for (size_t i = 0; i < img[0].rgba.size(); i += 4)
            for (int c = 0; c < 3; ++c) {
                open[c] += linear_of(img[0].rgba[i + c]);
                covered[c] += linear_of(img[1].rgba[i + c]);
            }
        const glm::dvec3 ratio = covered / open;
        std::printf("%s: mean linear open (%.4f %.4f %.4f), through the block / open (%.4f %.4f %.4f), "
                    "expected (%.4f %.4f %.4f)\n",
                    sampled ? "faces sampled" : "sky rays", open.r / 1024, open.g / 1024, open.b / 1024,
                    ratio.r, ratio.g, ratio.b, expected.r, expected.g, expected.b);
        EXPECT_GT(open.r / 1024, 0.02) << "the room is too dark to tell";
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(ratio[c], expected[c], 0.03 * expected[c])
                << (sampled ? "faces sampled" : "sky rays") << (glazed ? ", glass under" : "") << ", channel "
                << c;
    }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// What the pool of ALampInAPool... passes of the lamp's light on the floor, over the image from
// `cam` but the lamp's own pixels: at each pixel's floor point the light of the lamp's four side
// faces (x, z in [0, 1], y in [1, 2]; n x n points each) without the pool and with it (each ray
// a^(its path in the pool)), the latter also down the view's path in the pool; summed, with over
// without.
glm::dvec3 pool_lamp_ratio(const Camera& cam, uint32_t w, uint32_t h, glm::vec3 a, int n = 24) {
    const glm::dvec3 eye = test::eye_of(cam), lo(-4, 1, -4), hi(5, 3, 5);
    glm::dvec3 open(0.0), covered(0.0);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            if (x >= 11 && x <= 21 && y >= 11 && y <= 21)
                continue;
            const glm::dvec3 d = test::primary_dir(cam, x, y, w, h);
            const glm::dvec3 p = eye + d * ((1.0 - eye.y) / d.y);
            const glm::dvec3 view(test::absorbed(a, test::path_in_box(eye, p, lo, hi)));
            for (int axis : {0, 2})
                for (double side : {0.0, 1.0}) {
                    const double out = side > 0.0 ? p[axis] - 1.0 : -p[axis]; // p in front of the face.
                    if (out <= 0.0)
                        continue;
                    for (int i = 0; i < n; ++i)
                        for (int j = 0; j < n; ++j) {
                            glm::dvec3 q(0.0, 1.0 + (j + 0.5) / n, 0.0);
                            q[axis] = side;
                            q[2 - axis] = (i + 0.5) / n;
                            const glm::dvec3 l = q - p;
                            const double r2 = glm::dot(l, l);
                            const double e = l.y * out / (r2 * r2); // cos_p cos_q / r^2, both over r.
                            open += glm::dvec3(e);
                            covered += e * view * glm::dvec3(test::absorbed(a, test::path_in_box(p, q, lo, hi)));
                        }
                }
        }
    return covered / open;
}

// A lamp standing on the floor of a pool two deep (the pool fills x, z in [-4, 5), y in [1, 3)
// but the lamp's cell (0, 1, 0)), no other light, seen from above. The lamp's faces lie against
// the pool, whose faces there are not meshed, as are the floor's: the light goes from the lamp to
// the floor inside the pool, crossing no face, and the view ray enters through the pool's top. So
// each floor pixel is the floor without the pool times what the pool passes on the light's paths
// and the view's (pool_lamp_ratio), where a shadow ray samples the lamp's faces (it crossed no
// face: it ends in the block it began in) and where a sky ray finds the lamp (a walk begun inside
// the pool). Checked: with the walks begun outside any block, the sky rays' ratio is (0.037, 0.18,
// 0.59) where (0.0021, 0.036, 0.35) is wanted, and so is the faces' with the shadow rays' start
// ignored (trace_shadow's `start`). The pool is exposed
// kPoolBrighter EV brighter per channel (a render for red, one for the rest): its red, 0.2% of the
// open floor's, and its green, 4%, would otherwise lie in the darkest bytes, whose rounding alone
// moved the ratio by 4% on the NVIDIA driver. 128 samples a pixel: few sky rays find the lamp, and
// its red comes from the shortest paths (at 16, 7% under).
constexpr float kPoolBrighter[2] = {8.f, 3.f}; // Red; green and blue.
TEST_F(RendererTest, ALampInAPoolLightsItsFloorThroughThePoolAlone) {
    const TintRegistry t = tint_registry(true);
    m_renderer->set_registry(t.reg);
    RenderSettings s = lit_by(false, 128);
    const Camera cam = Camera::look_at({0.5, 6.0, 0.5}, {0.5, 0.0, 0.5}, {0, 0, -1}, 90.f);
    const glm::dvec3 expected = pool_lamp_ratio(cam, s.width, s.height, TintRegistry::kSmoke);
    for (bool sampled : {true, false}) {
        s.emitter_sampling = sampled;
        RenderImage img[3]; // Open; the pool for red; for green and blue.
        for (int pool : {0, 1, 2}) {
            const world::BlockPos hi = pool ? world::BlockPos{5, 3, 5} : world::BlockPos{-4, 1, -4};
            world::World w = floor_with_pool(t, {-4, 1, -4}, hi);
            w.set_block({0, 1, 0}, test::block_id("lamp"));
            m_renderer->clear_chunks();
            test::load_meshes(*m_renderer, test::mesh_world(w));
            RenderSettings pool_s = s;
            pool_s.exposure.ev100 -= pool > 0 ? kPoolBrighter[pool - 1] : 0.f;
            img[pool] = m_renderer->render(pool_s, cam);
        }
        test::maybe_save(img[2], sampled ? "lamp_in_pool_sampled" : "lamp_in_pool_rays");
        // The floor around the lamp, not the lamp's own pixels (its top face: rows and columns
        // 12..20 at most, seen 5 blocks away over a 90 degree view) nor beyond the pool (6 blocks
        // down the floor is 4.5 blocks out at the image's edge).
        glm::dvec3 open(0.0), covered(0.0);
        for (uint32_t y = 0; y < 32; ++y)
            for (uint32_t x = 0; x < 32; ++x) {
                if (x >= 11 && x <= 21 && y >= 11 && y <= 21)
                    continue;
                for (int c = 0; c < 3; ++c) {
                    open[c] += linear_of(img[0].at(x, y)[c]);
                    const int k = c == 0 ? 0 : 1; // Red's render, or green's and blue's.
                    covered[c] += linear_of(img[1 + k].at(x, y)[c], s.exposure.ev100 - kPoolBrighter[k]);
                }
            }
        const glm::dvec3 ratio = covered / open;
        const char* how = sampled ? "faces sampled" : "sky rays";
        std::printf("%s: pool / open (%.4f %.4f %.4f), expected (%.4f %.4f %.4f)\n", how, ratio.r, ratio.g,
                    ratio.b, expected.r, expected.g, expected.b);
        EXPECT_GT(open.g / 800, 0.02) << "the floor is too dark to tell";
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(ratio[c], expected[c], 0.04 * expected[c]) << how << ", channel " << c;
    }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The eye under water (RenderSettings::eye_block): a pool of the smoked block three deep over a
// stone floor, the camera inside it, 2.5 blocks over the floor and 0.5 under the surface. Flat:
// the floor straight down is stone x albedo^2.5, the sky straight up sky x albedo^0.5. Full mode
// under the open sky: each floor pixel as pool_floor_pixel says (the view's path in the pool from
// the eye), 64 sky rays a pixel. An eye in air or in an opaque block draws as none given.
// Checked: without the eye's block the floor and the sky are untinted in Flat (115 where 4 is wanted,
// in red), and every Full pixel is off.
TEST_F(RendererTest, AnEyeUnderWaterSeesThroughTheWaterItIsIn) {
    const TintRegistry t = tint_registry();
    m_renderer->set_registry(t.reg);
    const glm::dvec3 lo(-6, 1, -6), hi(7, 4, 7);
    test::load_meshes(*m_renderer, test::mesh_world(floor_with_pool(t, {-6, 1, -6}, {7, 4, 7})));
    const glm::vec3 stone = albedo_of(t.reg, test::block_id("stone")), smoke = TintRegistry::kSmoke;
    RenderSettings s = lit_by(true, 64);
    s.mode = ShadingMode::Flat;
    s.eye_block = t.smoke;
    const Camera down = Camera::look_at({0.3, 3.5, 0.2}, {0.3, 0.0, 0.2}, {0, 0, -1});
    const Camera up = Camera::look_at({0.3, 3.5, 0.2}, {0.3, 9.0, 0.2}, {0, 0, -1});
    // Pixel (16, 16)'s ray is a half pixel off the axis: its slant (1.0007) is below a rounding.
    EXPECT_TRUE(test::rgb_near(m_renderer->render(s, down).at(16, 16), stone * test::absorbed(smoke, 2.5)));
    EXPECT_TRUE(test::rgb_near(m_renderer->render(s, up).at(16, 16), s.sky * test::absorbed(smoke, 0.5)));
    s.mode = ShadingMode::Full;
    const RenderImage img = m_renderer->render(s, down);
    test::maybe_save(img, "eye_under_water");
    const auto expected = [&](uint32_t x, uint32_t y) { return pool_floor_pixel(down, s, x, y, lo, hi, 3.5); };
    EXPECT_EQ(pixels_off(img, expected, 2, "eye under water"), 0);
    s.mode = ShadingMode::Flat;
    s.eye_block = world::kAir;
    const RenderImage none = m_renderer->render(s, down);
    for (world::BlockId b : {test::block_id("stone")}) {
        s.eye_block = b;
        EXPECT_EQ(test::differing_bytes(m_renderer->render(s, down), none), 0);
    }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

// The denoiser's albedo guide (render/gbuffer.h albedo) is the albedo as seen: through a pool of
// the smoked block two deep its floor's guide is stone x albedo^(2 / cos_eye), beside the pool plain
// stone; from an eye inside the pool 1.5 over the floor, stone x albedo^1.5; in Flat mode too. A
// tint's edge is then an albedo edge, which the filter keeps (render_report.md: a checker of water
// on grass, 4 spp denoised, RMSE 0.0082 -> 0.0047). Checked: with the plain albedo, the pool's
// pixels fail.
TEST_F(RendererTest, TheAlbedoGuideIsTheAlbedoAsSeenThroughSeeThroughBlocks) {
    const TintRegistry t = tint_registry();
    m_renderer->set_registry(t.reg);
    test::load_meshes(*m_renderer, test::mesh_world(floor_with_pool(t, {-16, 1, -16}, {0, 3, 16}))); // x < 0
    const glm::vec3 stone = albedo_of(t.reg, test::block_id("stone"));
    RenderSettings s = lit_by(true, 2);
    // Straight down from above the pool's surface, x to the right: the left half over the pool.
    const Camera above = Camera::look_at({0.0, 6.0, 0.3}, {0.0, 0.0, 0.3}, {0, 0, -1});
    const Camera inside = Camera::look_at({-6.0, 2.5, 0.3}, {-6.0, 0.0, 0.3}, {0, 0, -1});
    const auto seen = [&](const Camera& cam, uint32_t x, uint32_t y, double depth) {
        return stone * test::absorbed(TintRegistry::kSmoke, depth / -test::primary_dir(cam, x, y, 32, 32).y);
    };
    // How far the guide at (x, y) is from `expected` (an 8-bit step: 0.004).
    const auto off = [](const GBufferImage& g, uint32_t x, uint32_t y, glm::vec3 expected) {
        return glm::length(glm::vec3(g.at(g.albedo, x, y)) - expected);
    };
    for (ShadingMode mode : {ShadingMode::Full, ShadingMode::Flat}) {
        s.mode = mode;
        const char* name = mode == ShadingMode::Full ? "Full" : "Flat";
        GBufferImage g;
        s.eye_block = world::kAir;
        m_renderer->render(s, above, &g);
        EXPECT_LT(off(g, 4, 16, seen(above, 4, 16, 2.0)), 2.f / 255) << name << ", over the pool";
        EXPECT_LT(off(g, 28, 16, stone), 2.f / 255) << name << ", beside it";
        s.eye_block = t.smoke;
        m_renderer->render(s, inside, &g);
        EXPECT_LT(off(g, 16, 16, seen(inside, 16, 16, 1.5)), 2.f / 255) << name << ", the eye in it";
    }
    EXPECT_EQ(m_renderer->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
