#pragma once
// The sandbox's GLFW input callbacks (keys, mouse buttons, cursor, wheel) and the two helpers the
// rest of the glue shares with them: cursor capture and the status-line message.
#include <string>

#include "app.h"

namespace sandbox {

// Hides the cursor for mouse look (the menu closed), or shows it with the menu open.
void set_captured(App& app, bool captured);
// Shows `text` on the status line and prints it; "" does nothing.
void say(App& app, const std::string& text);

// GLFW callbacks; the window's user pointer is the App.
void on_key(GLFWwindow* w, int key, int scancode, int action, int mods);
void on_mouse_button(GLFWwindow* w, int button, int action, int mods);
void on_cursor(GLFWwindow* w, double x, double y);
void on_scroll(GLFWwindow* w, double dx, double dy);

} // namespace sandbox
