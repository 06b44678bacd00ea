// vx::Engine: frames (the viewer's view traced by render::Renderer) and stats.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <vx/vx.h>

#include "engine/engine_impl.h"

namespace vx {

namespace {

using Clock = std::chrono::steady_clock;

render::Camera camera_of(const Viewer& v) {
    render::Camera cam;
    cam.block = v.block;
    cam.offset = glm::vec3(v.offset); // In 0..1 after set_viewer folded the whole blocks away.
    cam.forward = glm::vec3(v.forward);
    cam.up = glm::vec3(v.up);
    cam.fov_y_degrees = v.fov_y_degrees;
    return cam;
}

render::RenderSettings settings_of(const RenderSettings& s, const Viewer& v, uint32_t width, uint32_t height) {
    render::RenderSettings r;
    r.width = width;
    r.height = height;
    r.pipeline = s.pipeline == RenderSettings::Pipeline::Raster ? render::PipelineKind::Raster
                                                                 : render::PipelineKind::RayTraced;
    r.mode = s.shading == RenderSettings::Shading::Flat ? render::ShadingMode::Flat : render::ShadingMode::Full;
    r.shadow_samples = s.shadow_samples;
    r.bounce_shadow_samples = s.bounce_shadow_samples;
    r.max_bounces = s.max_bounces;
    r.sky = s.sky;
    r.sky_light = s.sky_light;
    r.sun.direction = s.sun.direction;
    r.sun.angular_radius_degrees = s.sun.angular_radius_degrees;
    r.sun.irradiance = s.sun.irradiance;
    r.denoise = s.denoise;
    r.accumulate = std::max(s.accumulate, 1u);
    r.light.block = s.light.follow_viewer ? v.block + s.light.corner : s.light.corner;
    r.light.offset = glm::vec3(0.f);
    r.light.edge_u = s.light.edge_u;
    r.light.edge_v = s.light.edge_v;
    r.light.emission = s.light.emission;
    r.exposure.ev100 = s.exposure.ev100;
    r.exposure.automatic = s.exposure.automatic;
    r.exposure.adapt_speed = s.exposure.adapt_speed;
    return r;
}


void record_frame_stats(Stats& f, const render::RenderStats& rs) {
    f.render_cpu_ms = rs.cpu_ms;
    f.gpu_ms = rs.gpu_ms;
    f.gpu_blas_ms = rs.gpu_blas_ms;
    f.gpu_tlas_ms = rs.gpu_tlas_ms;
    f.gpu_trace_ms = rs.gpu_trace_ms;
    f.frame_ms = rs.frame_ms;
    f.wait_ms = rs.wait_ms;
    f.present_ms = rs.present_ms;
    f.blas_builds = rs.blas_builds;
    f.blas_refits = rs.blas_refits;
    f.instances = rs.instances;
    f.triangles = rs.triangles;
    f.upload_bytes = rs.upload_bytes;
    f.failed_chunks = rs.failed_chunks;
    f.ev100 = rs.ev100;
}

bool usable_view(const Viewer& v) {
    const glm::dvec3 f = v.forward, u = v.up;
    const double cross = glm::length(glm::cross(glm::normalize(f), glm::normalize(u)));
    return glm::length(f) > 0 && glm::length(u) > 0 && std::isfinite(cross) && cross > 1e-6 &&
           v.fov_y_degrees > 0.f && v.fov_y_degrees < 180.f;
}

} // namespace

render::RenderSettings Engine::Impl::frame_settings(uint32_t width, uint32_t height) {
    render::RenderSettings r = settings_of(render_settings, viewer, width, height);
    r.sky_access = sky.get(streamer->world(), viewer.block, sink->world_changes());
    return r;
}

void Engine::set_render_settings(const RenderSettings& settings) { m->render_settings = settings; }

Status Engine::render_to_image(Image& out) {
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind != RenderTarget::Kind::Headless || !m->renderer)
        return Error{"render_to_image needs a headless render target (RenderTarget::headless)"};
    if (!usable_view(m->viewer))
        return Error{"the viewer's forward and up must be non-zero and not parallel, and its fov in (0, 180)"};
    const RenderTarget& t = m->info.render.target;
    const Clock::time_point t0 = Clock::now();
    render::RenderImage img = m->renderer->render(m->frame_settings(t.width, t.height), camera_of(m->viewer));
    m->frame.render_wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    out.width = img.width;
    out.height = img.height;
    out.rgba = std::move(img.rgba);
    record_frame_stats(m->frame, m->renderer->last_stats());
    return {};
}

Status Engine::render_to_window(Image* capture) {
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind != RenderTarget::Kind::Window || !m->renderer)
        return Error{"render_to_window needs a window render target (RenderTarget::glfw_window)"};
    if (!usable_view(m->viewer))
        return Error{"the viewer's forward and up must be non-zero and not parallel, and its fov in (0, 180)"};
    const Clock::time_point t0 = Clock::now();
    render::RenderImage img;
    // The size comes from the swapchain; settings' width and height are ignored there.
    auto done = m->renderer->present(m->frame_settings(1, 1), camera_of(m->viewer), capture ? &img : nullptr);
    if (!done)
        return Error{done.error()};
    m->frame.render_wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (*done == render::PresentResult::Skipped)
        return {};
    if (capture) {
        capture->width = img.width;
        capture->height = img.height;
        capture->rgba = std::move(img.rgba);
    }
    record_frame_stats(m->frame, m->renderer->last_stats());
    return {};
}

Status Engine::set_ui(const UiDrawList& ui) {
    if (Status s = m->alive(); !s)
        return s;
    if (!m->renderer)
        return Error{"set_ui needs a render target (headless or window)"};
    render::UiDrawList list;
    list.vertices.reserve(ui.vertices.size());
    for (const UiVertex& v : ui.vertices)
        list.vertices.push_back({v.pos, v.uv, v.rgba});
    list.indices = ui.indices;
    list.cmds.reserve(ui.cmds.size());
    for (const UiDrawCmd& c : ui.cmds)
        list.cmds.push_back({c.index_offset, c.index_count, c.clip_rect});
    if (std::string why = render::ui_draw_list_error(list); !why.empty())
        return Error{"set_ui: " + why};
    m->renderer->set_ui(std::move(list));
    return {};
}

Status Engine::set_ui_texture(uint32_t width, uint32_t height, std::span<const uint8_t> rgba) {
    if (Status s = m->alive(); !s)
        return s;
    if (!m->renderer)
        return Error{"set_ui_texture needs a render target (headless or window)"};
    if (width == 0 || height == 0 || width > 16384 || height > 16384 || rgba.size() != size_t(width) * height * 4)
        return Error{"set_ui_texture: the texture must be 1..16384 texels a side and width * height * 4 bytes"};
    m->renderer->set_ui_texture(width, height, std::vector<uint8_t>(rgba.begin(), rgba.end()));
    return {};
}

Stats Engine::stats() const {
    Stats s = m->frame;
    if (m->streamer) {
        const engine::StreamingMetrics sm = m->streamer->metrics();
        s.chunks_loaded = sm.loaded;
        s.chunks_queued = sm.pending_data;
        s.chunks_meshed = sm.meshed;
        s.chunks_in_view = sm.wanted_meshes;
        s.meshes_queued = sm.pending_meshes;
        s.dirty_chunks = sm.dirty;
        s.chunks_unloaded = sm.unloaded + sm.evicted;
        s.block_memory_bytes = sm.block_bytes;
        s.store_connected = sm.store.connected;
        s.store_pending_edits = sm.store.pending_edits;
        s.store_conflicts = sm.store.conflicts;
        s.store_reconnects = sm.store.reconnects;
        s.chunks_reloaded = sm.reloaded;
    }
    if (m->renderer) {
        const render::GpuHeapStats mem = m->renderer->memory_stats();
        s.gpu_memory_bytes = mem.held_bytes;
        s.gpu_memory_used_bytes = mem.used_bytes;
        s.validation_errors = m->renderer->validation_errors();
    }
    return s;
}

Status write_png(const std::string& path, const Image& image) {
    if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
        return Error{"write_png: the image is empty or its pixel count does not match its size"};
    render::RenderImage img;
    img.width = image.width;
    img.height = image.height;
    img.rgba = image.rgba;
    return render::write_png(path, img);
}

} // namespace vx
