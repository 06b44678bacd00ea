// The default picture through the facade (issue 19): exposure (EV100, a physical camera) and the
// filmic tone curve (shaders/shared/tonemap.h) put ground of albedo 0.18 under the default
// lights at photographic mid-grey, keep grass, sand and snow apart and unclipped, and auto
// exposure lifts a dark cave-like view to mid-grey. Lavapipe, validation on; label vulkan.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_test_util.h"

namespace {

using vx::test::settle;

// Flat ground, blocks y = 0 (top faces at y = 1), in four quadrants around x = z = 0:
// x < 0, z < 0 grey (albedo 0.18); x >= 0, z < 0 grass; x < 0, z >= 0 sand; x >= 0, z >= 0 snow.
class QuadrantGround final : public vx::Generator {
public:
    QuadrantGround(vx::BlockId grey, vx::BlockId grass, vx::BlockId sand, vx::BlockId snow)
        : m_ids{grey, grass, sand, snow} {}
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int z = 0; z < 32; ++z)
            for (int x = 0; x < 32; ++x) {
                const vx::BlockPos p = o + vx::BlockPos(x, 0, z);
                blocks[vx::chunk_index(x, 0, z)] = m_ids[(p.x >= 0 ? 1 : 0) + (p.z >= 0 ? 2 : 0)];
            }
    }
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        if (c.y == 0)
            return std::nullopt;
        return vx::kAir;
    }

private:
    vx::BlockId m_ids[4];
};

struct Fixture {
    std::unique_ptr<vx::Engine> engine;
    std::string error;
};

// An engine over QuadrantGround (the default blocks plus "grey"; all_grey: grey in every
// quadrant), 32x32 headless, the eye at (0, 7.5, 0): 6.5 blocks above the ground, looking
// straight down (image right = +x, image up = -z), so each quadrant fills a quarter of the image.
Fixture make_engine(bool all_grey = false) {
    std::vector<vx::BlockType> blocks = vx::default_blocks();
    blocks.push_back({"grey", glm::vec3(0.18f)});
    auto id = [&](const char* name) {
        for (size_t i = 0; i < blocks.size(); ++i)
            if (blocks[i].name == name)
                return vx::BlockId(i + 1);
        return vx::kAir;
    };
    vx::EngineCreateInfo info;
    const vx::BlockId grey = id("grey");
    info.world = all_grey ? vx::WorldSource::custom(std::make_shared<QuadrantGround>(grey, grey, grey, grey))
                          : vx::WorldSource::custom(
                                std::make_shared<QuadrantGround>(grey, id("grass"), id("sand"), id("snow")));
    info.blocks = blocks;
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    info.render.target = vx::RenderTarget::headless(32, 32);
    info.render.device = vx::test::test_device();
    info.render.validation = true;
    auto engine = vx::Engine::create(info);
    if (!engine)
        return {nullptr, engine.error()};
    vx::Viewer v;
    v.block = {0, 7, 0};
    v.offset = {0.0, 0.5, 0.0};
    v.forward = {0, -1, 0};
    v.up = {0, 0, -1};
    EXPECT_TRUE((*engine)->set_viewer(v));
    EXPECT_TRUE(settle(**engine));
    return {std::move(*engine), ""};
}

// Pixel centres of the quadrants: (8, 8) grey, (24, 8) grass, (8, 24) sand, (24, 24) snow,
// each about 1.6 blocks from the quadrant borders.
glm::ivec3 rgb(const vx::Image& img, uint32_t x, uint32_t y) { return glm::ivec3(glm::u8vec3(img.at(x, y))); }

double distance(glm::ivec3 a, glm::ivec3 b) { return glm::length(glm::dvec3(a - b)); }

// The expected bytes, from the default lights (vx.h): the sun (0.35, 1, 0.2) at cos 0.9275 to
// the ground gives irradiance (2.782, 2.690, 2.504), / pi = (0.886, 0.856, 0.797); the open
// sky adds its radiance (0.55, 0.7, 0.95) (cosine-weighted sky rays: the 1/pi cancels); the
// 48 x 48 area light of radiance 20, 126 blocks above and offset (-16, -36) from the eye, adds
// 2.33 irradiance, / pi = 0.742. Sum (2.178, 2.299, 2.490) per unit albedo. EV100 14.7 scales
// by 10^4 / (1.2 * 2^14.7) = 0.3131 (tonemap.h), then the ACES fit and sRGB:
//   grey  0.18               radiance (0.392, 0.414, 0.448) -> bytes (113, 117, 123)
//   grass (0.30, 0.55, 0.20)          (0.653, 1.264, 0.498) ->       (150, 194, 131)
//   sand  (0.86, 0.80, 0.58)          (1.873, 1.839, 1.444) ->       (213, 212, 201)
//   snow  (0.95, 0.95, 0.97)          (2.069, 2.184, 2.415) ->       (217, 219, 223)
// (Before exposure and the filmic curve: grey (168, 172, 179), grass green 253, sand and snow
// 255: white-out.) Sand and snow differ by (4, 7, 22): 23 apart.
TEST(Exposure, DefaultLightsPutGreyAtMidGreyAndKeepColoursApart) {
    Fixture f = make_engine();
    if (!f.engine)
        GTEST_SKIP() << "no ray-tracing device: " << f.error;
    vx::Engine& e = *f.engine;
    vx::Image img;
    ASSERT_TRUE(e.render_to_image(img));
    EXPECT_FLOAT_EQ(e.stats().ev100, vx::RenderSettings{}.exposure.ev100);
    const glm::ivec3 grey = rgb(img, 8, 8), grass = rgb(img, 24, 8);
    const glm::ivec3 sand = rgb(img, 8, 24), snow = rgb(img, 24, 24);
    std::printf("EV100 %.2f: grey (%d, %d, %d), grass (%d, %d, %d), sand (%d, %d, %d), snow (%d, %d, %d)\n",
                double(e.stats().ev100), grey.r, grey.g, grey.b, grass.r, grass.g, grass.b, sand.r, sand.g,
                sand.b, snow.r, snow.g, snow.b);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(grey[c], 118, 12) << "channel " << c; // Photographic mid-grey: sRGB 118.
    const glm::ivec3 expected[] = {{150, 194, 131}, {213, 212, 201}, {217, 219, 223}};
    const glm::ivec3 got[] = {grass, sand, snow};
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_LT(got[i][c], 250) << "block " << i << " channel " << c; // Unclipped.
            EXPECT_NEAR(got[i][c], expected[i][c], 3) << "block " << i << " channel " << c;
        }
    EXPECT_GT(distance(grass, sand), 40.0);
    EXPECT_GT(distance(grass, snow), 40.0);
    EXPECT_GT(distance(sand, snow), 15.0);
    EXPECT_GT(grass.g, grass.r + 30); // Grass stays green.
    EXPECT_GT(snow.b, sand.b + 12);   // Snow stays white, sand yellow.
    EXPECT_EQ(e.stats().validation_errors, 0u);
}

// A cave-like view of grey ground (every quadrant): no sun, no sky light, the area light at
// 1/400 of its default radiance. The default exposure leaves the ground black (radiance 0.18 x
// 0.0058 / pi = 3.3e-4, x 0.313 exposure = 1e-4: byte 0); auto exposure meters the frame (the
// uniform ground, all of it) and shows it at mid-grey. Brought back to daylight, the exposure
// moves towards daylight's as fast as adapt_speed says: not at all with 0.
TEST(Exposure, AutoExposureLiftsADarkViewToMidGrey) {
    Fixture f = make_engine(true);
    if (!f.engine)
        GTEST_SKIP() << "no ray-tracing device: " << f.error;
    vx::Engine& e = *f.engine;
    vx::RenderSettings dark;
    dark.sun.irradiance = glm::vec3(0.f);
    dark.sky_light = 0.f;
    dark.light.emission = glm::vec3(0.05f);
    e.set_render_settings(dark);
    vx::Image img;
    ASSERT_TRUE(e.render_to_image(img));
    for (int c = 0; c < 3; ++c)
        EXPECT_LE(rgb(img, 8, 8)[c], 2) << "channel " << c;

    dark.exposure.automatic = true;
    e.set_render_settings(dark);
    ASSERT_TRUE(e.render_to_image(img));
    const float dark_ev = e.stats().ev100;
    std::printf("auto in the dark: EV100 %.2f, grey ground (%d, %d, %d)\n", double(dark_ev), rgb(img, 8, 8).r,
                rgb(img, 8, 8).g, rgb(img, 8, 8).b);
    // Luminance 3.3e-4 units = 3.3 cd/m^2 at mid-grey: EV100 = log2(3.3 / (1.2 x 0.1308)) = 4.4.
    EXPECT_NEAR(dark_ev, 4.4f, 0.3f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(rgb(img, 8, 8)[c], 118, 12) << "channel " << c;

    // Daylight again with adaptation frozen: the exposure stays the cave's (grey blows out).
    vx::RenderSettings day;
    day.exposure.automatic = true;
    day.exposure.adapt_speed = 0.f;
    e.set_render_settings(day);
    ASSERT_TRUE(e.render_to_image(img));
    ASSERT_TRUE(e.render_to_image(img));
    EXPECT_FLOAT_EQ(e.stats().ev100, dark_ev);
    EXPECT_GT(rgb(img, 8, 8).g, 240);
    // Adapting: each frame moves the exposure towards daylight's, never past it: for grey ground
    // under the default lights (luminance 0.41) the default EV100, log2(0.41e4 / (1.2 x 0.1308))
    // = 14.7.
    day.exposure.adapt_speed = 1.5f;
    e.set_render_settings(day);
    float ev = dark_ev;
    for (int i = 0; i < 2; ++i) {
        ASSERT_TRUE(e.render_to_image(img));
        EXPECT_GE(e.stats().ev100, ev);
        ev = e.stats().ev100;
    }
    ASSERT_TRUE(e.render_to_image(img));
    EXPECT_GT(e.stats().ev100, dark_ev);
    EXPECT_LT(e.stats().ev100, 14.8f);
    EXPECT_EQ(e.stats().validation_errors, 0u);
}

// Pixels no light reaches are not metered (they would pull the log-average to its floor and
// blow out whatever is lit). Ground under no light at all: nothing is metered, the exposure
// stays ev100 and the picture black.
TEST(Exposure, AutoExposureIgnoresPixelsWithoutLight) {
    Fixture f = make_engine(true);
    if (!f.engine)
        GTEST_SKIP() << "no ray-tracing device: " << f.error;
    vx::Engine& e = *f.engine;
    vx::RenderSettings none;
    none.sun.irradiance = glm::vec3(0.f);
    none.sky_light = 0.f;
    none.light.emission = glm::vec3(0.f);
    none.exposure.automatic = true;
    none.exposure.ev100 = 9.f;
    e.set_render_settings(none);
    vx::Image img;
    ASSERT_TRUE(e.render_to_image(img));
    EXPECT_FLOAT_EQ(e.stats().ev100, 9.f);
    EXPECT_EQ(rgb(img, 16, 16), glm::ivec3(0));
}

} // namespace
