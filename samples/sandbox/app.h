#pragma once
// The vx_sandbox executable's state, shared by its GLFW glue (sandbox_main.cpp, input.cpp,
// app_ui.cpp): options, window, engine, game, the replay's position, UI and screenshot state.
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <vx/vx.h>

#include "game.h"
#include "options.h"
#include "replay.h"
#include "ui.h"

struct GLFWwindow;

namespace sandbox {

inline constexpr const char* kHelpLines[] = {
    "mouse look, WASD move, space/shift rise/sink (fly) or jump (walk), F walk/fly",
    "left click remove, right click place, middle click pick, 1-9 and wheel: hotbar",
    "F1 help, F2 screenshot, F3 stats, G shadows, R reflections, N denoiser, P raster, V vsync",
    "Esc menu",
};

struct App {
    Options opt;
    GLFWwindow* window = nullptr;
    std::unique_ptr<vx::Engine> engine;
    std::unique_ptr<Game> game;
    std::vector<ReplayCommand> replay;
    size_t next_command = 0;
    uint64_t frame = 0;
    std::FILE* csv = nullptr;
    bool captured = false, menu = false, show_stats = false, show_help = false, quit = false;
    std::vector<std::string> stats;       // F3 lines, refreshed 4 times a second.
    std::vector<std::string> block_names; // Id i + 1 = block_names[i].
    std::unique_ptr<Ui> ui;
    // Mouse buttons for the UI (left, right, middle): held, and pressed since the last frame (a
    // press and release within one poll still reaches ImGui as a click).
    std::array<bool, 3> mouse_down{}, mouse_pressed{};
    bool screenshot_now = false;
    bool screenshot_failed = false; // A scripted screenshot (--screenshot, a replay's) not written.
    bool screenshot_scripted = false; // The pending one is scripted (F2's: no exit code).
    bool last_frame_shot = false;     // --screenshot was taken in the last frame of --frames.
    DeviceLossPolicy loss_policy;     // Renderers recreated since the last frame drawn.
    std::string screenshot_path;
    std::string message;
    double last_x = 0, last_y = 0;
    bool have_last = false;
    double fps_ms = 16.7;
};

} // namespace sandbox
