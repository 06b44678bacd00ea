#include "game.h"

#include <algorithm>
#include <cmath>

namespace sandbox {

Game::Game(vx::Engine& engine, bool persistent, double fly_speed)
    : m_engine(&engine), m_persistent(persistent) {
    m_player.params().fly_speed = fly_speed;
    // The settings chosen from the moving-camera curves (vx::RenderSettings::recommended): 1
    // shadow sample, 1 per bounce, the denoiser with 8 frames of history.
    m_settings = vx::RenderSettings::recommended();
    m_shadow_samples = m_settings.shadow_samples;
    m_bounces = m_settings.max_bounces;
    m_engine->set_render_settings(m_settings);
}

void Game::set_pose(glm::dvec3 eye, double yaw, double pitch) {
    m_player.set_eye(eye);
    m_yaw = yaw;
    m_pitch = std::clamp(pitch, -89.0, 89.0);
}

void Game::look(double dyaw, double dpitch) {
    m_yaw = std::fmod(m_yaw + dyaw, 360.0);
    m_pitch = std::clamp(m_pitch + dpitch, -89.0, 89.0);
}

void Game::key(const std::string& name, bool down) {
    if (name == "w") m_keys.w = down;
    else if (name == "a") m_keys.a = down;
    else if (name == "s") m_keys.s = down;
    else if (name == "d") m_keys.d = down;
    else if (name == "space") m_keys.space = down;
    else if (name == "shift") m_keys.shift = down;
    else if (name == "f" && down) toggle("walk");
}

vx::Viewer Game::viewer() const {
    const glm::dvec3 eye = m_player.eye();
    vx::Viewer v;
    v.block = vx::BlockPos(glm::floor(eye));
    v.offset = eye - glm::floor(eye);
    v.forward = view_forward(m_yaw, m_pitch);
    v.velocity = m_player.velocity();
    return v;
}

std::optional<vx::RayHit> Game::crosshair() const {
    const vx::Viewer v = viewer();
    auto hit = m_engine->raycast(v.block, v.offset, v.forward, kReach);
    if (!hit || hit->kind != vx::RayHit::Kind::Hit)
        return std::nullopt;
    return *hit;
}

std::string Game::click(Button button) {
    const auto hit = crosshair();
    if (!hit)
        return "";
    vx::Status s;
    if (button == Button::Middle) {
        m_hotbar.pick(hit->id);
        return "";
    }
    if (button == Button::Left)
        s = m_engine->set_block(hit->block, vx::kAir);
    else if (m_player.overlaps_block(hit->previous) || hit->inside)
        return "cannot place a block inside the player";
    else
        s = m_engine->set_block(hit->previous, m_hotbar.selected_block());
    if (!s)
        return s.error();
    m_edit_frames = 0;
    m_edited_since_save = true;
    return "";
}

std::string Game::toggle(const std::string& name) {
    bool on = false;
    if (name == "shadows") {
        if (m_settings.shadow_samples > 0)
            m_shadow_samples = m_settings.shadow_samples;
        m_settings.shadow_samples = m_settings.shadow_samples > 0 ? 0 : m_shadow_samples;
        on = shadows();
    } else if (name == "reflections") {
        if (m_settings.max_bounces > 0)
            m_bounces = m_settings.max_bounces;
        m_settings.max_bounces = m_settings.max_bounces > 0 ? 0 : m_bounces;
        on = reflections();
    } else if (name == "denoise") {
        m_settings.denoise = !m_settings.denoise;
        on = denoise();
    } else if (name == "raster") {
        m_settings.pipeline = raster() ? vx::RenderSettings::Pipeline::RayTraced : vx::RenderSettings::Pipeline::Raster;
        on = raster();
    } else if (name == "walk") {
        m_player.set_walking(!m_player.walking());
        return m_player.walking() ? "walk mode" : "fly mode";
    } else {
        return name + ": unknown toggle";
    }
    m_engine->set_render_settings(m_settings);
    return name + (on ? " on" : " off");
}

void Game::step(double dt) {
    const glm::dvec3 fwd = view_forward(m_yaw, 0.0), right = view_right(m_yaw);
    MoveIntent in;
    in.wish = fwd * double(m_keys.w - m_keys.s) + right * double(m_keys.d - m_keys.a);
    if (glm::length(in.wish) > 1.0)
        in.wish = glm::normalize(in.wish);
    in.wish.y = double(m_keys.space - m_keys.shift);
    in.jump = m_keys.space;
    const SolidQuery solid = [this](vx::BlockPos p) {
        const auto id = m_engine->get_block(p);
        return !id || *id != vx::kAir; // Unloaded counts as solid: never fall out of the world.
    };
    m_player.step(dt, in, solid);
    if (m_player.walking() && m_player.inside_solid(solid))
        ++m_frames_inside;
    (void)m_engine->set_viewer(viewer()); // Fails only outside the world: the camera stays put.
}

FrameFigures Game::after_frame(uint64_t frame, double frame_ms) {
    const vx::Stats s = m_engine->stats();
    FrameFigures f;
    f.frame = frame;
    f.frame_ms = frame_ms;
    f.update_ms = s.update_wall_ms;
    f.render_ms = s.render_wall_ms;
    f.update_cpu_ms = s.update_cpu_ms;
    f.render_cpu_ms = s.render_cpu_ms;
    f.gpu_ms = s.gpu_ms;
    f.chunks_loaded = s.chunks_loaded;
    f.chunks_in_view = s.chunks_in_view;
    f.chunks_meshed = s.chunks_meshed;
    f.builds = s.blas_builds;
    f.refits = s.blas_refits;
    f.holes = s.holes;
    f.gpu_mb = double(s.gpu_memory_bytes) / 1048576.0;
    for (int k = 1; k <= s.lod_top_level; ++k)
        f.coarse_drawn += s.level_chunks_drawn[size_t(k)];
    if (m_edit_frames >= 0) {
        ++m_edit_frames; // This frame was rendered after the edit call.
        if (s.upload_bytes > 0 && s.blas_refits + s.blas_builds > 0) {
            f.edit_to_screen = m_last_edit_to_screen = m_edit_frames;
            m_edit_frames = -1;
        }
    }
    return f;
}

void Game::maybe_save(double now_s) {
    constexpr double kSaveInterval = 5.0;
    if (!m_persistent || !m_edited_since_save || now_s - m_last_save_s < kSaveInterval)
        return;
    if (m_save && m_engine->save_state(*m_save) == vx::SaveState::Pending)
        return;
    auto ticket = m_engine->save();
    if (ticket) {
        m_save = *ticket;
        m_edited_since_save = false;
    }
    m_last_save_s = now_s;
}

std::string Game::save_text() const {
    if (!m_persistent)
        return "read-only";
    if (m_edited_since_save)
        return "unsaved edits";
    if (!m_save)
        return "saved";
    switch (m_engine->save_state(*m_save)) {
    case vx::SaveState::Pending: return "saving";
    case vx::SaveState::Durable: return "saved";
    case vx::SaveState::Failed: return "save failed";
    case vx::SaveState::Unknown: return "";
    }
    return "";
}

} // namespace sandbox
