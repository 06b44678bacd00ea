#pragma once
// `vx render`'s arguments (RenderArgs) and their translation into the renderer's settings and
// camera (tools/cmd_render_settings.cpp). CLI thread only.

#include <cstdint>
#include <optional>
#include <string>

#include "engine/scene_loader.h"
#include "render/renderer.h"
#include "scene_args.h"

namespace vx::tools {

struct RenderArgs {
    SceneArgs scene;
    std::string eye, target, up = "0,1,0", light, size = "640x360", shading = "full", shadows = "on";
    std::string device = "auto", out = "render.png", blas_update = "on";
    float fov = 60.f;
    uint32_t spp = 4, reflections = 2, repeat = 1, edit_burst = 0;
    uint32_t versus_raw = 0; // --versus-raw: then time the view against this many spp raw (0: not).
    uint32_t sample_seed = 1; // --sample-seed: RenderSettings::seed (the samples' random numbers).
    int64_t bounce_spp = -1; // -1: as --spp.
    std::string samples_by = "count"; // --samples-by: count (--spp, --bounce-spp) or weight.
    float weight_exponent = 1.f;      // --weight-exponent (render::RenderSettings::weight_exponent).
    std::string first_hit_pass = "off"; // --first-hit-pass: on is --split-hits 1.
    uint32_t split_hits = 0;            // --split-hits (render::RenderSettings::split_hits).
    std::string see_through_check = "auto"; // --see-through-check (render::RenderSettings::see_through_check).
    float see_through_check_share = 0.25f; // --see-through-check-share.
    std::string sun = "0.35,1,0.2", sky_access = "on", area_light = "on";
    float sun_radius = 0.27f, sky_light = 1.f;
    bool validation = false;
    bool pipeline_report = false; // --pipeline-report: print render::Renderer::pipeline_report().
    std::string pipeline = "rt"; // --pipeline (raster baseline, render/raster_pipeline.h).
    std::string denoise = "off"; // --denoise (render/denoiser.h).
    uint32_t denoise_passes = render::kDefaultDenoisePasses; // --denoise-passes: its a-trous passes.
    uint32_t accumulate = 1;     // --accumulate: frames of the still camera averaged.
    std::string history_clamp = "on"; // --history-clamp (render::RenderSettings::history_clamp).
    std::string emitter_sampling = "on"; // --emitter-sampling (render::RenderSettings::emitter_sampling).
    std::string light_cache = "off";    // --light-cache (render::RenderSettings::light_cache).
    float light_cache_pixels = 3.f;      // --light-cache-pixels.
    std::string exposure;        // --exposure: EV100 or auto; empty: the default EV100.
    std::string haze = "on";     // --haze: aerial perspective of Full shading.
    std::string visibility;      // --visibility: the haze's visibility in blocks; empty: the default.
    std::string lighting = "default"; // --lighting: default or thesis (apply_lighting_preset).
};

struct Settings {
    render::RenderSettings settings;
    render::Camera camera;
    // The first frame that failed (Renderer::try_render's line: out of GPU memory, a lost
    // device); later frames are skipped and the command reports it.
    mutable std::string failure;
};

// Camera and light from the arguments or the scene's defaults: a view over the whole scene.
// Returns the first argument's problem (one line), or nullopt.
std::optional<std::string> make_settings(const RenderArgs& a, const engine::LoadedScene& scene, Settings& out);

// --pipeline: the ray tracer or the raster baseline (same chunks and camera).
// --denoise, --accumulate: the denoiser on the ray tracer's Full-mode radiance.
void apply_pipeline_args(const RenderArgs& a, render::RenderSettings& s);

} // namespace vx::tools
