// vx_sandbox: a block game on <vx/vx.h> — fly or walk through the ray-traced world streaming
// around you, remove and place blocks, scripted play (--replay) for tests and benchmarks.
// This file is the GLFW glue: window, the frame loop, the replay driver, screenshots and the
// per-frame CSV; the state is in app.h, the input callbacks in input.*, the UI feed in app_ui.*.
// The game logic lives in game.*, player_physics.*, hotbar.*, replay.* and options.*.
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <vx/vx.h>

#include "app.h"
#include "app_ui.h"
#include "game.h"
#include "input.h"
#include "options.h"
#include "replay.h"
#include "ui.h"

namespace sandbox {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kReplayStep = 1.0 / 60.0; // Seconds of game time per replay frame.

// Runs until every chunk in view is meshed, without advancing game time. False after 10 minutes.
bool wait_loaded(App& app, Clock::time_point game_now) {
    const auto limit = Clock::now() + std::chrono::minutes(10);
    while (Clock::now() < limit) {
        app.engine->update(game_now);
        if (app.engine->settled())
            return true;
        glfwPollEvents();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

// Runs this frame's replay commands. Returns false when the game must stop with an error.
bool run_replay_commands(App& app, Clock::time_point game_now) {
    while (app.next_command < app.replay.size() && app.replay[app.next_command].frame <= app.frame) {
        const ReplayCommand& c = app.replay[app.next_command++];
        using K = ReplayCommand::Kind;
        switch (c.kind) {
        case K::Pose: app.game->set_pose({c.pose[0], c.pose[1], c.pose[2]}, c.pose[3], c.pose[4]); break;
        case K::Key:
            if (c.name == "escape")
                app.menu = c.down ? !app.menu : app.menu;
            else if (c.name == "f1")
                app.show_help = c.down ? !app.show_help : app.show_help;
            else if (c.name == "f3")
                app.show_stats = c.down ? !app.show_stats : app.show_stats;
            else
                app.game->key(c.name, c.down);
            break;
        case K::Click:
            say(app, app.game->click(c.name == "left" ? Button::Left : c.name == "right" ? Button::Right : Button::Middle));
            break;
        case K::Select: app.game->hotbar().select(c.value - 1); break;
        case K::Block: app.game->select_block(vx::BlockId(c.value)); break;
        case K::Toggle: say(app, app.game->toggle(c.name)); break;
        case K::WaitLoaded:
            app.game->step(0.0); // Hand the current pose to the engine first.
            if (!wait_loaded(app, game_now)) {
                std::fprintf(stderr, "vx_sandbox: replay line %d: the view did not load within 10 minutes\n", c.line);
                return false;
            }
            break;
        case K::Screenshot:
            app.screenshot_now = true;
            app.screenshot_path = c.name;
            app.screenshot_scripted = true;
            break;
        case K::Quit: app.quit = true; break;
        }
    }
    return true;
}

vx::Result<std::unique_ptr<vx::Engine>> create_engine(const Options& o, GLFWwindow* window) {
    vx::EngineCreateInfo info;
    if (!o.vdb.empty()) {
        info.world = vx::WorldSource::vdb(o.vdb);
        info.world.read_only = o.read_only; // Else edits go to "<file>.edits.sqlite".
    } else {
        std::error_code ec; // A folder that cannot be made shows as the world's open error.
        if (const std::string folder = world_folder(o.world); !folder.empty())
            std::filesystem::create_directories(folder, ec);
        info.world = vx::WorldSource::sqlite(o.world, o.seed);
    }
    info.streaming.view_radius = o.view_radius;
    info.streaming.view_radius_vertical = std::max(1, std::min(o.view_radius, 4));
    info.streaming.view_distance = o.view_distance;
    info.render.target =
        window ? vx::RenderTarget::glfw_window(window) : vx::RenderTarget::headless(o.width, o.height);
    info.render.device = o.device;
    info.render.validation = o.validation;
    info.render.vsync = o.vsync && o.replay.empty(); // Replays run as fast as they can.
    return vx::Engine::create(info);
}

bool write_csv_row(std::FILE* f, const FrameFigures& r) {
    return std::fprintf(f, "%llu,%.3f,%.3f,%.3f,%.3f,%zu,%u,%u,%d,%zu,%zu,%.3f,%.3f,%u,%u,%.1f\n", (unsigned long long)r.frame,
                        r.frame_ms, r.update_ms, r.render_ms, r.gpu_ms, r.chunks_loaded, r.builds, r.refits,
                        r.edit_to_screen, r.chunks_in_view, r.chunks_meshed, r.update_cpu_ms, r.render_cpu_ms, r.holes,
                        r.coarse_drawn, r.gpu_mb) > 0;
}

// Writes the pending screenshot and says so (with the crosshair pixel: tests and demos compare it
// across screenshots); a scripted one not written makes the exit 1.
void write_screenshot(App& app, const vx::Image& shot) {
    app.screenshot_now = false;
    if (vx::Status s = vx::write_png(app.screenshot_path, shot); !s) {
        say(app, s.error());
        app.screenshot_failed |= app.screenshot_scripted;
        return;
    }
    const glm::u8vec4 c = shot.at(shot.width / 2, shot.height / 2);
    say(app, "screenshot " + app.screenshot_path + " centre " + std::to_string(c.r) + " " + std::to_string(c.g) +
                 " " + std::to_string(c.b));
}

// --screenshot when the run ended before a last frame with --frames took it (a replay's quit, a
// closed window): one more frame of the world as it is. It was silently never written.
void last_frame_screenshot(App& app) {
    if (app.opt.screenshot.empty() || app.last_frame_shot)
        return;
    app.screenshot_path = app.opt.screenshot;
    app.screenshot_scripted = true;
    vx::Image shot;
    const vx::Status drawn = app.window ? app.engine->render_to_window(&shot) : app.engine->render_to_image(shot);
    if (!drawn) {
        say(app, "--screenshot: " + drawn.error());
        app.screenshot_failed = true;
        return;
    }
    write_screenshot(app, shot);
}

// The frame loop. Returns the exit code.
int run(App& app) {
    const Clock::time_point start = Clock::now();
    Clock::time_point last = start;
    double next_title_s = 0;
    const bool replaying = !app.opt.replay.empty();
    while ((!app.window || !glfwWindowShouldClose(app.window)) && !app.quit) {
        if (app.window)
            glfwPollEvents();
        const Clock::time_point now = Clock::now();
        const double real_dt = std::chrono::duration<double>(now - last).count();
        last = now;
        const double dt = replaying ? kReplayStep : std::min(real_dt, 0.1);
        const double game_s = replaying ? double(app.frame) * kReplayStep : std::chrono::duration<double>(now - start).count();
        const Clock::time_point game_now = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(game_s));
        if (replaying && !run_replay_commands(app, game_now))
            return 1;
        if (app.quit)
            break;
        if (app.opt.frames > 0 && app.frame + 1 == app.opt.frames && !app.opt.screenshot.empty()) {
            app.screenshot_now = true;
            app.screenshot_path = app.opt.screenshot;
            app.screenshot_scripted = true;
            app.last_frame_shot = true;
        }
        app.game->step(app.menu && !replaying ? 0.0 : dt);
        app.engine->update(game_now);
        int fb_w = int(app.opt.width), fb_h = int(app.opt.height); // Headless: the image size.
        if (app.window)
            glfwGetFramebufferSize(app.window, &fb_w, &fb_h);
        if (fb_w > 0 && fb_h > 0)
            update_ui(app, uint32_t(fb_w), uint32_t(fb_h), replaying ? kReplayStep : real_dt);
        if (app.quit)
            break;
        vx::Image shot;
        const bool capture = app.screenshot_now;
        // Headless (--headless): traced into memory every frame, the UI drawn over it as well.
        vx::Status drawn = app.window ? app.engine->render_to_window(capture ? &shot : nullptr)
                                      : app.engine->render_to_image(shot);
        if (vx::Status s = drawn; !s) {
            std::fprintf(stderr, "vx_sandbox: %s\n", s.error().c_str());
            // A lost GPU device: a new renderer, the world and every edit kept; another failure:
            // the next frame; either given up when it persists (DeviceLossPolicy).
            if (!app.engine->stats().device_lost) {
                if (!app.loss_policy.try_next_frame())
                    return 1;
                continue;
            }
            if (!app.loss_policy.recreate())
                return 1;
            if (vx::Status r = app.engine->recreate_renderer(); !r) {
                std::fprintf(stderr, "vx_sandbox: %s\n", r.error().c_str());
                return 1;
            }
            say(app, "the GPU device was lost: renderer recreated");
            continue;
        }
        app.loss_policy.frame_drawn();
        if (capture)
            write_screenshot(app, shot);
        const double frame_ms = real_dt * 1000.0;
        app.fps_ms = app.fps_ms * 0.9 + frame_ms * 0.1;
        const FrameFigures fig = app.game->after_frame(app.frame, frame_ms);
        if (app.csv)
            write_csv_row(app.csv, fig);
        app.game->maybe_save(game_s);
        const double real_s = std::chrono::duration<double>(now - start).count();
        if (real_s >= next_title_s) {
            app.stats = stats_lines(app);
            next_title_s = real_s + 0.25;
        }
        ++app.frame;
        if (app.opt.frames > 0 && app.frame >= app.opt.frames)
            break;
    }
    last_frame_screenshot(app);
    return 0;
}

int finish(App& app, int code) {
    const uint32_t errors = app.engine->stats().validation_errors;
    if (vx::Status s = app.engine->shutdown(); !s) {
        std::fprintf(stderr, "vx_sandbox: saving the world failed: %s\n", s.error().c_str());
        code = code ? code : 1;
    }
    if (app.csv) { // Buffered rows reach the file here: a full disk shows at ferror or fclose.
        const bool written = std::ferror(app.csv) == 0;
        if (std::fclose(app.csv) != 0 || !written) {
            std::fprintf(stderr, "vx_sandbox: cannot write --stats-out %s: %s\n", app.opt.stats_out.c_str(),
                         std::strerror(errno));
            code = code ? code : 1;
        }
        app.csv = nullptr;
    }
    const glm::dvec3 feet = app.game->player().feet();
    std::printf("vx_sandbox: player's feet at %.2f %.2f %.2f (%s)\n", feet.x, feet.y, feet.z,
                app.game->player().walking() ? "walk" : "fly");
    std::printf("vx_sandbox: %llu frames, edit->screen %d frames, frames inside a block %llu, validation errors: %u\n",
                (unsigned long long)app.frame, app.game->last_edit_to_screen(),
                (unsigned long long)app.game->frames_inside_block(), errors);
    if (app.opt.validation && errors > 0)
        code = code ? code : 1;
    if (app.screenshot_failed)
        code = code ? code : 1;
    return code;
}

GLFWwindow* create_window(const Options& o) {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    GLFWmonitor* monitor = o.fullscreen ? glfwGetPrimaryMonitor() : nullptr;
    int w = int(o.width), h = int(o.height);
    if (monitor) {
        const GLFWvidmode* mode = glfwGetVideoMode(monitor);
        w = mode->width;
        h = mode->height;
    }
    return glfwCreateWindow(w, h, "vx_sandbox", monitor, nullptr);
}

} // namespace

// --headless: the replay without a window or GLFW (figures on a GPU host with no display).
int main_headless(App& app) {
    auto engine = create_engine(app.opt, nullptr);
    if (!engine) {
        std::fprintf(stderr, "vx_sandbox: %s\n", engine.error().c_str());
        return 2;
    }
    app.engine = std::move(*engine);
    for (const vx::BlockType& b : vx::default_blocks())
        app.block_names.push_back(b.name);
    app.ui = std::make_unique<Ui>(vx::default_blocks());
    if (vx::Status s = app.ui->attach(*app.engine); !s) {
        std::fprintf(stderr, "vx_sandbox: %s\n", s.error().c_str());
        return 2;
    }
    app.game = std::make_unique<Game>(*app.engine, !app.opt.read_only, app.opt.fly_speed);
    const int64_t ground = vx::terrain_height(app.opt.seed, 0, 0);
    app.game->set_pose({0.5, double(ground) + 6.0, 0.5}, 0.0, -20.0);
    if (!app.opt.stats_out.empty()) {
        app.csv = std::fopen(app.opt.stats_out.c_str(), "w");
        if (!app.csv) {
            std::fprintf(stderr, "vx_sandbox: cannot write %s\n", app.opt.stats_out.c_str());
            return 2;
        }
        std::fprintf(app.csv, "frame,frame_ms,update_ms,render_ms,gpu_ms,chunks,builds,refits,edit_to_screen,in_view,meshed,update_cpu_ms,render_cpu_ms,holes,coarse_drawn,gpu_mb\n");
    }
    return finish(app, run(app));
}

int main_with(const Options& opt) {
    App app;
    app.opt = opt;
    if (opt.replay.empty()) {
        if (vx::Status s = check_outputs(opt, {}); !s) {
            std::fprintf(stderr, "vx_sandbox: %s\n", s.error().c_str());
            return 2;
        }
    } else {
        auto parsed = load_replay(opt.replay);
        if (!parsed) {
            std::fprintf(stderr, "vx_sandbox: %s\n", parsed.error().c_str());
            return 2;
        }
        app.replay = std::move(*parsed);
        if (vx::Status s = check_outputs(opt, app.replay); !s) {
            std::fprintf(stderr, "vx_sandbox: %s\n", s.error().c_str());
            return 2;
        }
        if (opt.headless && opt.frames == 0 && !replay_quits(app.replay)) {
            std::fprintf(stderr, "vx_sandbox: --headless: %s has no 'quit' line and no --frames N was given, so "
                                 "it would never end\n", opt.replay.c_str());
            return 2;
        }
    }
    if (opt.headless)
        return main_headless(app);
    if (glfwInit() != GLFW_TRUE) {
        std::fprintf(stderr, "vx_sandbox: cannot open a window (GLFW: no display?)\n");
        return 2;
    }
    if (glfwVulkanSupported() != GLFW_TRUE) {
        std::fprintf(stderr, "vx_sandbox: no Vulkan driver found, so no device can ray trace here\n");
        glfwTerminate();
        return 2;
    }
    app.window = create_window(opt);
    if (!app.window) {
        std::fprintf(stderr, "vx_sandbox: cannot create a %ux%u window\n", opt.width, opt.height);
        glfwTerminate();
        return 2;
    }
    int code = 0;
    {
        auto engine = create_engine(opt, app.window);
        if (!engine) {
            std::fprintf(stderr, "vx_sandbox: %s\n", engine.error().c_str()); // E.g. no device that can ray trace.
            glfwDestroyWindow(app.window);
            glfwTerminate();
            return 2;
        }
        app.engine = std::move(*engine);
        for (const vx::BlockType& b : vx::default_blocks())
            app.block_names.push_back(b.name);
        app.ui = std::make_unique<Ui>(vx::default_blocks());
        (void)app.ui->attach(*app.engine); // Cannot fail: a window target and a valid atlas.
        app.game = std::make_unique<Game>(*app.engine, !opt.read_only, opt.fly_speed);
        const int64_t ground = vx::terrain_height(opt.seed, 0, 0);
        app.game->set_pose({0.5, double(ground) + 6.0, 0.5}, 0.0, -20.0);
        std::printf("vx_sandbox: seed %llu, terrain top at (0, %lld, 0)\n", (unsigned long long)opt.seed, (long long)ground);
        if (!opt.stats_out.empty()) {
            app.csv = std::fopen(opt.stats_out.c_str(), "w");
            if (!app.csv) {
                std::fprintf(stderr, "vx_sandbox: cannot write %s\n", opt.stats_out.c_str());
                code = 2;
            } else
                std::fprintf(app.csv, "frame,frame_ms,update_ms,render_ms,gpu_ms,chunks,builds,refits,edit_to_screen,in_view,meshed,update_cpu_ms,render_cpu_ms,holes,coarse_drawn,gpu_mb\n");
        }
        glfwSetWindowUserPointer(app.window, &app);
        glfwSetKeyCallback(app.window, on_key);
        glfwSetMouseButtonCallback(app.window, on_mouse_button);
        glfwSetCursorPosCallback(app.window, on_cursor);
        glfwSetScrollCallback(app.window, on_scroll);
        if (opt.replay.empty()) {
            set_captured(app, true);
            for (const char* l : kHelpLines)
                std::printf("%s\n", l);
        }
        code = code ? finish(app, code) : finish(app, run(app));
        app.game.reset();
        app.ui.reset();
        app.engine.reset();
    }
    glfwDestroyWindow(app.window);
    glfwTerminate();
    return code;
}

} // namespace sandbox

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            std::printf("%s", sandbox::usage());
            return 0;
        }
    auto opt = sandbox::parse_options(args);
    if (!opt) {
        std::fprintf(stderr, "%s\n%s", opt.error().c_str(), sandbox::usage());
        return 2;
    }
    return sandbox::main_with(*opt);
}
