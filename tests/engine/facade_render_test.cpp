// The facade <vx/vx.h> rendering headless on lavapipe with the validation layer on: a streamed
// terrain view into memory (a real picture, BLAS builds then refits after an edit, GPU memory
// reported), and a game's transparent block that shows the block behind it. CTest label vulkan.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "engine/engine_testing.h"
#include "facade_test_util.h"

using Clock = std::chrono::steady_clock;

namespace {

using vx::test::settle;

vx::EngineCreateInfo render_info(vx::WorldSource source, uint32_t w, uint32_t h) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.streaming.view_radius = 2;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    info.render.target = vx::RenderTarget::headless(w, h);
    info.render.device = vx::test::test_device();
    info.render.validation = true;
    return info;
}

// 12 blocks above terrain seed 3 at the origin, looking down the slope.
vx::Viewer terrain_view() {
    vx::Viewer v;
    v.block = {0, vx::terrain_height(3, 0, 0) + 12, 0};
    v.forward = {1, -0.35, 0.2};
    return v;
}

// Sets terrain_view() and waits until it is streamed; false (with a failure) if a step fails.
bool view_terrain(vx::Engine& e) {
    const vx::Status viewer = e.set_viewer(terrain_view());
    EXPECT_TRUE(viewer) << viewer.error();
    const bool settled = viewer && settle(e);
    EXPECT_TRUE(settled);
    return settled;
}

TEST(FacadeRender, TerrainToMemory) {
    auto engine = vx::Engine::create(render_info(vx::WorldSource::terrain(3), 64, 48));
    if (!engine)
        GTEST_SKIP() << "no ray-tracing device: " << engine.error();
    vx::Engine& e = **engine;
    const vx::Viewer v = terrain_view();
    ASSERT_TRUE(e.set_viewer(v));
    ASSERT_TRUE(settle(e));

    vx::Image img;
    ASSERT_TRUE(e.render_to_image(img));
    ASSERT_EQ(img.width, 64u);
    ASSERT_EQ(img.height, 48u);
    ASSERT_EQ(img.rgba.size(), 64u * 48u * 4u);
    // A real picture: terrain below (many colours), sky at the top row's centre.
    std::set<uint32_t> colours;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const glm::u8vec4 p = img.at(x, y);
            colours.insert(uint32_t(p.r) << 16 | uint32_t(p.g) << 8 | p.b);
        }
    EXPECT_GT(colours.size(), 20u);
    const glm::u8vec4 sky = img.at(32, 0);
    EXPECT_GT(sky.b, sky.r); // Blue sky (the light is above).
    vx::Stats s = e.stats();
    EXPECT_GT(s.blas_builds, 0u);
    EXPECT_GT(s.instances, 0u);
    EXPECT_GT(s.triangles, 0u);
    EXPECT_GT(s.gpu_memory_bytes, 0u);
    EXPECT_GE(s.gpu_memory_bytes, s.gpu_memory_used_bytes);
    EXPECT_GT(s.render_wall_ms, 0.0);

    // An edit in view: its chunk's BLAS is refitted or rebuilt in the next frame, nothing else.
    auto hit = e.raycast(v.block, v.offset, v.forward, 200.0);
    ASSERT_TRUE(hit);
    ASSERT_EQ(hit->kind, vx::RayHit::Kind::Hit);
    ASSERT_TRUE(e.set_block(hit->previous, *e.find_block("lamp")));
    // The edit reached the renderer's denoiser (render/edit_marks.h), and the next frame took it.
    EXPECT_EQ(vx::EngineTesting::noted_edits(e), 1);
    e.update();
    ASSERT_TRUE(e.render_to_image(img));
    EXPECT_EQ(vx::EngineTesting::noted_edits(e), 0);
    s = e.stats();
    EXPECT_GE(s.blas_builds + s.blas_refits, 1u);
    EXPECT_LE(s.blas_builds + s.blas_refits, 3u); // The chunk and at most two face neighbours.
    // Undone: the chunk is hot now and its old mesh fits its slots, so the facade hands over the
    // changed slices and the BLAS is refitted, uploading those slices only.
    const uint64_t first_upload = s.upload_bytes;
    ASSERT_TRUE(e.set_block(hit->previous, vx::kAir));
    e.update();
    ASSERT_TRUE(e.render_to_image(img));
    s = e.stats();
    EXPECT_GE(s.blas_refits, 1u);
    EXPECT_EQ(s.blas_builds, 0u);
    EXPECT_LT(s.upload_bytes, first_upload);
    EXPECT_EQ(s.validation_errors, 0u);
    ASSERT_TRUE(e.shutdown());
    EXPECT_EQ(e.stats().validation_errors, 0u);
    EXPECT_FALSE(e.render_to_image(img)); // Shut down.
}

// Sum over pixels of |difference| of the RGB channels, per pixel (0..765).
double mean_abs_diff(const vx::Image& a, const vx::Image& b) {
    double sum = 0;
    for (size_t i = 0; i < a.rgba.size(); i += 4)
        for (size_t c = 0; c < 3; ++c)
            sum += std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c]));
    return sum / double(a.rgba.size() / 4);
}

// Mean |difference| between horizontal neighbours: the image's pixel noise (plus its edges).
double roughness(const vx::Image& img) {
    double sum = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 1; x < img.width; ++x)
            for (int c = 0; c < 3; ++c)
                sum += std::abs(int(img.at(x, y)[c]) - int(img.at(x - 1, y)[c]));
    return sum / double(img.height * (img.width - 1));
}

// Renders one frame of `rs` (the first step of each check below).
vx::Image render_with(vx::Engine& e, const vx::RenderSettings& rs) {
    e.set_render_settings(rs);
    vx::Image img;
    EXPECT_TRUE(e.render_to_image(img));
    return img;
}

// The raster pipeline covers the pixels the ray tracer covers (Flat) but shades differently
// (Full: no shadows); the denoiser smooths a one-sample image, and so does the light cache; the
// sun's irradiance lights the scene. Returns the Full settings these used.
vx::RenderSettings expect_pipelines_filters_and_sun(vx::Engine& e) {
    using P = vx::RenderSettings::Pipeline;
    vx::RenderSettings flat;
    flat.shading = vx::RenderSettings::Shading::Flat;
    const vx::Image rt_flat = render_with(e, flat);
    flat.pipeline = P::Raster;
    const vx::Image raster_flat = render_with(e, flat);
    // Flat writes the sky colour unencoded on a miss: (0.55, 0.7, 0.95) * 255 = (140, 179, 242).
    auto is_sky = [](glm::u8vec4 p) { return std::abs(int(p.r) - 140) <= 1 && std::abs(int(p.b) - 242) <= 1; };
    size_t sky = 0, agree = 0;
    for (uint32_t y = 0; y < 32; ++y)
        for (uint32_t x = 0; x < 48; ++x) {
            sky += is_sky(rt_flat.at(x, y));
            agree += is_sky(rt_flat.at(x, y)) == is_sky(raster_flat.at(x, y));
        }
    EXPECT_GT(sky, 48u);             // Some sky (the top rows)...
    EXPECT_LT(sky, 48u * 32u - 48u); // ...and some ground.
    EXPECT_GE(agree, 48u * 32u * 97 / 100); // The same coverage but for edge pixels.

    vx::RenderSettings full;
    full.shadow_samples = 1; // Noisy, so the denoiser has work.
    full.max_bounces = 0;
    const vx::Image rt_full = render_with(e, full);
    full.pipeline = P::Raster;
    const vx::Image raster_full = render_with(e, full);
    EXPECT_GT(mean_abs_diff(rt_full, raster_full), 10.0); // Phong and no shadows vs the tracer.
    full.pipeline = P::RayTraced;
    full.denoise = true;
    const vx::Image denoised = render_with(e, full);
    EXPECT_GT(mean_abs_diff(rt_full, denoised), 1.0);
    EXPECT_LT(roughness(denoised), roughness(rt_full));
    full.denoise = false;
    full.light_cache = true; // Shared light: smoother too, before any filter.
    const vx::Image cached = render_with(e, full);
    EXPECT_GT(mean_abs_diff(rt_full, cached), 1.0);
    EXPECT_LT(roughness(cached), roughness(rt_full));
    full.light_cache = false;
    vx::RenderSettings no_sun = full;
    no_sun.sun.irradiance = glm::vec3(0.f);
    const vx::Image dark_image = render_with(e, no_sun);
    double lit = 0, dark = 0;
    for (size_t i = 0; i < rt_full.rgba.size(); i += 4) {
        lit += rt_full.rgba[i] + rt_full.rgba[i + 1] + rt_full.rgba[i + 2];
        dark += dark_image.rgba[i] + dark_image.rgba[i + 1] + dark_image.rgba[i + 2];
    }
    EXPECT_LT(dark, lit * 0.95);
    return no_sun;
}

// At night (`night`: no sun) with a lamp at `at`: its faces sampled light the ground around it
// smoothly; found only by sky rays that hit it by chance, the same light is a scatter of bright
// pixels (emitter_sampling).
void expect_lamp_faces_sampled(vx::Engine& e, vx::RenderSettings night, vx::BlockPos at) {
    ASSERT_TRUE(e.set_block(at, *e.find_block("lamp")));
    ASSERT_TRUE(settle(e));
    night.sky_light = 0.f;
    night.light.emission = glm::vec3(0.f);
    const vx::Image faces = render_with(e, night);
    night.emitter_sampling = false;
    const vx::Image rays = render_with(e, night);
    std::printf("lamp at night, roughness: faces sampled %.2f, sky rays %.2f\n", roughness(faces), roughness(rays));
    EXPECT_GT(mean_abs_diff(faces, rays), 0.5);
    EXPECT_LT(roughness(faces), roughness(rays));
    ASSERT_TRUE(e.set_block(at, vx::kAir));
    ASSERT_TRUE(settle(e));
}

// Pixels whose colour changes when `s` takes samples by weight.
size_t changed_by_weight(vx::Engine& e, vx::RenderSettings s) {
    s.samples_by_weight = false;
    const vx::Image plain = render_with(e, s);
    s.samples_by_weight = true;
    const vx::Image weighted = render_with(e, s);
    size_t n = 0;
    for (size_t i = 0; i < plain.rgba.size(); i += 4)
        n += plain.rgba[i] != weighted.rgba[i] || plain.rgba[i + 1] != weighted.rgba[i + 1] ||
             plain.rgba[i + 2] != weighted.rgba[i + 2];
    return n;
}

// Samples by weight reach the renderer. Without haze a matte hit keeps its count: only the water
// in view (reflectivity 0.3: 3 of 4 samples) changes, one pixel here. A slab of glazed blocks
// around `at` (3 of 4) changes more; so does the weight exponent 0.8 (a glazed first hit keeps
// all 4 samples: ceil(4 x 0.75^0.8) = 4, against 3 at 1). Hits in passes of their own give the
// same picture of the slab (its paths go on through the passes; render/split_hits_test.cpp checks
// the G-buffer too), and the paths' buffer (88 bytes a pixel) is held.
void expect_samples_by_weight_and_split_hits(vx::Engine& e, vx::RenderSettings day, vx::BlockPos at) {
    day.haze.enabled = false; // Its transmittance is part of a hit's weight too.
    day.max_bounces = 2;
    day.shadow_samples = 4;
    const size_t matte = changed_by_weight(e, day);
    for (int64_t dz = -2; dz <= 2; ++dz)
        for (int64_t dx = -2; dx <= 2; ++dx)
            ASSERT_TRUE(e.set_block(at + vx::BlockPos(dx, 0, dz), *e.find_block("glazed")));
    ASSERT_TRUE(settle(e));
    const size_t glazed = changed_by_weight(e, day);
    std::printf("samples by weight: %zu pixels change, %zu with glazed blocks in view\n", matte, glazed);
    EXPECT_LE(matte, 48u * 32u / 100u);
    EXPECT_GT(glazed, matte + 4);
    day.samples_by_weight = true;
    const vx::Image by_weight = render_with(e, day);
    day.weight_exponent = 0.8f;
    const vx::Image by_weight_08 = render_with(e, day);
    day.weight_exponent = 1.f;
    size_t exponent_changed = 0;
    for (size_t i = 0; i < by_weight.rgba.size(); ++i)
        exponent_changed += by_weight.rgba[i] != by_weight_08.rgba[i];
    std::printf("weight exponent 0.8: %zu channels change\n", exponent_changed);
    EXPECT_GT(exponent_changed, 12u);
    vx::RenderSettings split = day;
    const vx::Image one_pass = render_with(e, split);
    const uint64_t before = e.stats().gpu_memory_used_bytes;
    split.split_hits = 2;
    EXPECT_EQ(render_with(e, split).rgba, one_pass.rgba);
    EXPECT_GE(e.stats().gpu_memory_used_bytes, before + 48u * 32u * 88u);
}

// The facade's RenderSettings reach the renderer: pipelines, filters and the sun; emitter
// sampling; samples by weight, their exponent and split hits (the steps above, on one engine).
TEST(FacadeRender, SettingsReachTheRenderer) {
    auto engine = vx::Engine::create(render_info(vx::WorldSource::terrain(3), 48, 32));
    if (!engine)
        GTEST_SKIP() << "no ray-tracing device: " << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(view_terrain(e));
    vx::RenderSettings no_sun = expect_pipelines_filters_and_sun(e);
    auto hit = e.raycast(terrain_view().block, terrain_view().offset, terrain_view().forward, 200.0);
    ASSERT_TRUE(hit);
    ASSERT_EQ(hit->kind, vx::RayHit::Kind::Hit);
    expect_lamp_faces_sampled(e, no_sun, hit->previous);
    if (::testing::Test::HasFatalFailure())
        return;
    expect_samples_by_weight_and_split_hits(e, no_sun, hit->previous);
    EXPECT_EQ(e.stats().validation_errors, 0u);
}

// A cube of a game's block W (8³ blocks) with an opaque block O against its -z side and another
// opaque block P behind O. The eye sits inside W looking -z. When W is transparent, O's face
// towards W is meshed and the centre pixel shows O; when W is opaque that face is culled (both
// sides opaque), and the ray, which ignores facing, runs through W and O to the back face of P.
class WindowGenerator final : public vx::Generator {
public:
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int z = 0; z < 32; ++z)
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const vx::BlockPos p = o + vx::BlockPos(x, y, z);
                    vx::BlockId id = vx::kAir;
                    if (p.x >= 0 && p.x < 8 && p.y >= 0 && p.y < 8 && p.z >= 0 && p.z < 8)
                        id = 1; // W
                    else if (p == vx::BlockPos(4, 4, -1))
                        id = 2; // O
                    else if (p == vx::BlockPos(4, 4, -2))
                        id = 3; // P
                    blocks[vx::chunk_index(x, y, z)] = id;
                }
    }
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        if (c == vx::ChunkCoord(0) || c == vx::ChunkCoord(0, 0, -1))
            return std::nullopt;
        return vx::kAir;
    }
};

glm::u8vec4 centre_pixel(bool window_transparent) {
    vx::EngineCreateInfo info = render_info(vx::WorldSource::custom(std::make_shared<WindowGenerator>()), 16, 16);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.blocks = {{"window", {0.9f, 0.1f, 0.1f}}, {"blue", {0.1f, 0.1f, 0.9f}}, {"green", {0.1f, 0.9f, 0.1f}}};
    info.blocks[0].opaque = !window_transparent;
    auto engine = vx::Engine::create(info);
    if (!engine)
        return {0, 0, 0, 0};
    vx::Engine& e = **engine;
    vx::Viewer v;
    v.block = {4, 4, 4};
    v.offset = {0.5, 0.5, 0.5};
    v.forward = {0, 0, -1};
    v.fov_y_degrees = 20.f;
    EXPECT_TRUE(e.set_viewer(v));
    vx::RenderSettings rs;
    rs.shading = vx::RenderSettings::Shading::Flat;
    e.set_render_settings(rs);
    EXPECT_TRUE(settle(e));
    vx::Image img;
    EXPECT_TRUE(e.render_to_image(img));
    EXPECT_EQ(e.stats().validation_errors, 0u);
    return img.at(8, 8);
}

// A sun direction of any finite length is the same sun: {1e20, 1e20, 1e20} (infinitely long in
// float: the shader got a zero direction and sampled a ring round the horizon) and {1e-25, ...}
// (zero in float: no sun) render as {1, 1, 1} does. A zero direction with the sun on, and area
// light edges whose area overflows float, are refused where they are handed over.
TEST(FacadeRender, TheSunsDirectionNeedNotBeUnit) {
    auto engine = vx::Engine::create(render_info(vx::WorldSource::terrain(3), 48, 32));
    if (!engine)
        GTEST_SKIP() << "no ray-tracing device: " << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(view_terrain(e));
    auto frame = [&](glm::vec3 sun) {
        vx::RenderSettings r;
        r.shadow_samples = 2;
        r.sun.direction = sun;
        EXPECT_TRUE(e.set_render_settings(r));
        vx::Image img;
        EXPECT_TRUE(e.render_to_image(img));
        return img.rgba;
    };
    const std::vector<uint8_t> unit = frame({1.f, 1.f, 1.f});
    EXPECT_EQ(frame({1e20f, 1e20f, 1e20f}), unit);
    EXPECT_EQ(frame({1e-25f, 1e-25f, 1e-25f}), unit);
    vx::RenderSettings r;
    r.sun.direction = glm::vec3(0.f);
    const vx::Status zero = e.set_render_settings(r);
    ASSERT_FALSE(zero);
    EXPECT_NE(zero.error().find("direction is zero"), std::string::npos) << zero.error();
    r.sun.irradiance = glm::vec3(0.f); // No sun: any direction.
    EXPECT_TRUE(e.set_render_settings(r));
    r = vx::RenderSettings{};
    r.light.edge_u = {1e20f, 0.f, 0.f};
    EXPECT_FALSE(e.set_render_settings(r));
    r.light.edge_u = {float(1 << 20), 0.f, 0.f};
    EXPECT_TRUE(e.set_render_settings(r));
    EXPECT_EQ(e.stats().validation_errors, 0u);
}

TEST(FacadeRender, TransparentBlockShowsWhatIsBehind) {
    if (!vx::Engine::create(render_info(vx::WorldSource::terrain(1), 4, 4)))
        GTEST_SKIP() << "no ray-tracing device";
    const glm::u8vec4 through = centre_pixel(true);
    const glm::u8vec4 solid = centre_pixel(false);
    // Flat shading writes linear albedo: blue O through the transparent W, green P otherwise.
    // The eye lies inside W, 4.5 blocks from its end, and the ray leaves W where it lies against O
    // (no face there): the engine tells the renderer the eye's block, so the view is tinted by 4.5
    // blocks of W (Beer-Lambert), O x W^4.5 = (0.062, 0.000, 0.000): red 16 (without the eye's
    // block: O untinted, blue 230).
    const glm::dvec3 o(0.1, 0.1, 0.9), w(0.9, 0.1, 0.1);
    for (int c = 0; c < 3; ++c)
        EXPECT_LE(std::abs(int(through[c]) - int(std::lround(255 * o[c] * std::pow(w[c], 4.5)))), 1)
            << "channel " << c << ": " << int(through.r) << "," << int(through.g) << "," << int(through.b);
    EXPECT_GT(solid.g, 200) << int(solid.r) << "," << int(solid.g) << "," << int(solid.b);
    EXPECT_LT(solid.b, 60);
}

// A floor at y = -1 tiled 4 x 4 with 16 blocks of distinct albedo: the block at (x, z) is
// 1 + (x mod 4) + 4 (z mod 4), so a pixel's colour names the block the renderer shows there.
class TileGenerator final : public vx::Generator {
public:
    static vx::BlockId tile(vx::BlockPos p) { return vx::BlockId(1 + (p.x & 3) + 4 * (p.z & 3)); }
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int z = 0; z < 32; ++z)
            for (int x = 0; x < 32; ++x)
                blocks[vx::chunk_index(x, 31, z)] = tile(o + vx::BlockPos(x, 31, z)); // y = -1.
    }
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        if (c.y == -1)
            return std::nullopt;
        return vx::kAir;
    }
};

// Mouse picking: the ray Engine::screen_ray gives for a pixel hits (raycast) the block the
// renderer drew at that pixel, over the whole frame (off-centre, both axes, a non-square frame).
TEST(FacadeRender, ScreenRayPicksTheBlockDrawnAtThePixel) {
    constexpr uint32_t kW = 40, kH = 24;
    vx::EngineCreateInfo info = render_info(vx::WorldSource::custom(std::make_shared<TileGenerator>()), kW, kH);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    for (int i = 0; i < 16; ++i)
        info.blocks.push_back({"tile" + std::to_string(i), {0.1f + 0.25f * float(i % 4), 0.1f + 0.25f * float(i / 4), 0.3f}});
    auto engine = vx::Engine::create(info);
    if (!engine)
        GTEST_SKIP() << "no ray-tracing device: " << engine.error();
    vx::Engine& e = **engine;
    vx::Viewer v;
    v.block = {3, 5, 5};
    v.offset = {0.3, 0.6, 0.7};
    v.forward = {0.3, -1, -0.2}; // Steeply down: every floor pixel lies in the meshed chunks.
    v.fov_y_degrees = 50.f;
    ASSERT_TRUE(e.set_viewer(v));
    vx::RenderSettings rs;
    rs.shading = vx::RenderSettings::Shading::Flat;
    e.set_render_settings(rs);
    ASSERT_TRUE(settle(e));
    vx::Image img;
    ASSERT_TRUE(e.render_to_image(img));
    size_t checked = 0;
    std::set<vx::BlockId> seen;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            auto ray = e.screen_ray({x + 0.5, y + 0.5});
            ASSERT_TRUE(ray) << ray.error();
            auto hit = e.raycast(ray->origin_block, ray->origin_offset, ray->direction, 100.0);
            ASSERT_TRUE(hit) << hit.error();
            ASSERT_EQ(hit->kind, vx::RayHit::Kind::Hit) << x << "," << y;
            // A hit within 0.02 blocks of a tile's edge may fall either side in the GPU's floats.
            const glm::dvec3 at = glm::dvec3(ray->origin_block) + ray->origin_offset + ray->direction * hit->distance;
            const glm::dvec2 frac = glm::fract(glm::dvec2(at.x, at.z));
            if (glm::any(glm::lessThan(glm::min(frac, 1.0 - frac), glm::dvec2(0.02))))
                continue;
            const vx::BlockType type = *e.block_type(hit->id);
            const glm::u8vec4 p = img.at(x, y);
            for (int c = 0; c < 3; ++c) // Flat shading writes the linear albedo: round(albedo * 255).
                EXPECT_NEAR(int(p[c]), int(std::lround(type.albedo[c] * 255.f)), 2)
                    << "pixel " << x << "," << y << " shows another block than " << type.name;
            ++checked;
            seen.insert(hit->id);
        }
    EXPECT_GT(checked, size_t(kW * kH / 2));
    EXPECT_EQ(seen.size(), 16u); // The view spans every tile.
    EXPECT_EQ(e.stats().validation_errors, 0u);
}

} // namespace
