// The sandbox's GLFW input callbacks: keys, mouse buttons, cursor motion and the wheel.
#include "input.h"

#include <cstdio>
#include <utility>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace sandbox {
namespace {

constexpr double kMouseDegreesPerPixel = 0.1;

App* app_of(GLFWwindow* w) { return static_cast<App*>(glfwGetWindowUserPointer(w)); }

} // namespace

void set_captured(App& app, bool captured) {
    if (!app.window) // Headless: no cursor to capture.
        return;
    app.captured = captured;
    app.menu = !captured;
    app.have_last = false;
    glfwSetInputMode(app.window, GLFW_CURSOR, captured ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
}

void say(App& app, const std::string& text) {
    if (text.empty())
        return;
    app.message = text;
    std::printf("vx_sandbox: %s\n", text.c_str());
}

void on_key(GLFWwindow* w, int key, int, int action, int) {
    App& app = *app_of(w);
    if (action == GLFW_REPEAT)
        return;
    const bool down = action == GLFW_PRESS;
    static const std::pair<int, const char*> kMove[] = {{GLFW_KEY_W, "w"},         {GLFW_KEY_A, "a"},
                                                        {GLFW_KEY_S, "s"},         {GLFW_KEY_D, "d"},
                                                        {GLFW_KEY_SPACE, "space"}, {GLFW_KEY_LEFT_SHIFT, "shift"}};
    for (auto [k, name] : kMove)
        if (key == k)
            app.game->key(name, down && app.captured);
    if (!down)
        return;
    if (key == GLFW_KEY_ESCAPE) {
        set_captured(app, app.menu); // The menu open: Esc resumes (Quit is in the menu, or Q).
    } else if (key == GLFW_KEY_Q && app.menu) {
        app.quit = true;
    } else if (key == GLFW_KEY_F) {
        say(app, app.game->toggle("walk"));
    } else if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
        app.game->hotbar().select(key - GLFW_KEY_1);
    } else if (key == GLFW_KEY_F1) {
        app.show_help = !app.show_help;
    } else if (key == GLFW_KEY_F2) {
        app.screenshot_now = true;
        app.screenshot_path = "vx_sandbox_" + std::to_string(app.frame) + ".png";
        app.screenshot_scripted = false;
    } else if (key == GLFW_KEY_F3) {
        app.show_stats = !app.show_stats;
    } else if (key == GLFW_KEY_G) {
        say(app, app.game->toggle("shadows"));
    } else if (key == GLFW_KEY_V) {
        // The swapchain is recreated at the next frame; the engine, its world and edits stay.
        app.opt.vsync = !app.opt.vsync;
        vx::Status s = app.engine->set_vsync(app.opt.vsync);
        say(app, !s ? s.error() : app.opt.vsync ? "vsync on" : "vsync off");
    } else if (key == GLFW_KEY_R) {
        say(app, app.game->toggle("reflections"));
    } else if (key == GLFW_KEY_N) {
        say(app, app.game->toggle("denoise"));
    } else if (key == GLFW_KEY_P) {
        say(app, app.game->toggle("raster"));
    }
}

void on_mouse_button(GLFWwindow* w, int button, int action, int) {
    App& app = *app_of(w);
    if (button >= 0 && button < 3) {
        app.mouse_down[size_t(button)] = action == GLFW_PRESS;
        app.mouse_pressed[size_t(button)] |= action == GLFW_PRESS;
    }
    if (action != GLFW_PRESS)
        return;
    if (!app.captured) {
        if (!app.ui->wants_mouse()) // A click beside the menu resumes; on it, the menu has it.
            set_captured(app, true);
        return;
    }
    const Button b = button == GLFW_MOUSE_BUTTON_LEFT ? Button::Left
                     : button == GLFW_MOUSE_BUTTON_RIGHT ? Button::Right : Button::Middle;
    say(app, app.game->click(b));
}

void on_cursor(GLFWwindow* w, double x, double y) {
    App& app = *app_of(w);
    if (app.captured && app.have_last)
        app.game->look(-(x - app.last_x) * kMouseDegreesPerPixel, -(y - app.last_y) * kMouseDegreesPerPixel);
    app.last_x = x;
    app.last_y = y;
    app.have_last = true;
}

void on_scroll(GLFWwindow* w, double, double dy) {
    App& app = *app_of(w);
    if (dy != 0)
        app.game->hotbar().scroll(dy > 0 ? -1 : 1);
}

} // namespace sandbox
