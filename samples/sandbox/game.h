#pragma once
// The sandbox's game state on top of <vx/vx.h>: the player and camera, the held keys, the
// hotbar, block edits at the crosshair, render toggles, background saves and the per-frame
// figures. No window code: the GLFW glue (sandbox_main.cpp, input.cpp) and the replay feed it the same
// inputs. Main thread only (it drives the engine).
#include <cstdint>
#include <optional>
#include <string>

#include <vx/vx.h>

#include "hotbar.h"
#include "player_physics.h"

namespace sandbox {

enum class Button : uint8_t { Left, Right, Middle };

// Held movement keys.
struct Keys {
    bool w = false, a = false, s = false, d = false, space = false, shift = false;
};

// One frame's figures (a row of --stats-out).
struct FrameFigures {
    uint64_t frame = 0;
    double frame_ms = 0, update_ms = 0, render_ms = 0, gpu_ms = -1;
    double update_cpu_ms = 0, render_cpu_ms = 0; // Main-thread CPU: update(), recording the frame.
    size_t chunks_loaded = 0;
    size_t chunks_in_view = 0, chunks_meshed = 0; // Equal: no holes in the view.
    uint32_t builds = 0, refits = 0;
    uint32_t holes = 0;        // vx::Stats::holes: top-level chunks in view with nothing drawn.
    uint32_t coarse_drawn = 0; // Chunks of levels >= 1 drawn.
    double gpu_mb = 0;         // Device memory the renderer holds (vx::Stats::gpu_memory_bytes), MiB.
    int edit_to_screen = -1; // Frames from an edit call to the frame that uploaded it; -1: none ended here.
};

// When to give a lost GPU device another renderer: after each loss, unless this many renderers
// in a row were lost again before drawing a frame (a failure that persists, such as a swapchain
// the window cannot have: recreating every frame would never end). Main thread.
class DeviceLossPolicy {
public:
    static constexpr int kMaxInARow = 3;
    // Any other failed frame (out of GPU memory for it, say) is tried again next frame, up to this
    // many in a row (about 2 s at 60 Hz): embedding.md's advice, where the sandbox once quit.
    static constexpr int kMaxFailedFrames = 120;
    // A frame failed on a lost device: true to recreate the renderer, false to give up.
    bool recreate() { return ++m_in_a_row <= kMaxInARow; }
    // A frame failed otherwise: true to go on to the next frame, false to give up.
    bool try_next_frame() { return ++m_failed_frames <= kMaxFailedFrames; }
    void frame_drawn() { m_in_a_row = m_failed_frames = 0; }

private:
    int m_in_a_row = 0;
    int m_failed_frames = 0;
};

class Game {
public:
    static constexpr double kReach = 8.0; // Blocks: how far the crosshair edits.

    Game(vx::Engine& engine, bool persistent, double fly_speed);

    // Camera: eye position (world blocks) and angles in degrees (see view_forward).
    void set_pose(glm::dvec3 eye, double yaw, double pitch);
    void look(double dyaw, double dpitch);
    double yaw() const { return m_yaw; }
    double pitch() const { return m_pitch; }
    const Player& player() const { return m_player; }

    // A key by replay name (w a s d space shift f); f toggles walk mode on press.
    void key(const std::string& name, bool down);
    // Left removes, right places (never inside the player), middle picks. Returns a message for
    // the screen ("" when nothing to say).
    std::string click(Button button);
    // shadows, reflections, denoise (the ray tracer's denoiser), raster (the raster pipeline in
    // place of the ray tracer), walk. Returns the message ("shadows off", "walk mode").
    std::string toggle(const std::string& name);
    Hotbar& hotbar() { return m_hotbar; }
    const Hotbar& hotbar() const { return m_hotbar; }
    // Selects a block id directly (into the current slot).
    void select_block(vx::BlockId id) { m_hotbar.pick(id); }

    // Advances the player by dt seconds and hands the camera to the engine.
    void step(double dt);
    // After a frame was rendered: the frame's figures (edit-to-screen tracked here).
    FrameFigures after_frame(uint64_t frame, double frame_ms);
    // Every save_interval seconds of play: starts a background save if none is in flight.
    void maybe_save(double now_s);
    // Text for the save state: "saved", "saving", "unsaved edits", "read-only".
    std::string save_text() const;
    // Walk-mode frames that ended with a solid block inside the player's box (should stay 0).
    uint64_t frames_inside_block() const { return m_frames_inside; }
    int last_edit_to_screen() const { return m_last_edit_to_screen; }
    bool shadows() const { return m_settings.shadow_samples > 0; }
    bool reflections() const { return m_settings.max_bounces > 0; }
    bool denoise() const { return m_settings.denoise; }
    bool raster() const { return m_settings.pipeline == vx::RenderSettings::Pipeline::Raster; }

private:
    vx::Viewer viewer() const;
    std::optional<vx::RayHit> crosshair() const;

    vx::Engine* m_engine; // Not owned.
    bool m_persistent;
    Player m_player;
    Hotbar m_hotbar;
    Keys m_keys;
    double m_yaw = 0, m_pitch = -20;
    vx::RenderSettings m_settings;
    uint32_t m_shadow_samples = 0, m_bounces = 0; // Restored when toggled back on (the constructor's).
    int m_edit_frames = -1;        // Frames since an edit whose upload is not seen yet; -1: none.
    int m_last_edit_to_screen = -1;
    std::optional<vx::SaveTicket> m_save;
    double m_last_save_s = 0;
    bool m_edited_since_save = false;
    uint64_t m_frames_inside = 0;
};

} // namespace sandbox
