// The replay parser: every command parses into the right fields; bad lines are rejected with a
// message naming the line number and quoting the line.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "replay.h"

using sandbox::is_replay_key;
using sandbox::load_replay;
using sandbox::parse_replay;
using sandbox::replay_quits;
using Kind = sandbox::ReplayCommand::Kind;

TEST(Replay, ParsesEveryCommand) {
    const char* text = "# a demo\n"
                       "0 pose 1.5 70 -2 90 -10.5\n"
                       "\n"
                       "0 wait-loaded   # comment after a command\n"
                       "3 key w down\n"
                       "3 key shift up\n"
                       "4 click right\n"
                       "5 select 3\n"
                       "5 block 11\n"
                       "6 toggle denoise\n"
                       "7 screenshot out/a.png\n"
                       "9 quit\n";
    auto r = parse_replay(text);
    ASSERT_TRUE(r) << r.error();
    ASSERT_EQ(r->size(), 10u);
    const auto& c = *r;
    EXPECT_EQ(c[0].kind, Kind::Pose);
    EXPECT_DOUBLE_EQ(c[0].pose[0], 1.5);
    EXPECT_DOUBLE_EQ(c[0].pose[2], -2.0);
    EXPECT_DOUBLE_EQ(c[0].pose[4], -10.5);
    EXPECT_EQ(c[0].line, 2);
    EXPECT_EQ(c[1].kind, Kind::WaitLoaded);
    EXPECT_EQ(c[1].line, 4);
    EXPECT_EQ(c[2].kind, Kind::Key);
    EXPECT_EQ(c[2].name, "w");
    EXPECT_TRUE(c[2].down);
    EXPECT_FALSE(c[3].down);
    EXPECT_EQ(c[4].kind, Kind::Click);
    EXPECT_EQ(c[4].name, "right");
    EXPECT_EQ(c[4].frame, 4u);
    EXPECT_EQ(c[5].kind, Kind::Select);
    EXPECT_EQ(c[5].value, 3);
    EXPECT_EQ(c[6].kind, Kind::Block);
    EXPECT_EQ(c[6].value, 11);
    EXPECT_EQ(c[7].name, "denoise");
    EXPECT_EQ(c[8].kind, Kind::Screenshot);
    EXPECT_EQ(c[8].name, "out/a.png");
    EXPECT_EQ(c[9].kind, Kind::Quit);
    EXPECT_EQ(c[9].frame, 9u);
}

TEST(Replay, BadLinesNameTheLine) {
    struct Case {
        const char* text;
        const char* expect; // Part of the message.
    };
    const Case cases[] = {
        {"0 pose 1 2 3 4\n", "replay line 1: pose takes 5"},
        {"0 pose 1 2 x 4 5\n", "pose wants 5 numbers"},
        {"# ok\n0 quit\n1 jump\n", "replay line 3: unknown command 'jump': 1 jump"},
        {"5 quit\n4 quit\n", "replay line 2: frame 4 is before frame 5"},
        {"x pose 1 2 3 4 5\n", "replay line 1: expected FRAME"},
        {"-1 quit\n", "replay line 1"},
        {"0 key q down\n", "unknown key 'q'"},
        {"0 key f2 down\n", "unknown key 'f2'"},
        {"0 key w pressed\n", "down or up"},
        {"0 click up\n", "left, right or middle"},
        {"0 select 0\n", "slot 1..9"},
        {"0 select 10\n", "slot 1..9"},
        {"0 block 0\n", "id 1..65535"},
        {"0 toggle fog\n", "toggle wants"},
        {"0 quit now\n", "quit takes 0"},
        {"0 screenshot\n", "screenshot takes 1"},
        {"7\n", "expected FRAME COMMAND"},
        {"0 pose 1 2 3 nan 5\n", "pose wants 5 numbers"},
        // Outside the streamed world: the engine refused the viewer and the game went on silently.
        {"0 pose 1e300 100 0.5 0 -10\n", "inside the streamed world"},
        {"0 pose 0 -68719345665 0 0 0\n", "inside the streamed world"},
        {"0 pose 0 0 68719345664 0 0\n", "inside the streamed world"},
        {"0 pose 0 0 0 1e300 0\n", "yaw and pitch"},
    };
    for (const Case& c : cases) {
        auto r = parse_replay(c.text);
        ASSERT_FALSE(r) << c.text;
        EXPECT_NE(r.error().find(c.expect), std::string::npos) << r.error();
    }
}

TEST(Replay, UiKeysAreReplayKeys) {
    for (const char* k : {"escape", "f1", "f3"})
        EXPECT_TRUE(is_replay_key(k)) << k;
    EXPECT_FALSE(is_replay_key("f2")); // Screenshots have their own command.
    auto r = parse_replay("0 key f3 down\n0 key f1 up\n");
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ((*r)[0].name, "f3");
    EXPECT_FALSE((*r)[1].down);
}

TEST(Replay, EmptyAndCommentOnlyFilesAreEmptyReplays) {
    auto r = parse_replay("# nothing\n\n   \n");
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->empty());
}

// A headless replay without a `quit` would run for ever (vx_sandbox refuses it without --frames).
TEST(Replay, QuitsOnlyWithAQuitLine) {
    EXPECT_FALSE(replay_quits({}));
    auto r = parse_replay("0 pose 0 40 0 0 0\n10 key w down\n");
    ASSERT_TRUE(r);
    EXPECT_FALSE(replay_quits(*r));
    r = parse_replay("0 pose 0 40 0 0 0\n10 quit\n");
    ASSERT_TRUE(r);
    EXPECT_TRUE(replay_quits(*r));
}

// A folder opens as an ifstream and reads as an empty replay: refused, saying so.
TEST(Replay, AFolderIsNotAReplay) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_replay_folder_test";
    std::filesystem::create_directories(dir);
    auto r = load_replay(dir.string());
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("folder"), std::string::npos) << r.error();
    EXPECT_FALSE(load_replay((dir / "missing.txt").string()));
    std::ofstream(dir / "ok.txt") << "5 quit\n";
    r = load_replay((dir / "ok.txt").string());
    ASSERT_TRUE(r) << r.error();
    EXPECT_TRUE(replay_quits(*r));
    std::filesystem::remove_all(dir);
}
