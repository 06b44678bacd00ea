// The sandbox's per-frame UI feed: the stats and status lines, ImGui's input and the menu's actions.
#include "app_ui.h"

#include <cstdio>
#include <iterator>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "input.h"

namespace sandbox {
namespace {

UiView ui_view(const App& app) {
    const Game& g = *app.game;
    const vx::BlockId id = g.hotbar().selected_block();
    const std::string name = id >= 1 && id <= app.block_names.size() ? app.block_names[id - 1u] : std::to_string(id);
    UiView v;
    const char* vdb = app.opt.vdb.empty() ? "" : app.opt.read_only ? " | VDB read-only" : " | VDB + edits overlay";
    v.status = std::string(g.player().walking() ? "walk" : "fly") + " | " + name + vdb + " | " + g.save_text() +
               (app.message.empty() ? "" : " | " + app.message);
    if (app.show_stats)
        v.stats = app.stats;
    if (app.show_help)
        v.help.assign(std::begin(kHelpLines), std::end(kHelpLines));
    v.menu = app.menu;
    v.shadows = g.shadows();
    v.reflections = g.reflections();
    v.denoise = g.denoise();
    v.raster = g.raster();
    return v;
}

} // namespace

// The F3 lines, refreshed a few times a second.
std::vector<std::string> stats_lines(const App& app) {
    const vx::Stats s = app.engine->stats();
    char l[5][256];
    std::snprintf(l[0], sizeof l[0], "%.0f fps, %.1f ms a frame: update %.1f, render %.1f (wait %.1f, present %.1f)",
                  1000.0 / app.fps_ms, app.fps_ms, s.update_wall_ms, s.render_wall_ms, s.wait_ms, s.present_ms);
    std::snprintf(l[1], sizeof l[1], "GPU ms: BLAS %.2f, TLAS %.2f, trace %.2f (-1: no timestamps)", s.gpu_blas_ms,
                  s.gpu_tlas_ms, s.gpu_trace_ms);
    std::snprintf(l[2], sizeof l[2], "chunks %zu loaded, %zu queued, %zu/%zu meshed (%zu mesh jobs)", s.chunks_loaded,
                  s.chunks_queued, s.chunks_meshed, s.chunks_in_view, s.meshes_queued);
    std::snprintf(l[3], sizeof l[3], "BLAS this frame: %u builds, %u refits; %u chunks drawn; edit to screen %d frames",
                  s.blas_builds, s.blas_refits, s.instances, app.game->last_edit_to_screen());
    std::snprintf(l[4], sizeof l[4], "memory: blocks %.0f MB, GPU %.0f / %.0f MB", s.block_memory_bytes / 1048576.0,
                  s.gpu_memory_used_bytes / 1048576.0, s.gpu_memory_bytes / 1048576.0);
    std::string levels = "levels (drawn/kept): ";
    for (int k = 0; k <= s.lod_top_level; ++k) {
        char t[64];
        std::snprintf(t, sizeof t, "%s%d: %u/%u", k ? ", " : "", k, s.level_chunks_drawn[size_t(k)],
                      s.level_chunks_kept[size_t(k)]);
        levels += t;
    }
    char h[96];
    std::snprintf(h, sizeof h, "; holes %u, swaps %llu", s.holes, (unsigned long long)s.lod_swaps);
    return {l[0], l[1], l[2], l[3], l[4], levels + h};
}

// This frame's UI: ImGui's input from the window, the menu's actions applied, the draw list to
// the engine.
void update_ui(App& app, uint32_t fb_w, uint32_t fb_h, double dt) {
    UiInput in;
    in.width = fb_w;
    in.height = fb_h;
    in.dt = dt;
    in.mouse_free = app.window && !app.captured;
    if (in.mouse_free) {
        int win_w = 0, win_h = 0;
        glfwGetWindowSize(app.window, &win_w, &win_h); // Cursor: screen units; UI: pixels.
        double x = 0, y = 0;
        glfwGetCursorPos(app.window, &x, &y);
        in.mouse = {float(x * (win_w > 0 ? double(fb_w) / win_w : 1.0)), float(y * (win_h > 0 ? double(fb_h) / win_h : 1.0))};
    }
    for (size_t b = 0; b < 3; ++b)
        in.mouse_down[b] = app.mouse_down[b] || app.mouse_pressed[b];
    app.mouse_pressed = {};
    const UiActions act = app.ui->frame(in, app.game->hotbar(), ui_view(app));
    for (const std::string& t : act.toggles)
        say(app, app.game->toggle(t));
    if (act.resume)
        set_captured(app, true);
    if (act.quit)
        app.quit = true;
    if (vx::Status s = app.engine->set_ui(app.ui->draw_list()); !s)
        say(app, s.error());
}

} // namespace sandbox
