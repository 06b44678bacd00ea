// `vx render`'s arguments turned into the renderer's settings and camera
// (tools/cmd_render_settings.h): checked one step at a time, the first problem reported.
#include "cmd_render_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <glm/glm.hpp>

#include "cli_common.h"
#include "world/coords.h"

namespace vx::tools {
namespace {

// --size, --shading, --shadows, the samples and the bounces.
std::optional<std::string> apply_image_args(const RenderArgs& a, render::RenderSettings& s) {
    const std::optional<glm::uvec2> size = parse_image_size(a.size);
    if (!size)
        return "--size must be WxH (1..16384), got '" + a.size + "'";
    s.width = size->x;
    s.height = size->y;
    s.mode = a.shading == "flat" ? render::ShadingMode::Flat : render::ShadingMode::Full;
    s.shadow_samples = a.shadows == "off" ? 0 : a.spp;
    if (a.bounce_spp >= 0)
        s.bounce_shadow_samples = a.shadows == "off" ? 0 : uint32_t(std::min<int64_t>(a.bounce_spp, 1 << 16));
    s.samples_by_weight = a.samples_by == "weight";
    s.weight_exponent = a.weight_exponent;
    s.split_hits = split_hits_arg(a.first_hit_pass, a.split_hits);
    s.max_bounces = a.reflections;
    s.seed = a.sample_seed;
    return std::nullopt;
}

// --sun, --sun-radius, --sky-light, --sky-access; --area-light off.
std::optional<std::string> apply_sky_args(const RenderArgs& a, render::RenderSettings& s) {
    if (a.sun == "off") {
        s.sun.irradiance = glm::vec3(0.f);
    } else {
        const auto sun = parse_dvec3(a.sun);
        const glm::dvec3 towards = sun ? world::unit_direction(*sun) : glm::dvec3(0.0);
        if (towards == glm::dvec3(0.0))
            return "--sun must be a non-zero direction X,Y,Z towards the sun, or off; got '" + a.sun + "'";
        s.sun.direction = glm::vec3(towards); // Unit in double first: 1e308 is infinite as a float.
    }
    if (!(a.sun_radius >= 0.f && a.sun_radius <= 45.f))
        return "--sun-radius must be within 0..45 degrees";
    s.sun.angular_radius_degrees = a.sun_radius;
    if (!(a.sky_light >= 0.f && a.sky_light <= 1000.f))
        return "--sky-light must be within 0..1000";
    s.sky_light = a.sky_light;
    s.sky_access = a.sky_access == "on";
    if (a.area_light == "off")
        s.light.emission = glm::vec3(0.f);
    return std::nullopt;
}

// --exposure, --haze, --visibility.
std::optional<std::string> apply_exposure_args(const RenderArgs& a, render::RenderSettings& s) {
    if (a.exposure == "auto") {
        s.exposure.automatic = true;
    } else if (!a.exposure.empty()) {
        char* end = nullptr;
        const float ev = std::strtof(a.exposure.c_str(), &end);
        if (end == a.exposure.c_str() || *end != '\0' || !(ev >= -10.f && ev <= 30.f))
            return "--exposure must be an EV100 within -10..30 or auto, got '" + a.exposure + "'";
        s.exposure.ev100 = ev;
    }
    s.haze.enabled = a.haze == "on";
    if (!a.visibility.empty()) {
        char* end = nullptr;
        const float v = std::strtof(a.visibility.c_str(), &end);
        if (end == a.visibility.c_str() || *end != '\0' || !(v >= 1.f)) // strtof reads "inf".
            return "--visibility must be a distance in blocks >= 1 (inf: clear air), got '" + a.visibility + "'";
        s.haze.visibility = v;
    }
    return std::nullopt;
}

// --fov, --eye, --target, --up, or the scene's default view over its whole box.
std::optional<std::string> aim_camera(const RenderArgs& a, const engine::LoadedScene& scene, render::Camera& camera) {
    if (!(a.fov >= 1.f && a.fov <= 179.f))
        return "--fov must be within 1..179 degrees";
    const glm::dvec3 lo(scene.box_min), hi(scene.box_max), centre = 0.5 * (lo + hi), ext = hi - lo;
    const double half_fov = glm::radians(double(a.fov)) * 0.5;
    std::optional<WorldPos> eye = scene.default_eye, target = scene.default_target;
    if (ext == glm::dvec3(0.0) && !eye && a.eye.empty() && a.target.empty()) // It said "--target must differ".
        return "the scene holds no chunk to frame (" + scene.description + "): give --eye and --target";
    if (!target)
        target = world_pos_at(centre);
    if (!eye) {
        const double dist = 0.35 * glm::length(ext) / std::tan(half_fov); // Corners may be cut a little.
        eye = world_pos_at(centre + dist * glm::normalize(glm::dvec3(-1.0, 0.9, -1.0)));
    }
    if (!a.eye.empty() && !(eye = parse_world_pos(a.eye)))
        return "--eye must be X,Y,Z (decimals, inside the world), got '" + a.eye + "'";
    if (!world::in_world(eye->block)) // The eye framing a volume at the world's edge.
        return "the default eye would stand outside the world (|coordinate| < 2^36): give --eye";
    if (!a.target.empty() && !(target = parse_world_pos(a.target)))
        return "--target must be X,Y,Z (decimals, inside the world), got '" + a.target + "'";
    const auto up = parse_dvec3(a.up);
    if (!up || *up == glm::dvec3(0.0))
        return "--up must be a non-zero X,Y,Z, got '" + a.up + "'";
    // Unit vectors before the camera's floats: a target 1e-30 blocks from the eye made a NaN basis.
    const glm::dvec3 fwd = world::unit_direction(world_delta(*target, *eye));
    const glm::dvec3 unit_up = world::unit_direction(*up);
    if (fwd == glm::dvec3(0.0) || !(glm::length(glm::cross(fwd, unit_up)) >= 1e-6))
        return "--target must differ from --eye and not lie along --up";
    camera.block = eye->block;
    camera.offset = glm::vec3(eye->frac);
    camera.forward = glm::vec3(fwd);
    camera.up = glm::vec3(unit_up);
    camera.fov_y_degrees = a.fov;
    return std::nullopt;
}

// --light, or above the scene.
std::optional<std::string> place_area_light(const RenderArgs& a, const engine::LoadedScene& scene,
                                            render::RenderSettings& s) {
    const glm::dvec3 lo(scene.box_min), hi(scene.box_max), centre = 0.5 * (lo + hi), ext = hi - lo;
    // Light: a square above the scene, its side half its height above the top. Emission 10:
    // irradiance ≈ 10 / 4 = 2.5 below it, the facade's default Light's, so the default exposure
    // shows the default picture (ground of albedo 0.18 at mid-grey).
    const double above = std::max(32.0, 0.25 * std::max(ext.x, ext.z));
    std::optional<WorldPos> light = world_pos_at({centre.x, hi.y + above, centre.z});
    if (!a.light.empty() && !(light = parse_world_pos(a.light)))
        return "--light must be X,Y,Z (decimals, inside the world), got '" + a.light + "'";
    if (!world::in_world(light->block)) // Above a volume at the world's top.
        return "the default light would lie outside the world (|coordinate| < 2^36): give --light";
    const float side = float(above * 0.5);
    s.light.edge_u = {side, 0, 0};
    s.light.edge_v = {0, 0, side};
    if (a.area_light != "off")
        s.light.emission = glm::vec3(10.f);
    s.light.block = light->block;
    s.light.offset = glm::vec3(light->frac) - 0.5f * (s.light.edge_u + s.light.edge_v);
    return std::nullopt;
}

} // namespace

std::optional<std::string> make_settings(const RenderArgs& a, const engine::LoadedScene& scene, Settings& out) {
    render::RenderSettings& s = out.settings;
    if (auto err = apply_image_args(a, s))
        return err;
    if (auto err = apply_sky_args(a, s))
        return err;
    if (auto err = apply_exposure_args(a, s))
        return err;
    if (auto err = aim_camera(a, scene, out.camera))
        return err;
    s.eye_block = scene.world->get_block(out.camera.block); // An eye under water sees through it.
    return place_area_light(a, scene, s);
}

void apply_pipeline_args(const RenderArgs& a, render::RenderSettings& s) {
    s.pipeline = a.pipeline == "raster" ? render::PipelineKind::Raster : render::PipelineKind::RayTraced;
    s.denoise = a.denoise == "on";
    s.denoise_passes = a.denoise_passes;
    s.accumulate = std::max<uint32_t>(a.accumulate, 1);
    s.history_clamp = a.history_clamp == "on";
    s.emitter_sampling = a.emitter_sampling == "on";
    s.light_cache = a.light_cache == "on";
    using Check = render::RenderSettings::SeeThroughCheck;
    s.see_through_check = a.see_through_check == "on" ? Check::kOn : a.see_through_check == "off" ? Check::kOff : Check::kAuto;
    s.see_through_check_share = a.see_through_check_share;
    s.light_cache_pixels = a.light_cache_pixels;
}

} // namespace vx::tools
