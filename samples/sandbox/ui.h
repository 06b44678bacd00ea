#pragma once
// The sandbox's on-screen UI in Dear ImGui (Debian's libimgui-dev 1.86), drawn by the engine
// through Engine::set_ui (the facade takes a plain triangle list, so no ImGui backend is needed):
// a crosshair (four arms around a free centre pixel, so screenshots show the world under it),
// the hotbar with the block colours and the selected slot framed, a status line, the F3 stats
// window, the F1 help window and the Esc menu (Resume, the render toggles, Quit). The game owns
// the window and feeds ImGui's input (display size, time step, mouse) here each frame.
// Main thread only (Dear ImGui's context is global state).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <vx/vx.h>

#include "hotbar.h"

struct ImGuiContext;

namespace sandbox {

// This frame's input for ImGui.
struct UiInput {
    uint32_t width = 0, height = 0;      // Framebuffer pixels.
    double dt = 1.0 / 60.0;              // Seconds since the last frame.
    bool mouse_free = false;             // The cursor is released (menu); else ImGui ignores it.
    glm::vec2 mouse{0.f};                // Framebuffer pixels.
    std::array<bool, 3> mouse_down{};    // Left, right, middle.
};

// What the UI shows.
struct UiView {
    std::string status;                  // One line: mode, block, save state, the last message.
    std::vector<std::string> stats;      // F3 lines (shown when not empty).
    std::vector<std::string> help;       // F1 lines (shown when not empty).
    bool menu = false;                   // The Esc menu.
    bool shadows = false, reflections = false, denoise = false, raster = false; // Menu toggles.
};

// What the user did in the menu this frame.
struct UiActions {
    bool resume = false, quit = false;
    std::vector<std::string> toggles;    // Game::toggle names: shadows, reflections, denoise, raster.
};

class Ui {
public:
    // `blocks`: the engine's palette (id i + 1 = blocks[i]), for the hotbar colours.
    explicit Ui(std::vector<vx::BlockType> blocks);
    ~Ui();
    Ui(const Ui&) = delete;
    Ui& operator=(const Ui&) = delete;

    // Hands the font atlas to `engine` (once per engine: Engine::set_ui_texture).
    vx::Status attach(vx::Engine& engine) const;
    // Builds this frame's UI; draw_list() then holds it for Engine::set_ui.
    UiActions frame(const UiInput& input, const Hotbar& hotbar, const UiView& view);
    const vx::UiDrawList& draw_list() const { return m_list; }
    // The mouse is over a UI window (a click goes to the UI, not the game).
    bool wants_mouse() const;

private:
    void draw_crosshair_and_hotbar(const UiInput& input, const Hotbar& hotbar, bool menu);
    UiActions draw_windows(const UiInput& input, const UiView& view);
    void convert();
    uint32_t block_colour(vx::BlockId id) const;

    std::vector<vx::BlockType> m_blocks;
    ImGuiContext* m_ctx = nullptr;
    int m_tex_w = 0, m_tex_h = 0;
    std::vector<uint8_t> m_texture; // RGBA8 font atlas.
    vx::UiDrawList m_list;
    int m_hotbar_top = 0; // Pixels: the hotbar's frame's top row this frame.
};

} // namespace sandbox
