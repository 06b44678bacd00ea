// The hotbar (select, wheel wrap, pick) and the command line.
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "hotbar.h"
#include "options.h"

TEST(Hotbar, SelectScrollPick) {
    sandbox::Hotbar h; // Slots hold ids 1..9.
    EXPECT_EQ(h.selected_block(), 1);
    h.select(4);
    EXPECT_EQ(h.selected_block(), 5);
    h.select(9); // Out of range: ignored.
    EXPECT_EQ(h.selected_slot(), 4);
    h.scroll(5); // 4 + 5 = 9 wraps to 0.
    EXPECT_EQ(h.selected_slot(), 0);
    h.scroll(-1);
    EXPECT_EQ(h.selected_slot(), 8);
    h.pick(3); // Held in slot 2: select it.
    EXPECT_EQ(h.selected_slot(), 2);
    h.pick(42); // Not held: replaces the selected slot.
    EXPECT_EQ(h.selected_slot(), 2);
    EXPECT_EQ(h.selected_block(), 42);
    EXPECT_EQ(h.slot(3), 4);
    h.pick(0); // Air is never picked.
    EXPECT_EQ(h.selected_block(), 42);
}

TEST(Options, ParsesAndRejects) {
    auto o = sandbox::parse_options({"--size", "160x120", "--world", "/tmp/w.sqlite", "--seed", "7", "--replay",
                                     "r.txt", "--frames", "30", "--view-radius", "2", "--no-vsync", "--validation",
                                     "--view-distance", "4096"});
    ASSERT_TRUE(o) << o.error();
    EXPECT_EQ(o->width, 160u);
    EXPECT_EQ(o->height, 120u);
    EXPECT_EQ(o->world, "/tmp/w.sqlite");
    EXPECT_EQ(o->seed, 7u);
    EXPECT_EQ(o->frames, 30u);
    EXPECT_EQ(o->view_radius, 2);
    EXPECT_EQ(o->view_distance, 4096);
    EXPECT_EQ(sandbox::parse_options({})->view_distance, 2048) << "the default reaches 2,048 blocks";
    EXPECT_FALSE(o->vsync);
    EXPECT_TRUE(o->validation);
    for (auto bad : std::vector<std::vector<std::string>>{{"--size", "160"},
                                                          {"--size", "0x5"},
                                                          {"--seed", "-1"},
                                                          {"--view-radius", "0"},
                                                          {"--view-distance", "-1"},
                                                          {"--view-distance", "100000"},
                                                          {"--frames"},
                                                          {"--bogus", "1"},
                                                          {"--world", "a", "--vdb", "b"},
                                                          {"--world", "a", "--read-only"}}) {
        auto r = sandbox::parse_options(bad);
        EXPECT_FALSE(r) << bad[0];
    }
}

// Scripted outputs that cannot be written are refused before the world opens.
TEST(Options, OutputsThatCannotBeWrittenAreRefusedFirst) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_sandbox_outputs_test";
    std::filesystem::create_directories(dir);
    sandbox::Options o;
    EXPECT_TRUE(sandbox::check_outputs(o, {}));
    o.screenshot = (dir / "shot.png").string();
    o.stats_out = (dir / "stats.csv").string();
    EXPECT_TRUE(sandbox::check_outputs(o, {}));
    o.screenshot = dir.string();
    auto s = sandbox::check_outputs(o, {});
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("--screenshot"), std::string::npos) << s.error();
    o.screenshot.clear();
    o.stats_out = (dir / "no" / "stats.csv").string();
    s = sandbox::check_outputs(o, {});
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("--stats-out"), std::string::npos) << s.error();
    o.stats_out.clear();
    auto replay = sandbox::parse_replay("5 screenshot " + (dir / "missing" / "a.png").string() + "\n");
    ASSERT_TRUE(replay) << replay.error();
    s = sandbox::check_outputs(o, *replay);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("replay"), std::string::npos) << s.error();
    std::filesystem::remove_all(dir);
}

// --vdb plays with the edits overlay; --read-only keeps none.
TEST(Options, VdbWithOverlayOrReadOnly) {
    auto o = sandbox::parse_options({"--vdb", "w.vdb"});
    ASSERT_TRUE(o) << o.error();
    EXPECT_EQ(o->vdb, "w.vdb");
    EXPECT_FALSE(o->read_only);
    o = sandbox::parse_options({"--vdb", "w.vdb", "--read-only"});
    ASSERT_TRUE(o) << o.error();
    EXPECT_TRUE(o->read_only);
}

// A PostgreSQL world makes no folder (it made "postgresql:/host" in the current folder).
TEST(Options, OnlyAFileWorldMakesItsFolder) {
    EXPECT_EQ(sandbox::world_folder("/data/x/vx/worlds/default.sqlite"), "/data/x/vx/worlds");
    EXPECT_EQ(sandbox::world_folder("w.sqlite"), "");
    EXPECT_EQ(sandbox::world_folder("postgresql://host/db"), "");
    EXPECT_EQ(sandbox::world_folder("postgres://user@host:5432/db?sslmode=disable"), "");
}

TEST(Options, DefaultWorldUnderXdgDataHome) {
    setenv("XDG_DATA_HOME", "/data/x", 1);
    EXPECT_EQ(sandbox::default_world_path(), "/data/x/vx/worlds/default.sqlite");
    unsetenv("XDG_DATA_HOME");
    setenv("HOME", "/home/p", 1);
    EXPECT_EQ(sandbox::default_world_path(), "/home/p/.local/share/vx/worlds/default.sqlite");
}
