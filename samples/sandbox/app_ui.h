#pragma once
// The sandbox's per-frame feed of its UI (ui.h): ImGui's input from the window, the status line,
// the F3 stats lines and the F1 help, and the menu's actions applied.
#include <cstdint>
#include <string>
#include <vector>

#include "app.h"

namespace sandbox {

// The F3 lines, refreshed a few times a second.
std::vector<std::string> stats_lines(const App& app);
// This frame's UI: ImGui's input from the window, the menu's actions applied, the draw list to
// the engine.
void update_ui(App& app, uint32_t fb_w, uint32_t fb_h, double dt);

} // namespace sandbox
