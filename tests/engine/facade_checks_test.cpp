// The facade <vx/vx.h> refuses bad input at the call that receives it (a viewer at set_viewer,
// render settings at set_render_settings, a block's material at create), and the small queries a
// game's UI needs: the ray through a screen pixel and the block registry read back. Stored worlds'
// generators: facade_stored_world_test.cpp; write_png: facade_png_test.cpp.
// No GPU (RenderTarget::none).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include <unistd.h>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_checks_util.h"
#include "facade_test_util.h"
#include "world/store/store_open.h"

namespace {

using vx::test::checks_world;
using vx::test::error_of;
using vx::test::tiny_info;

// An engine of `info` (a world of seed 1) with the viewer 4 blocks above the terrain at the
// origin, settled; null (with a test failure) when a step fails.
std::unique_ptr<vx::Engine> settled_above_origin(const vx::EngineCreateInfo& info) {
    auto engine = vx::Engine::create(info);
    EXPECT_TRUE(engine) << engine.error();
    if (!engine)
        return nullptr;
    vx::Viewer v;
    v.block = {0, vx::terrain_height(1, 0, 0) + 4, 0};
    const bool ready = (*engine)->set_viewer(v).ok() && vx::test::settle(**engine);
    EXPECT_TRUE(ready);
    return ready ? std::move(*engine) : nullptr;
}

// A game may create its engine on a loading thread and use it from the game loop's, then destroy
// it on a third: one thread at a time (vx.h, Threads). update() on the second aborted the process
// (the job system's completions asserted their creator's thread), and so did the destruction.
TEST(FacadeChecks, TheEngineMovesBetweenThreadsOneAtATime) {
    const std::string path = checks_world("moves.db");
    std::unique_ptr<vx::Engine> engine;
    std::thread loader([&] {
        auto made = vx::Engine::create(tiny_info(vx::WorldSource::sqlite(path, 1)));
        ASSERT_TRUE(made) << made.error();
        engine = std::move(*made);
    });
    loader.join();
    ASSERT_TRUE(engine);
    vx::Viewer v;
    v.block = {0, vx::terrain_height(1, 0, 0) + 4, 0};
    ASSERT_TRUE(engine->set_viewer(v));
    ASSERT_TRUE(vx::test::settle(*engine));
    const vx::BlockPos p{1, vx::terrain_height(1, 1, 1) + 2, 1};
    ASSERT_TRUE(engine->set_block(p, 1));
    std::thread other([&] { // And on again, with an edit saved there.
        engine->update();
        auto ticket = engine->save();
        ASSERT_TRUE(ticket) << ticket.error();
        EXPECT_TRUE(engine->wait(*ticket)) << "saved";
    });
    other.join();
    EXPECT_EQ(engine->get_block(p), std::optional<vx::BlockId>(1));
    std::thread closer([&] { engine.reset(); });
    closer.join();
    auto reopened = vx::Engine::create(tiny_info(vx::WorldSource::sqlite(path, 1)));
    ASSERT_TRUE(reopened) << reopened.error();
    ASSERT_TRUE((*reopened)->set_viewer(v));
    ASSERT_TRUE(vx::test::settle(**reopened));
    EXPECT_EQ((*reopened)->get_block(p), std::optional<vx::BlockId>(1));
}

// Two threads calling at once, which the rule above forbids: the call that finds another thread
// inside is refused and touches nothing. Unguarded, edits and queries from a second thread during
// update() crashed the process within seconds (SIGSEGV, "corrupted size vs. prev_size").
TEST(FacadeChecks, ACallWhileAnotherThreadIsInsideIsRefused) {
    vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
    info.streaming.view_radius = 3;
    auto engine = settled_above_origin(info);
    ASSERT_TRUE(engine);
    const vx::BlockPos p{1, vx::terrain_height(1, 1, 1) + 2, 1};
    std::atomic<bool> stop{false};
    std::atomic<int> refused{0}, placed{0};
    std::string message;
    std::thread other([&] {
        const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (refused.load() < 50 && std::chrono::steady_clock::now() < limit) {
            const vx::Status s = engine->set_block(p, placed.load() % 2 ? 1 : vx::kAir);
            if (s) {
                placed.fetch_add(1);
            } else if (s.error().find("another thread was inside") != std::string::npos) {
                if (refused.fetch_add(1) == 0)
                    message = s.error();
            } else {
                ADD_FAILURE() << s.error();
                break;
            }
            (void)engine->get_block(p + vx::BlockPos{0, 1, 0});
        }
        stop = true;
    });
    // The main thread keeps moving the viewer back and forth: each update() has work to do.
    for (int i = 0; !stop.load(); ++i) {
        vx::Viewer v;
        v.block = {32 * (i % 2), vx::terrain_height(1, 0, 0) + 4, 0};
        (void)engine->set_viewer(v); // Refused too at times: the other thread may be inside.
        engine->update();
    }
    other.join();
    EXPECT_GE(refused.load(), 50) << "the threads never overlapped";
    EXPECT_NE(message.find("Engine::set_blocks"), std::string::npos) << message;
    // Alone again: every call works, and the last edit that was accepted is there.
    ASSERT_TRUE(engine->set_block(p, 1));
    EXPECT_EQ(engine->get_block(p), std::optional<vx::BlockId>(1));
    EXPECT_TRUE(engine->shutdown());
}

// An edit made without levels of detail marks the coarse levels above it stale in the store, so a
// later session with them on derives them from the blocks: unmarked, they read as current, or,
// absent, as plain terrain, and the far view hid what the player built.
TEST(FacadeChecks, EditsWithoutLevelsOfDetailMarkTheCoarseLevelsStale) {
    const std::string path = checks_world("no_lod_marks.db");
    const vx::BlockPos p{3, vx::terrain_height(1, 3, 3) + 3, 3};
    {
        auto engine = settled_above_origin(tiny_info(vx::WorldSource::sqlite(path, 1)));
        ASSERT_TRUE(engine);
        ASSERT_TRUE(engine->set_block(p, 1));
        ASSERT_TRUE(engine->set_block(p + vx::BlockPos{1, 0, 0}, 1)); // The same chunk: marked once.
        auto ticket = engine->save();
        ASSERT_TRUE(ticket) << ticket.error();
        ASSERT_TRUE(engine->wait(*ticket));
    }
    auto store = vx::world::open_store({path, /*read_only=*/true, /*create=*/false, /*listen=*/false});
    ASSERT_TRUE(store) << store.error();
    auto dirty = (*store)->list_lod_dirty();
    ASSERT_TRUE(dirty) << dirty.error();
    const vx::world::ChunkCoord c = vx::world::chunk_of(vx::world::BlockPos(p.x, p.y, p.z));
    for (int k = 1; k <= vx::world::kMaxLodLevel; ++k)
        EXPECT_NE(std::find(dirty->begin(), dirty->end(), vx::world::lod_ancestor({0, c}, k)), dirty->end())
            << "level " << k;
    EXPECT_EQ(dirty->size(), size_t(vx::world::kMaxLodLevel));
}

// Levels of detail whose boxes would hold millions of coarse chunks are refused at create: each
// setting was in range, but together (vertical reach 65536) the first update kept 2.4 million
// nodes in a second, and ring 64 with view distance 65536 took 95 s and 7.5 GB.
TEST(FacadeChecks, LevelsOfDetailTooLargeTogetherAreRefused) {
    vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
    info.streaming.view_distance = 4096;
    info.streaming.lod_vertical_reach = 65536;
    auto refused = vx::Engine::create(info);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("coarse chunks around the viewer"), std::string::npos) << refused.error();
    info.streaming.lod_vertical_reach = 256; // The default.
    auto fine = vx::Engine::create(info);
    EXPECT_TRUE(fine) << fine.error();
}

TEST(FacadeChecks, SetViewerRefusesACameraTheRendererCannotMake) {
    auto engine = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const vx::Viewer good;
    ASSERT_TRUE(e.set_viewer(good));

    struct Case {
        const char* what;
        glm::dvec3 forward, up;
        float fov;
        const char* message;
    };
    const Case cases[] = {
        {"zero forward", {0, 0, 0}, {0, 1, 0}, 60.f, "forward is zero"},
        {"zero up", {0, 0, -1}, {0, 0, 0}, 60.f, "up is zero"},
        {"forward along up", {0, 2, 0}, {0, 1, 0}, 60.f, "parallel to up"},
        {"forward against up", {0, -1, 0}, {0, 1, 0}, 60.f, "parallel to up"},
        {"fov 0", {0, 0, -1}, {0, 1, 0}, 0.f, "fov_y_degrees must be in (0, 180)"},
        {"fov 180", {0, 0, -1}, {0, 1, 0}, 180.f, "fov_y_degrees must be in (0, 180)"},
        {"fov 270", {0, 0, -1}, {0, 1, 0}, 270.f, "fov_y_degrees must be in (0, 180)"},
        {"fov -60", {0, 0, -1}, {0, 1, 0}, -60.f, "fov_y_degrees must be in (0, 180)"},
        {"fov inf", {0, 0, -1}, {0, 1, 0}, std::numeric_limits<float>::infinity(), "must be finite"},
    };
    for (const Case& c : cases) {
        vx::Viewer v;
        v.block = {100, 5, 100};
        v.forward = c.forward;
        v.up = c.up;
        v.fov_y_degrees = c.fov;
        const vx::Status s = e.set_viewer(v);
        ASSERT_FALSE(s) << c.what;
        EXPECT_NE(s.error().find(c.message), std::string::npos) << c.what << ": " << s.error();
    }
    // The previous viewer stays: screen rays still come from it.
    auto ray = vx::screen_ray(good, {0.5, 0.5}, {1, 1});
    ASSERT_TRUE(ray) << ray.error();
    EXPECT_NEAR(ray->direction.z, -1.0, 1e-12);
    // Looking straight down works with another up; a tiny but valid fov too.
    vx::Viewer down;
    down.forward = {0, -1, 0};
    down.up = {0, 0, -1};
    EXPECT_TRUE(e.set_viewer(down));
    down.fov_y_degrees = 0.5f;
    EXPECT_TRUE(e.set_viewer(down));
}

// Forward and up of any finite, non-zero length are directions: 1e-200 and 1e300 long ones give
// the same screen rays as unit ones (their squares underflowed or overflowed, and the camera's
// basis became NaN), and set_viewer takes them. An offset past 2^40 is refused by screen_ray as
// by set_viewer.
TEST(FacadeChecks, ViewerDirectionsOfAnyLengthAreDirections) {
    auto engine = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Viewer unit;
    unit.forward = {0.6, 0, -0.8};
    unit.up = {0, 1, 0};
    const glm::uvec2 size{64, 48};
    auto expected = vx::screen_ray(unit, {10, 7}, size);
    ASSERT_TRUE(expected) << expected.error();
    for (const double scale : {1e-200, 1e-30, 1e30, 1e300}) {
        vx::Viewer v = unit;
        v.forward *= scale;
        v.up *= scale;
        EXPECT_TRUE((*engine)->set_viewer(v)) << scale;
        auto ray = vx::screen_ray(v, {10, 7}, size);
        ASSERT_TRUE(ray) << scale << ": " << ray.error();
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(ray->direction[i], expected->direction[i], 1e-12) << scale;
    }
    vx::Viewer far = unit;
    far.offset = {double(int64_t(1) << 41), 0, 0};
    auto ray = vx::screen_ray(far, {10, 7}, size);
    ASSERT_FALSE(ray);
    EXPECT_NE(ray.error().find("keep the offset small"), std::string::npos) << ray.error();
}

// Pixels far outside the frame are rays too: toward the pixel's bearing, a unit vector. Past 1e154
// the direction's squared length overflowed (a zero direction), and at 1e308 the doubled pixel
// did (NaN), both returned as success.
TEST(FacadeChecks, ScreenRaysOfFarPixelsAreUnitDirections) {
    vx::Viewer v;
    v.forward = {0, 0, -1};
    v.up = {0, 1, 0};
    v.fov_y_degrees = 179.99f;
    for (const glm::dvec2 pixel : {glm::dvec2(1e160, 0.5), glm::dvec2(1e150, 0.5), glm::dvec2(1e308, 0.5),
                                   glm::dvec2(0.5, -1e308), glm::dvec2(-1e300, 1e300), glm::dvec2(1e9, 0.5)}) {
        auto ray = vx::screen_ray(v, pixel, {1, 1});
        ASSERT_TRUE(ray) << pixel.x << "," << pixel.y << ": " << ray.error();
        EXPECT_NEAR(glm::length(ray->direction), 1.0, 1e-12) << pixel.x << "," << pixel.y;
        // Right (+x) for pixels right of the frame, up (+y) for those above it.
        const glm::dvec2 bearing = glm::sign(pixel - 0.5) * glm::dvec2(1, -1);
        EXPECT_EQ(glm::sign(ray->direction.x), bearing.x) << pixel.x << "," << pixel.y;
        EXPECT_EQ(glm::sign(ray->direction.y), bearing.y) << pixel.x << "," << pixel.y;
        if (std::abs(pixel.x) == std::abs(pixel.y)) { // The diagonal's bearing, not an axis's.
            EXPECT_NEAR(std::abs(ray->direction.x), std::abs(ray->direction.y), 1e-9);
        }
    }
}

// The streamed world ends 2^17 blocks inside the world's edge (2^36), on every axis and side: a
// viewer past it is refused (its box of chunks once ended at INT32_MAX, and the loop over it
// never did). A viewer just inside it streams and meshes as anywhere else.
TEST(FacadeChecks, SetViewerKeepsTheStreamedBoxInsideTheWorld) {
    auto engine = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const int64_t edge = (int64_t(1) << 36) - (int64_t(1) << 17); // First block outside, positive side.
    // screen_ray refuses the same viewers (it took them, and INT64_MAX plus an offset of 1.5
    // overflowed to INT64_MIN); so does a block past the edge that the offset would bring back.
    for (int axis = 0; axis < 3; ++axis)
        for (int64_t at : {edge, -edge - 1, edge + 1000, (int64_t(1) << 36) - 1, int64_t(1) << 50, INT64_MAX,
                           INT64_MIN}) {
            vx::Viewer v;
            v.block[axis] = at;
            v.offset[axis] = at > edge + 1000 ? 1.5 : at < -edge - 1 ? -1.5 : 0.5; // Folded in: overflow.
            const vx::Status s = e.set_viewer(v);
            ASSERT_FALSE(s) << axis << " " << at;
            EXPECT_NE(s.error().find("outside the streamed world"), std::string::npos) << s.error();
            auto ray = vx::screen_ray(v, {0.5, 0.5}, {1, 1});
            ASSERT_FALSE(ray) << axis << " " << at;
            EXPECT_NE(ray.error().find("outside the streamed world"), std::string::npos) << ray.error();
        }
    vx::Viewer back;
    back.block.x = int64_t(1) << 37;
    back.offset.x = -double(int64_t(1) << 37);
    EXPECT_FALSE(e.set_viewer(back));
    vx::Viewer inside;
    inside.block = {edge - 1, 0, -edge};
    inside.block.y = vx::terrain_height(1, inside.block.x, inside.block.z) + 4;
    ASSERT_TRUE(e.set_viewer(inside));
    ASSERT_TRUE(vx::test::settle(e));
    EXPECT_EQ(e.stats().chunks_meshed, 27u); // Radius 1: 3 x 3 x 3 chunks in view.
    EXPECT_TRUE(e.get_block(inside.block).has_value());
}

// Any accepted update budget makes progress: with 0.0003 ms the request pass used it all, and
// completions and meshes (which had no minimum per frame, unlike unloads) never ran: nothing
// ever loaded. A few of each now run in every update().
TEST(FacadeChecks, ATinyUpdateBudgetStillFillsTheView) {
    vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
    info.streaming.update_budget_ms = 0.0003;
    const std::unique_ptr<vx::Engine> e = settled_above_origin(info);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->stats().chunks_meshed, 27u); // Radius 1: 3 x 3 x 3 chunks in view.
}

// terrain_height is defined for every column: past the world's edge it is the edge's height (near
// 2^63 the noise lattice overflowed, undefined behaviour and a meaningless height).
TEST(FacadeChecks, TerrainHeightPastTheWorldsEdgeIsTheEdges) {
    const int64_t lo = int64_t(INT32_MIN) * 32, hi = int64_t(INT32_MAX) * 32 + 31;
    for (const uint64_t seed : {uint64_t(1), ~uint64_t(0)}) {
        EXPECT_EQ(vx::terrain_height(seed, INT64_MAX, 5), vx::terrain_height(seed, hi, 5));
        EXPECT_EQ(vx::terrain_height(seed, INT64_MAX - 100, INT64_MIN), vx::terrain_height(seed, hi, lo));
        EXPECT_EQ(vx::terrain_height(seed, 7, INT64_MAX - (int64_t(1) << 20)), vx::terrain_height(seed, 7, hi));
    }
}

TEST(FacadeChecks, SetRenderSettingsRefusesWhatCannotBeRendered) {
    auto engine = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_render_settings(vx::RenderSettings{}));
    // The curve-chosen game settings (what the sandbox runs) are accepted, and are what vx.h says.
    const vx::RenderSettings game = vx::RenderSettings::recommended();
    EXPECT_TRUE(e.set_render_settings(game));
    EXPECT_EQ(game.shadow_samples, 1u);
    EXPECT_EQ(game.bounce_shadow_samples.value_or(0), 1u);
    EXPECT_TRUE(game.denoise);
    EXPECT_EQ(game.accumulate, 8u);
    struct Case {
        const char* what;
        void (*change)(vx::RenderSettings&);
        const char* message;
    };
    const Case cases[] = {
        {"2000 samples", [](vx::RenderSettings& s) { s.shadow_samples = 2000; }, "shadow samples"},
        {"2000 bounce samples", [](vx::RenderSettings& s) { s.bounce_shadow_samples = 2000u; }, "shadow samples"},
        {"17 bounces", [](vx::RenderSettings& s) { s.max_bounces = 17; }, "max_bounces"},
        {"weight exponent 0", [](vx::RenderSettings& s) { s.weight_exponent = 0.f; }, "weight_exponent"},
        {"weight exponent 1.5", [](vx::RenderSettings& s) { s.weight_exponent = 1.5f; }, "weight_exponent"},
        {"NaN weight exponent", [](vx::RenderSettings& s) { s.weight_exponent = std::nanf(""); }, "weight_exponent"},
        {"accumulate 0", [](vx::RenderSettings& s) { s.accumulate = 0; }, "accumulate"},
        {"negative sky", [](vx::RenderSettings& s) { s.sky = {-1.f, 0.5f, 0.5f}; }, "sky"},
        {"NaN sky light", [](vx::RenderSettings& s) { s.sky_light = std::numeric_limits<float>::quiet_NaN(); }, "sky"},
        {"sun radius 90", [](vx::RenderSettings& s) { s.sun.angular_radius_degrees = 90.f; }, "sun"},
        {"NaN sun direction", [](vx::RenderSettings& s) { s.sun.direction.x = std::numeric_limits<float>::quiet_NaN(); }, "sun"},
        {"negative light", [](vx::RenderSettings& s) { s.light.emission = glm::vec3(-1.f); }, "area light"},
        {"NaN ev100", [](vx::RenderSettings& s) { s.exposure.ev100 = std::numeric_limits<float>::quiet_NaN(); }, "exposure"},
        {"negative adapt speed", [](vx::RenderSettings& s) { s.exposure.adapt_speed = -1.f; }, "exposure"},
        {"zero visibility", [](vx::RenderSettings& s) { s.haze.visibility = 0.f; }, "haze"},
        {"negative visibility", [](vx::RenderSettings& s) { s.haze.visibility = -100.f; }, "haze"},
        {"NaN visibility", [](vx::RenderSettings& s) { s.haze.visibility = std::nanf(""); }, "haze"},
        {"negative falloff", [](vx::RenderSettings& s) { s.haze.height_falloff = -0.001f; }, "haze"},
        {"infinite falloff", [](vx::RenderSettings& s) { s.haze.height_falloff = HUGE_VALF; }, "haze"},
        {"NaN base height", [](vx::RenderSettings& s) { s.haze.base_height = std::nan(""); }, "haze"},
        {"zero light cache pixels", [](vx::RenderSettings& s) { s.light_cache_pixels = 0.f; }, "light_cache_pixels"},
        {"NaN light cache pixels", [](vx::RenderSettings& s) { s.light_cache_pixels = std::nanf(""); }, "light_cache_pixels"},
        {"no denoise passes", [](vx::RenderSettings& s) { s.denoise_passes = 0; }, "denoise_passes"},
        {"nine denoise passes", [](vx::RenderSettings& s) { s.denoise_passes = 9; }, "denoise_passes"},
    };
    for (const Case& c : cases) {
        vx::RenderSettings s;
        c.change(s);
        const vx::Status r = e.set_render_settings(s);
        ASSERT_FALSE(r) << c.what;
        EXPECT_NE(r.error().find(c.message), std::string::npos) << c.what << ": " << r.error();
    }
    // The limits themselves are accepted.
    vx::RenderSettings edge;
    edge.shadow_samples = 1024;
    edge.max_bounces = 16;
    edge.accumulate = 1024;
    edge.sky_light = 0.f;
    edge.exposure.adapt_speed = 0.f;
    edge.haze.visibility = std::numeric_limits<float>::infinity(); // Clear air: no haze.
    edge.haze.height_falloff = 0.f;
    EXPECT_TRUE(e.set_render_settings(edge));
    for (uint32_t passes : {1u, 8u}) {
        edge.denoise_passes = passes;
        EXPECT_TRUE(e.set_render_settings(edge)) << passes << " denoise passes";
    }
}

TEST(FacadeChecks, CreateRefusesBlockMaterialsOutOfRange) {
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    struct Case {
        vx::BlockType block;
        const char* message;
    };
    const Case cases[] = {
        {{"paint", {2.f, -1.f, 0.5f}}, "albedo must be 0..1 per channel, got 2, -1, 0.5"},
        {{"paint", {0.5f, nan, 0.5f}}, "albedo must be 0..1"},
        {{"paint", {0.5f, 0.5f, 0.5f}, 1.5f}, "reflectivity must be 0..1, got 1.5"},
        {{"paint", {0.5f, 0.5f, 0.5f}, -0.1f}, "reflectivity must be 0..1"},
        {{"paint", {0.5f, 0.5f, 0.5f}, 0.f, {-1.f, 0.f, 0.f}}, "emission must be finite and >= 0"},
        {{"paint", {0.5f, 0.5f, 0.5f}, 0.f, {inf, 0.f, 0.f}}, "emission must be finite and >= 0"},
    };
    for (const Case& c : cases) {
        vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
        info.blocks = {{"rock", {0.4f, 0.4f, 0.4f}}, c.block};
        auto engine = vx::Engine::create(info);
        ASSERT_FALSE(engine) << c.message;
        // The block is named: its id and name.
        EXPECT_NE(engine.error().find("block type 2 ('paint')"), std::string::npos) << engine.error();
        EXPECT_NE(engine.error().find(c.message), std::string::npos) << engine.error();
    }
    // The edges of the ranges are fine: albedo 0 and 1, full mirror, a bright lamp.
    vx::EngineCreateInfo edges = tiny_info(vx::WorldSource::terrain(1));
    edges.blocks = {{"black", glm::vec3(0.f)}, {"white", glm::vec3(1.f), 1.f}, {"lamp", glm::vec3(1.f), 0.f, glm::vec3(1e4f)}};
    auto engine = vx::Engine::create(edges);
    EXPECT_TRUE(engine) << engine.error();
}

// Streaming delays are seconds >= 0 (infinity: never); the update budget is (0, 1000] ms, as it
// becomes integer nanoseconds (infinity once overflowed the conversion); worker threads 0..256
// (100,000 once aborted the process when the OS ran out of threads).
TEST(FacadeChecks, CreateRefusesStreamingSettingsOutOfRange) {
    for (int workers : {-1, 257, 100000}) {
        vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
        info.streaming.worker_threads = workers;
        const std::string error = error_of(vx::Engine::create(info));
        EXPECT_NE(error.find("worker_threads must be 0..256"), std::string::npos) << workers << ": " << error;
    }
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    for (double budget : {0.0, -1.0, nan, inf, 1e30, 1000.5}) {
        vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
        info.streaming.update_budget_ms = budget;
        const std::string error = error_of(vx::Engine::create(info));
        EXPECT_NE(error.find("update_budget_ms must be in (0, 1000]"), std::string::npos) << budget << ": " << error;
    }
    for (double delay : {-1.0, nan}) {
        vx::EngineCreateInfo unload = tiny_info(vx::WorldSource::terrain(1)), save = unload;
        unload.streaming.unload_delay_s = delay;
        save.streaming.save_delay_s = delay;
        EXPECT_NE(error_of(vx::Engine::create(unload)).find("streaming delays must be >= 0"), std::string::npos);
        EXPECT_NE(error_of(vx::Engine::create(save)).find("streaming delays must be >= 0"), std::string::npos);
    }
    // The edges: a budget of 1000 ms, and delays of infinity: an edit stays unsaved through
    // updates an hour apart until save() writes it.
    const std::string path = checks_world("never_saves");
    vx::EngineCreateInfo edges = tiny_info(vx::WorldSource::sqlite(path, 1));
    edges.streaming.update_budget_ms = 1000.0;
    edges.streaming.unload_delay_s = inf;
    edges.streaming.save_delay_s = inf;
    const std::unique_ptr<vx::Engine> engine = settled_above_origin(edges);
    ASSERT_NE(engine, nullptr);
    vx::Engine& e = *engine;
    const vx::BlockPos above{0, vx::terrain_height(1, 0, 0) + 4, 0}; // The viewer's block.
    ASSERT_TRUE(e.set_block(above, *e.find_block("stone")));
    const auto now = std::chrono::steady_clock::now();
    for (int hour = 1; hour <= 3; ++hour)
        e.update(now + std::chrono::hours(hour));
    EXPECT_EQ(e.stats().dirty_chunks, 1u);
    auto ticket = e.save();
    ASSERT_TRUE(ticket) << ticket.error();
    ASSERT_TRUE(e.wait(*ticket));
    EXPECT_EQ(e.stats().dirty_chunks, 0u);
}

// Derivations below: forward -z, up +y, so right = forward x up = +x. fov 90: tan(45°) = 1; a
// 200 x 100 frame has aspect 2. Pixel p maps to ndc = p / size * 2 - 1, y down, and the direction
// is forward + ndc.x * 1 * 2 * right - ndc.y * 1 * up, normalised.
TEST(FacadeChecks, ScreenRayFollowsTheRenderersCamera) {
    vx::Viewer v;
    v.block = {10, 20, 30};
    v.offset = {1.5, 0.25, -0.5}; // Whole blocks fold into the block, as set_viewer does.
    v.forward = {0, 0, -3};
    v.up = {0, 1, 0};
    v.fov_y_degrees = 90.f;
    const glm::uvec2 size{200, 100};
    auto centre = vx::screen_ray(v, {100, 50}, size);
    ASSERT_TRUE(centre) << centre.error();
    EXPECT_EQ(centre->origin_block, vx::BlockPos(11, 20, 29));
    EXPECT_NEAR(glm::length(centre->origin_offset - glm::dvec3(0.5, 0.25, 0.5)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(centre->direction - glm::dvec3(0, 0, -1)), 0.0, 1e-12);
    // The top edge's middle: ndc (0, -1): (0, 1, -1) / sqrt 2, 45° up (half the fov).
    auto top = vx::screen_ray(v, {100, 0}, size);
    ASSERT_TRUE(top);
    EXPECT_NEAR(glm::length(top->direction - glm::normalize(glm::dvec3(0, 1, -1))), 0.0, 1e-12);
    // The top-left corner: ndc (-1, -1): (-2, 1, -1) / sqrt 6 (the width follows the aspect).
    auto corner = vx::screen_ray(v, {0, 0}, size);
    ASSERT_TRUE(corner);
    EXPECT_NEAR(glm::length(corner->direction - glm::normalize(glm::dvec3(-2, 1, -1))), 0.0, 1e-12);
    // The bottom-right corner: ndc (1, 1): (2, -1, -1) / sqrt 6.
    auto bottom_right = vx::screen_ray(v, {200, 100}, size);
    ASSERT_TRUE(bottom_right);
    EXPECT_NEAR(glm::length(bottom_right->direction - glm::normalize(glm::dvec3(2, -1, -1))), 0.0, 1e-12);
    // Pixel (0, 0) is traced through its centre (0.5, 0.5), one pixel in from the corner.
    auto first = vx::screen_ray(v, {0.5, 0.5}, size);
    ASSERT_TRUE(first);
    EXPECT_NEAR(glm::length(first->direction - glm::normalize(glm::dvec3(-1.99, 0.99, -1))), 0.0, 1e-12);

    EXPECT_NE(error_of(vx::screen_ray(v, {1, 1}, {0, 10})).find("frame size"), std::string::npos);
    EXPECT_NE(error_of(vx::screen_ray(v, {std::nan(""), 1}, size)).find("finite"), std::string::npos);
    vx::Viewer bad = v;
    bad.fov_y_degrees = 200.f;
    EXPECT_NE(error_of(vx::screen_ray(bad, {1, 1}, size)).find("fov"), std::string::npos);

    // The engine's own needs a frame: none without a render target.
    auto engine = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    EXPECT_NE(error_of((*engine)->screen_ray({1, 1})).find("vx::screen_ray(viewer, pixel, frame_size)"),
              std::string::npos);
}

TEST(FacadeChecks, BlockRegistryReadsBack) {
    vx::EngineCreateInfo info = tiny_info(vx::WorldSource::terrain(1));
    info.blocks = {{"rock", {0.4f, 0.3f, 0.2f}}, {"glow", {1.f, 0.9f, 0.8f}, 0.25f, {5.f, 4.f, 3.f}, false}};
    auto engine = vx::Engine::create(info);
    ASSERT_TRUE(engine) << engine.error();
    const vx::Engine& e = **engine;
    EXPECT_EQ(e.block_count(), 2u);
    EXPECT_EQ(e.block_type(vx::kAir), std::nullopt);
    EXPECT_EQ(e.block_type(3), std::nullopt);
    auto rock = e.block_type(1);
    ASSERT_TRUE(rock);
    EXPECT_EQ(rock->name, "rock");
    EXPECT_EQ(rock->albedo, glm::vec3(0.4f, 0.3f, 0.2f));
    EXPECT_TRUE(rock->opaque);
    auto glow = e.block_type(*e.find_block("glow"));
    ASSERT_TRUE(glow);
    EXPECT_EQ(glow->name, "glow");
    EXPECT_EQ(glow->reflectivity, 0.25f);
    EXPECT_EQ(glow->emission, glm::vec3(5.f, 4.f, 3.f));
    EXPECT_FALSE(glow->opaque);

    // The default palette: every id named as default_blocks() lists it.
    auto defaults = vx::Engine::create(tiny_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(defaults) << defaults.error();
    const std::vector<vx::BlockType> palette = vx::default_blocks();
    ASSERT_EQ((*defaults)->block_count(), palette.size());
    for (size_t i = 0; i < palette.size(); ++i)
        EXPECT_EQ((*defaults)->block_type(vx::BlockId(i + 1))->name, palette[i].name);
}

} // namespace
