#pragma once
// How vx::Engine renders (<vx/vx.h>): the lights (Light, Sun) and RenderSettings, taken by
// Engine::set_render_settings. Plain values: copy them; not thread-safe to share while one
// thread writes. Units: world blocks, degrees, linear RGB radiance; see each field.

#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include <vx/types.h>

namespace vx {

// A two-sided rectangular area light: corner plus two edges, in blocks. By default a large panel
// high above the viewer that lights the scene with soft shadows; the sun is `Sun` below.
struct Light {
    bool follow_viewer = true;       // `corner` is relative to the viewer's block.
    BlockPos corner{-40, 120, -60};  // World block (or offset from the viewer's block).
    glm::vec3 edge_u{48.f, 0.f, 0.f}, edge_v{0.f, 0.f, 48.f}; // Each at most 2^20 blocks long.
    glm::vec3 emission{20.f};        // Radiance, linear RGB.
};

// The sun: a directional light with a soft disc (its shadows are sampled over the disc).
struct Sun {
    glm::vec3 direction{0.35f, 1.f, 0.2f}; // World space, towards the sun; need not be unit (not 0
                                           // while irradiance is not 0).
    float angular_radius_degrees = 0.27f;  // Half the disc's apparent size (the real sun: 0.27).
    glm::vec3 irradiance{3.f, 2.9f, 2.7f}; // Linear RGB on a surface facing the sun; 0: no sun.
};

struct RenderSettings {
    enum class Shading : uint8_t {
        Flat, // Block albedo at the first hit, sky on a miss; linear, no lighting.
        Full, // Sun, sky light, area light, soft shadows, emission, mirrors; sRGB encoded.
    };
    enum class Pipeline : uint8_t {
        RayTraced, // The ray tracer: everything below.
        Raster,    // The raster baseline: the same chunks and camera with a depth buffer (see-through
                   // blocks drawn as solid); Full is Phong lit by the area light's centre, no shadows,
                   // reflections, haze or denoiser.
    };
    Pipeline pipeline = Pipeline::RayTraced;
    Shading shading = Shading::Full;
    uint32_t shadow_samples = 4; // Per pixel at the first hit (area light, sun, sky); 0: no shadows.
    // The same on each reflection bounce; unset: shadow_samples. Bounces cost most; 1 is cheap.
    std::optional<uint32_t> bounce_shadow_samples;
    // Each hit's samples by its weight in the pixel instead (path throughput, haze included, x
    // (1 - reflectivity)): ceil(shadow_samples x weight), at least 1. A matte first hit without
    // haze keeps shadow_samples; what a glazed block (reflectivity 0.25) mirrors takes a quarter
    // as many. For scenes of partly reflective blocks (docs/render_report.md: Table 6.3 with the
    // thesis's material). Main thread, as the rest of these settings.
    bool samples_by_weight = false;
    // With samples_by_weight: ceil(shadow_samples x weight^weight_exponent), in (0, 1]. Below 1
    // the weak bounces get more of the rays: 0.8 is the best split for stratified samples, whose
    // error falls as n^-0.75 in a penumbra (docs/render_report.md, stop 30).
    float weight_exponent = 1.0f;
    // Trace the first split_hits hits of every path (the primary hit, then its mirror bounces)
    // each in a pass of its own, later passes over only the paths still going, then the rest.
    // The same image, faster on a GPU with reflections (H200, 5 bounces: 23% at 1 sample, 31% at
    // 56 by weight; docs/render_report.md, stop 29) for 88 bytes a pixel (182 MB at 1080p). 0: one
    // pass; more than max_bounces counts as max_bounces. On terrain it was 0.5-1% slower
    // (stop 30).
    uint32_t split_hits = 0;
    uint32_t max_bounces = 2;    // Reflection depth: mirror blocks, water and glass surfaces.
    glm::vec3 sky{0.55f, 0.7f, 0.95f}; // Linear RGB radiance.
    float sky_light = 1.f;       // Ambient light from the sky (occluded by sky rays); 0: none.
    Sun sun;
    Light light;
    // Camera exposure of Full shading: a physical camera (Filament's and Frostbite's model, with
    // saturation-based ISO 100: the luminance that saturates is 1.2 * 2^ev100 cd/m^2), then an
    // ACES filmic tone curve (Narkowicz's fit) and sRGB. Light units: radiance (sky,
    // Light::emission, block emission) is in 10^4 cd/m^2, irradiance (Sun::irradiance) in
    // 10^4 lux, so the default lights are a clear day. Flat shading has no exposure.
    struct Exposure {
        // Exposure value at ISO 100; one more halves the picture's light (sunny-16 daylight: 15).
        // The default shows ground of albedo 0.18 under the default lights at mid-grey (sRGB 118).
        float ev100 = 14.7f;
        // Metered from each ray-traced frame (caves, night): its log-average luminance (of the
        // pixels any light reaches) is shown at mid-grey (key 0.18), adapting over time: after
        // dt seconds the gap in EV shrinks by exp(-adapt_speed * dt). The first metered image
        // meets its target at once
        // (render_to_image traces it twice; a window shows ev100 until the first meter is read,
        // two frames later). The raster pipeline keeps the last metered value, or ev100.
        bool automatic = false;
        float adapt_speed = 1.5f; // Per second (1.5: 78% of a change within a second).
    };
    Exposure exposure;
    // Ray tracer, Full shading: aerial perspective, haze towards the sky colour with distance so
    // that far terrain reads as far (primary rays and mirror bounces; single scattering of the
    // sky's light, sky * sky_light, with Beer-Lambert extinction and an exponential height
    // falloff). The defaults, clear air, change terrain within 100 blocks by under 2% and veil 55%
    // of it at 4,096 blocks. Without sky light (sky_light 0, or a viewer the engine finds sealed
    // off from the sky, in a cave) the haze only absorbs. Flat shading and the raster pipeline
    // have none.
    struct Haze {
        bool enabled = true;
        // Meteorological visibility at and below base_height, blocks (= metres), > 0: contrast
        // falls to 2% there (Koschmieder: extinction 3.912 / visibility per block). +infinity: none.
        float visibility = 20000.f;
        // Per block above base_height, >= 0: the density is exp(-height_falloff * height) of
        // that below (1 / 1200: the aerosol scale height of 1.2 km); 0: the same everywhere.
        float height_falloff = 1.f / 1200.f;
        double base_height = 0.0; // World y, blocks (the built-in terrain's sea level: 0).
    };
    Haze haze;
    // Ray tracer, Full shading: emissive blocks light by shadow rays aimed at their faces wherever
    // they could add an eighth of the light already there (caves, night, near a lamp): at 4
    // samples 4-17x less noise than rays that must hit them by chance. Off: only those rays (the
    // same light; by day, with lamps only in caves, 10-19% less trace time on an H200).
    bool emitter_sampling = true;
    // Ray tracer, Full shading: hits share their light (all but the sun's) within the frame with
    // the hits on the same patch of a face, light_cache_pixels wide at its distance, directly or
    // through mirrors (a per-frame world-space cache; each hit keeps its own estimate where
    // that has less expected error): at 4 samples half the noise of a frame, at the cost of a
    // small blur of soft light (docs/render_report.md). Off by default: the plain estimate.
    bool light_cache = false;
    float light_cache_pixels = 3.f; // Pixels, 1/64..4096 (set_render_settings refuses others).
    // Ray tracer, Full shading: the edge-aware denoiser over the traced radiance (off by default:
    // it costs a temporal and 5 a-trous compute passes a frame and softens edges; a game at 1-4 samples wants it).
    bool denoise = false;
    // Its a-trous passes, 1..8 (steps 1, 2, 4, ... pixels; set_render_settings refuses others),
    // all of the same cost. With the light cache fewer suffice (issue 18's lavapipe scene: 3
    // passes had the error of 5; docs/render_report.md).
    uint32_t denoise_passes = 5;
    // Ray tracer, Full shading: at most this many frames averaged (reprojected when the camera
    // moves); 1: none. Above 1 each frame traces with a new seed so the average converges.
    uint32_t accumulate = 1;
    // Settings for a game, chosen from measured curves (docs/render_report.md, "Sandbox
    // defaults"): of shadow samples 1-8 (bounces 1 or the same), denoiser on (history 8) or off,
    // at the default 2 bounces, the cheapest whose moving-camera error (RMSE p95 over an orbit and
    // a fly-over against converged references, 1920x1080 on an H200) is within 1.25x of the best
    // measured at up to twice its cost: 1 shadow sample, 1 per bounce, the denoiser with 8
    // frames of history (3.2 ms at RMSE p95 0.019 there; 8 samples halve the error at 3.8x the
    // cost: 12.1 ms; README, "Render defaults"). What the sandbox runs. Any thread.
    static RenderSettings recommended();
};

} // namespace vx
