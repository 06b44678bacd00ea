// vx::Engine: frames (the viewer's view traced by render::Renderer) and stats.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <vx/vx.h>

#include "engine/engine_impl.h"
#include "engine/engine_testing.h"

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
    r.samples_by_weight = s.samples_by_weight;
    r.weight_exponent = s.weight_exponent;
    r.split_hits = s.split_hits;
    r.max_bounces = s.max_bounces;
    r.sky = s.sky;
    r.sky_light = s.sky_light;
    r.sun.direction = s.sun.direction; // Any finite length: the renderer normalises it in double.
    r.sun.angular_radius_degrees = s.sun.angular_radius_degrees;
    r.sun.irradiance = s.sun.irradiance;
    r.denoise = s.denoise;
    r.denoise_passes = s.denoise_passes;
    r.emitter_sampling = s.emitter_sampling;
    r.light_cache = s.light_cache;
    r.light_cache_pixels = s.light_cache_pixels;
    r.accumulate = std::max(s.accumulate, 1u);
    r.light.block = s.light.follow_viewer ? v.block + s.light.corner : s.light.corner;
    r.light.offset = glm::vec3(0.f);
    r.light.edge_u = s.light.edge_u;
    r.light.edge_v = s.light.edge_v;
    r.light.emission = s.light.emission;
    r.exposure.ev100 = s.exposure.ev100;
    r.exposure.automatic = s.exposure.automatic;
    r.exposure.adapt_speed = s.exposure.adapt_speed;
    r.haze.enabled = s.haze.enabled;
    r.haze.visibility = s.haze.visibility;
    r.haze.height_falloff = s.haze.height_falloff;
    r.haze.base_height = s.haze.base_height;
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
    for (size_t k = 0; k < f.level_gpu_bytes.size(); ++k)
        f.level_gpu_bytes[k] = rs.level_gpu_bytes[k];
    f.ev100 = rs.ev100;
}

render::UiDrawList to_render(const UiDrawList& ui) {
    render::UiDrawList list;
    list.vertices.reserve(ui.vertices.size());
    for (const UiVertex& v : ui.vertices)
        list.vertices.push_back({v.pos, v.uv, v.rgba});
    list.indices = ui.indices;
    list.cmds.reserve(ui.cmds.size());
    for (const UiDrawCmd& c : ui.cmds)
        list.cmds.push_back({c.index_offset, c.index_count, c.clip_rect});
    return list;
}

} // namespace

render::RenderSettings Engine::Impl::frame_settings(uint32_t width, uint32_t height) {
    render::RenderSettings r = settings_of(render_settings, viewer, width, height);
    r.sky_access = sky.get(streamer->world(), viewer.block, sink->world_changes());
    r.eye_block = streamer->world().get_block(viewer.block); // Under water: the view is tinted by it.
    return r;
}

namespace {

bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool non_negative3(glm::vec3 v) { return finite3(v) && v.x >= 0.f && v.y >= 0.f && v.z >= 0.f; }

// Why `s` cannot be rendered, or success: checked where the game hands it over, not frames later.
Status check_render_settings(const RenderSettings& s) {
    constexpr uint32_t kMaxSamples = 1024, kMaxBounces = render::kMaxMirrorBounces, kMaxAccumulate = 1024;
    if (s.shadow_samples > kMaxSamples || s.bounce_shadow_samples.value_or(0) > kMaxSamples)
        return Error{"render settings: shadow samples must be 0.." + std::to_string(kMaxSamples)};
    if (!render::weight_exponent_valid(s.weight_exponent))
        return Error{"render settings: weight_exponent must be in (0, 1]"};
    if (s.max_bounces > kMaxBounces)
        return Error{"render settings: max_bounces must be 0.." + std::to_string(kMaxBounces)};
    if (s.accumulate < 1 || s.accumulate > kMaxAccumulate)
        return Error{"render settings: accumulate must be 1.." + std::to_string(kMaxAccumulate)};
    if (!non_negative3(s.sky) || !std::isfinite(s.sky_light) || s.sky_light < 0.f)
        return Error{"render settings: sky and sky_light must be finite and >= 0"};
    if (!finite3(s.sun.direction) || !non_negative3(s.sun.irradiance) ||
        !(s.sun.angular_radius_degrees >= 0.f && s.sun.angular_radius_degrees < 90.f))
        return Error{"render settings: the sun needs a finite direction, irradiance >= 0 and a radius of 0..90 degrees"};
    if (glm::dvec3(s.sun.direction) == glm::dvec3(0.0) && s.sun.irradiance != glm::vec3(0.f))
        return Error{"render settings: the sun's direction is zero (irradiance 0 turns the sun off)"};
    // An edge of 2^20 blocks keeps the light's area (their cross product) finite in float: edges
    // of 1e20 made it infinite, so the ray tracer dropped the light and the raster drew black.
    constexpr double kMaxLightEdge = double(1 << 20);
    if (!finite3(s.light.edge_u) || !finite3(s.light.edge_v) || !non_negative3(s.light.emission) ||
        glm::length(glm::dvec3(s.light.edge_u)) > kMaxLightEdge || glm::length(glm::dvec3(s.light.edge_v)) > kMaxLightEdge)
        return Error{"render settings: the area light needs edges of at most 2^20 blocks and emission >= 0"};
    if (!std::isfinite(s.exposure.ev100) || !std::isfinite(s.exposure.adapt_speed) || s.exposure.adapt_speed < 0.f)
        return Error{"render settings: exposure ev100 must be finite and adapt_speed finite and >= 0"};
    if (!(s.haze.visibility > 0.f) || !std::isfinite(s.haze.height_falloff) || s.haze.height_falloff < 0.f ||
        !std::isfinite(s.haze.base_height))
        return Error{"render settings: haze visibility must be > 0 (infinity: none), height_falloff finite and >= 0, "
                     "base_height finite"};
    if (!render::light_cache_pixels_valid(s.light_cache_pixels))
        return Error{"render settings: light_cache_pixels must be 1/64..4096"};
    static_assert(RenderSettings{}.denoise_passes == render::kDefaultDenoisePasses);
    if (s.denoise_passes < 1 || s.denoise_passes > render::kMaxDenoisePasses)
        return Error{"render settings: denoise_passes must be 1..8"};
    return {};
}

} // namespace

Status Engine::set_render_settings(const RenderSettings& settings) {
    const engine::CallGuard call(m->calls, "set_render_settings");
    if (!call)
        return call.error();
    if (Status s = check_render_settings(settings); !s)
        return s;
    m->render_settings = settings;
    return {};
}

Status Engine::render_to_image(Image& out) {
    const engine::CallGuard call(m->calls, "render_to_image");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind != RenderTarget::Kind::Headless)
        return Error{"render_to_image needs a headless render target (RenderTarget::headless)"};
    if (Status s = m->renderer_usable(); !s)
        return s;
    const RenderTarget& t = m->info.render.target;
    const Clock::time_point t0 = Clock::now();
    Result<render::RenderImage> img = m->renderer->try_render(m->frame_settings(t.width, t.height), camera_of(m->viewer));
    if (!img)
        return m->frame_failed(img.error());
    m->frame.render_wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    out.width = img->width;
    out.height = img->height;
    out.rgba = std::move(img->rgba);
    record_frame_stats(m->frame, m->renderer->last_stats());
    return {};
}

Status Engine::render_to_window(Image* capture) {
    const engine::CallGuard call(m->calls, "render_to_window");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind != RenderTarget::Kind::Window)
        return Error{"render_to_window needs a window render target (RenderTarget::glfw_window)"};
    if (Status s = m->renderer_usable(); !s)
        return s;
    const Clock::time_point t0 = Clock::now();
    render::RenderImage img;
    // The size comes from the swapchain; settings' width and height are ignored there.
    auto done = m->renderer->present(m->frame_settings(1, 1), camera_of(m->viewer), capture ? &img : nullptr);
    if (!done)
        return m->frame_failed(done.error());
    m->frame.render_wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (*done == render::PresentResult::Skipped)
        return {};
    if (capture) {
        capture->width = img.width;
        capture->height = img.height;
        capture->rgba = std::move(img.rgba);
    }
    record_frame_stats(m->frame, m->renderer->last_stats());
    m->window_frame_size = {m->renderer->last_stats().present_width, m->renderer->last_stats().present_height};
    return {};
}

Result<ScreenRay> Engine::screen_ray(glm::dvec2 pixel) const {
    const engine::CallGuard call(m->calls, "screen_ray");
    if (!call)
        return Error{call.error().error()};
    if (Status s = m->alive(); !s)
        return Error{s.error()};
    const RenderTarget& t = m->info.render.target;
    switch (t.kind) {
    case RenderTarget::Kind::None:
        break;
    case RenderTarget::Kind::Headless:
        return vx::screen_ray(m->viewer, pixel, {t.width, t.height});
    case RenderTarget::Kind::Window:
        if (m->window_frame_size.x == 0 || m->window_frame_size.y == 0)
            return Error{"screen_ray: no frame presented yet (the window's size is not known)"};
        return vx::screen_ray(m->viewer, pixel, m->window_frame_size);
    }
    return Error{"screen_ray: no render target (RenderTarget::none): use vx::screen_ray(viewer, pixel, frame_size)"};
}

Status Engine::set_ui(const UiDrawList& ui) {
    const engine::CallGuard call(m->calls, "set_ui");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind == RenderTarget::Kind::None)
        return Error{"set_ui needs a render target (headless or window)"};
    render::UiDrawList list = to_render(ui);
    if (std::string why = render::ui_draw_list_error(list); !why.empty())
        return Error{"set_ui: " + why};
    if (Status s = m->renderer_usable(); !s)
        return s;
    m->ui = ui; // Kept, so a recreated renderer gets it again.
    m->renderer->set_ui(std::move(list));
    return {};
}

Status Engine::set_ui_texture(uint32_t width, uint32_t height, std::span<const uint8_t> rgba) {
    const engine::CallGuard call(m->calls, "set_ui_texture");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind == RenderTarget::Kind::None)
        return Error{"set_ui_texture needs a render target (headless or window)"};
    if (width == 0 || height == 0 || width > 16384 || height > 16384 || rgba.size() != size_t(width) * height * 4)
        return Error{"set_ui_texture: the texture must be 1..16384 texels a side and width * height * 4 bytes"};
    if (Status s = m->renderer_usable(); !s)
        return s;
    // Kept, so a recreated renderer gets it again.
    m->ui_texture_width = width;
    m->ui_texture_height = height;
    m->ui_texture.assign(rgba.begin(), rgba.end());
    if (Status s = m->renderer->set_ui_texture(width, height, m->ui_texture); !s)
        return m->frame_failed("set_ui_texture: " + s.error());
    return {};
}

Status Engine::set_vsync(bool vsync) {
    const engine::CallGuard call(m->calls, "set_vsync");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind != RenderTarget::Kind::Window)
        return Error{"set_vsync needs a window render target (RenderTarget::glfw_window)"};
    m->info.render.vsync = vsync; // A recreated renderer keeps it (also one made after a failed recreate).
    if (m->renderer)
        m->renderer->set_vsync(vsync);
    return {};
}

Status Engine::Impl::resend_ui() {
    if (!ui.cmds.empty())
        renderer->set_ui(to_render(ui));
    if (!ui_texture.empty())
        return renderer->set_ui_texture(ui_texture_width, ui_texture_height, ui_texture);
    return {};
}

Status Engine::Impl::renderer_usable() {
    if (!renderer)
        return Error{"no renderer: the last recreate_renderer() failed; call it again"};
    if (renderer->device_lost())
        return frame_failed("");
    return {};
}

Status Engine::Impl::frame_failed(const std::string& why) {
    if (!renderer->device_lost())
        return Error{why};
    if (!loss_counted)
        ++frame.device_losses;
    loss_counted = true;
    return Error{"the GPU device was lost: call recreate_renderer(); the world, the streaming and every edit are "
                 "kept (save() and shutdown() still work)"};
}

Stats Engine::stats() const {
    const engine::CallGuard call(m->calls, "stats");
    if (!call)
        return Stats{};
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
        s.store_listener_down = sm.store.listener_down;
        s.chunks_reloaded = sm.reloaded;
        s.chunks_generate_failed = sm.generate_failed;
        s.generate_failures = sm.generate_failures;
        s.level_chunks_kept[0] = uint32_t(sm.loaded);
        s.level_block_bytes[0] = sm.block_bytes;
        // Without LOD, a hole is a chunk of the view not meshed yet (failed ones stay holes).
        s.holes = uint32_t(sm.wanted_meshes - std::min(sm.wanted_meshes, sm.meshed));
        s.level_chunks_drawn[0] = uint32_t(sm.meshed);
    }
    if (m->lod) {
        const engine::LodMetrics lm = m->lod->metrics();
        s.lod_top_level = lm.top_level;
        for (int k = 0; k < kLodLevels; ++k) {
            s.level_chunks_drawn[size_t(k)] = lm.drawn[size_t(k)];
            if (k > 0) {
                s.level_chunks_kept[size_t(k)] = lm.kept[size_t(k)];
                s.level_block_bytes[size_t(k)] = lm.block_bytes[size_t(k)];
            }
        }
        s.holes = lm.holes;
        s.lod_swaps = lm.swaps;
    }
    if (m->renderer) {
        const render::GpuHeapStats mem = m->renderer->memory_stats();
        s.gpu_memory_bytes = mem.held_bytes;
        s.gpu_memory_used_bytes = mem.used_bytes;
        s.validation_errors = m->validation_errors_before + m->renderer->validation_errors();
        s.device_lost = m->renderer->device_lost();
        s.vsync = m->renderer->vsync();
    } else if (m->info.render.target.kind != RenderTarget::Kind::None && !m->shut_down) {
        s.device_lost = true; // A recreate_renderer() failed: frames fail until one succeeds.
    }
    return s;
}

bool EngineTesting::lose_device(Engine& e) {
    if (!e.m->renderer)
        return false;
    e.m->renderer->simulate_device_loss();
    return true;
}

int EngineTesting::noted_edits(Engine& e) { return e.m->renderer ? int(e.m->renderer->noted_edits()) : -1; }

bool EngineTesting::fail_allocations(Engine& e, const std::string& name_prefix) {
    if (!e.m->renderer)
        return false;
    e.m->renderer->fail_allocations(name_prefix);
    return true;
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

RenderSettings RenderSettings::recommended() {
    RenderSettings s;
    s.shadow_samples = 1;
    s.bounce_shadow_samples = 1;
    s.denoise = true;
    s.accumulate = 8;
    return s;
}

} // namespace vx
