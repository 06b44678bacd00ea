// The game state on a real engine without a GPU (RenderTarget::none, built-in terrain or a
// SQLite world in a temporary folder): the crosshair places and removes blocks, never inside the
// player; middle click picks; toggles answer; walking never ends inside terrain; edits of a
// persistent world reach a durable save.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

#include <unistd.h>

#include <gtest/gtest.h>

#include "facade_test_util.h"
#include "game.h"

namespace {

using vx::test::settle;

using Clock = std::chrono::steady_clock;
constexpr uint64_t kSeed = 3;

std::unique_ptr<vx::Engine> make_engine(vx::WorldSource world) {
    vx::EngineCreateInfo info;
    info.world = std::move(world);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 1;
    auto e = vx::Engine::create(info);
    EXPECT_TRUE(e) << (e ? "" : e.error());
    return e ? std::move(*e) : nullptr;
}

// Eye 4.5 blocks above the terrain top at (0, 0), looking straight down.
void look_down(sandbox::Game& g, vx::Engine& e, double height_above = 4.5) {
    const double top = double(vx::terrain_height(kSeed, 0, 0));
    g.set_pose({0.5, top + height_above, 0.5}, 0, -89);
    g.step(0);
    ASSERT_TRUE(settle(e));
}

} // namespace

TEST(Game, PlacesRemovesAndPicksAtTheCrosshair) {
    auto e = make_engine(vx::WorldSource::terrain(kSeed));
    ASSERT_TRUE(e);
    sandbox::Game g(*e, false, 10.0);
    look_down(g, *e);
    const int64_t top = vx::terrain_height(kSeed, 0, 0);
    const vx::BlockPos ground{0, top, 0}, above{0, top + 1, 0};
    ASSERT_NE(e->get_block(ground).value_or(0), vx::kAir);
    ASSERT_EQ(e->get_block(above).value_or(1), vx::kAir);

    g.hotbar().select(7); // Slot 8: lamp.
    EXPECT_EQ(g.click(sandbox::Button::Right), "");
    EXPECT_EQ(e->get_block(above), std::optional<vx::BlockId>(8));
    g.hotbar().select(0);
    g.click(sandbox::Button::Middle); // Picks the lamp: selects its slot.
    EXPECT_EQ(g.hotbar().selected_block(), 8);
    EXPECT_EQ(g.click(sandbox::Button::Left), "");
    EXPECT_EQ(e->get_block(above), std::optional<vx::BlockId>(vx::kAir));

    EXPECT_TRUE(g.denoise()); // The game's default.
    EXPECT_EQ(g.toggle("denoise"), "denoise off");
    EXPECT_FALSE(g.denoise());
    EXPECT_EQ(g.toggle("raster"), "raster on");
    EXPECT_TRUE(g.raster());
    EXPECT_EQ(g.toggle("raster"), "raster off");
    EXPECT_EQ(g.toggle("fog"), "fog: unknown toggle");
    EXPECT_EQ(g.toggle("shadows"), "shadows off");
    EXPECT_EQ(g.toggle("shadows"), "shadows on");
    EXPECT_EQ(g.save_text(), "read-only");
}

TEST(Game, NeverPlacesInsideThePlayer) {
    auto e = make_engine(vx::WorldSource::terrain(kSeed));
    ASSERT_TRUE(e);
    sandbox::Game g(*e, false, 10.0);
    // Eye 2.5 above the ground top face: feet at +0.88 of the block above the ground, so that
    // block overlaps the player's box.
    look_down(g, *e, 2.5);
    const int64_t top = vx::terrain_height(kSeed, 0, 0);
    EXPECT_EQ(g.click(sandbox::Button::Right), "cannot place a block inside the player");
    EXPECT_EQ(e->get_block({0, top + 1, 0}), std::optional<vx::BlockId>(vx::kAir));
}

TEST(Game, WalkingOnTerrainNeverEndsInsideABlock) {
    auto e = make_engine(vx::WorldSource::terrain(kSeed));
    ASSERT_TRUE(e);
    sandbox::Game g(*e, false, 10.0);
    look_down(g, *e, 6.0);
    g.toggle("walk");
    g.key("w", true);
    g.key("space", true);
    const glm::dvec3 start = g.player().feet();
    double farthest = 0; // Horizontal blocks from the start.
    for (int i = 0; i < 600; ++i) {
        if (i % 120 == 0)
            g.look(70, 0); // Turn now and then: walks into slopes from several sides.
        g.step(1.0 / 60.0);
        e->update();
        const glm::dvec3 d = g.player().feet() - start;
        farthest = std::max(farthest, glm::length(glm::dvec2(d.x, d.z)));
    }
    EXPECT_EQ(g.frames_inside_block(), 0u);
    EXPECT_TRUE(g.player().walking());
    EXPECT_GT(farthest, 5.0) << "the player did not walk";
}

TEST(Game, EditsOfAPersistentWorldBecomeDurable) {
    const auto dir = std::filesystem::temp_directory_path() / ("vx_sandbox_game_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
        auto e = make_engine(vx::WorldSource::sqlite((dir / "w.sqlite").string(), kSeed));
        ASSERT_TRUE(e);
        sandbox::Game g(*e, true, 10.0);
        look_down(g, *e);
        EXPECT_EQ(g.save_text(), "saved");
        ASSERT_EQ(g.click(sandbox::Button::Right), "");
        EXPECT_EQ(g.save_text(), "unsaved edits");
        g.maybe_save(10.0); // Past the save interval: a background save starts.
        const auto limit = Clock::now() + std::chrono::minutes(1);
        while (g.save_text() != "saved" && Clock::now() < limit) {
            e->update();
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        EXPECT_EQ(g.save_text(), "saved");
        ASSERT_TRUE(e->shutdown());
    }
    std::filesystem::remove_all(dir);
}

// A device lost again before any frame is drawn, time after time, ends the game (exit 1) after
// DeviceLossPolicy::kMaxInARow renderers; one frame drawn between losses starts the count again.
// Every failed Vulkan call now reads as a lost device, and a failure that persists made the
// sandbox recreate its renderer in every frame forever.
TEST(DeviceLossPolicy, GivesUpOnlyOnLossesInARow) {
    using sandbox::DeviceLossPolicy;
    DeviceLossPolicy p;
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < DeviceLossPolicy::kMaxInARow; ++i)
            EXPECT_TRUE(p.recreate()) << round << " " << i;
        p.frame_drawn();
    }
    for (int i = 0; i < DeviceLossPolicy::kMaxInARow; ++i)
        EXPECT_TRUE(p.recreate());
    EXPECT_FALSE(p.recreate());
    EXPECT_FALSE(p.recreate());
}

// A frame that fails for another reason (no GPU memory for it) is tried again next frame, as
// embedding.md advises: the sandbox quit on the first. A failure that persists still ends it.
TEST(DeviceLossPolicy, OtherFailedFramesAreRetriedUntilTheyPersist) {
    using sandbox::DeviceLossPolicy;
    DeviceLossPolicy p;
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < DeviceLossPolicy::kMaxFailedFrames; ++i)
            ASSERT_TRUE(p.try_next_frame()) << round << " " << i;
        p.frame_drawn();
    }
    for (int i = 0; i < DeviceLossPolicy::kMaxFailedFrames; ++i)
        ASSERT_TRUE(p.try_next_frame());
    EXPECT_FALSE(p.try_next_frame());
}
