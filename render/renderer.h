#pragma once
// vx's ray-tracing renderer: the public API. A scene is a set of chunk meshes
// (LodCoord -> world::ChunkMesh; a ChunkCoord means level 0) plus a BlockRegistry for materials;
// render() traces one image and reads it back (headless); present() traces a frame into a GLFW
// window with two frames in flight. No Vulkan or GLFW types here: only render/ touches Vk* objects.
//
// Coordinates: world block units (y up). The camera and the light are given as a 64-bit block
// position plus a float offset inside (or from) that block; everything the GPU sees is relative
// to the camera's block, so far-away worlds (2^24 blocks and beyond) render like the origin.
// Levels of detail (world/lod/lod_coords.h): a level-k chunk's mesh is in cells of 2^k blocks
// (the same mesher, chunk-local cell units) and is drawn scaled by 2^k at lod_origin(); every
// shading path sees it as the blocks it covers.
// Main thread only.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/device_probe.h"
#include "render/pipeline_report.h"
#include "world/block_registry.h"
#include "world/mesh/chunk_mesh.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

class Context;

struct Camera {
    world::BlockPos block{0};       // World block holding the eye.
    glm::vec3 offset{0.5f};         // Eye position inside that block, 0..1 per axis.
    glm::vec3 forward{0, 0, -1};    // View direction (need not be unit). From doubles of any
                                    // length: world::unit_direction first (in float a 1e-30 one's
                                    // square underflowed, and the basis became NaN).
    glm::vec3 up{0, 1, 0};          // Approximate up; must not be parallel to forward.
    float fov_y_degrees = 60.f;     // Vertical field of view.

    // A camera at world position `eye` looking at `target` (double precision world units).
    static Camera look_at(glm::dvec3 eye, glm::dvec3 target, glm::vec3 up = {0, 1, 0}, float fov_y_degrees = 60.f);
};

// A two-sided rectangular area light: corner = block + offset, spanned by edge_u and edge_v
// (blocks, world axes). Orthogonal edges let points near it sample it by solid angle
// (shaders/shared/rect_light.h); a parallelogram is sampled by area everywhere.
struct AreaLight {
    world::BlockPos block{0};
    glm::vec3 offset{0.f};
    glm::vec3 edge_u{16, 0, 0};
    glm::vec3 edge_v{0, 0, 16};
    glm::vec3 emission{20.f}; // Radiance, linear RGB.
};

// The sun: a directional light with a soft disc (its shadows are sampled over the disc).
struct SunLight {
    glm::vec3 direction{0.35f, 1.f, 0.2f}; // World space, towards the sun; need not be unit.
    float angular_radius_degrees = 0.27f;  // Half the disc's apparent size (the real sun: 0.27).
    glm::vec3 irradiance{3.f, 2.9f, 2.7f}; // Linear RGB on a surface facing the sun; 0: no sun.
};

enum class ShadingMode : uint8_t {
    Flat,       // Block albedo (linear, unencoded) at the primary hit, sky colour on a miss.
    // Sun + sky term + area light with soft shadows + emissive blocks + mirror reflections,
    // seen through the haze (Haze), accumulated as HDR radiance, exposed (Exposure), tone-mapped and sRGB encoded
    // (shaders/shared/tonemap.h).
    Full,
    Visibility, // Fraction of unoccluded shadow samples at the primary hit (grey), sky on a miss.
};

// The camera exposure of Full shading, both pipelines (shaders/shared/tonemap.h: the camera
// model, the tone curve, and the units of radiance: 1 = 10^4 cd/m^2).
struct Exposure {
    // Manual exposure value at ISO 100 (the saturating luminance is 1.2 * 2^ev100 cd/m^2); one
    // more halves the exposure. The default puts flat ground of albedo 0.18 under the facade's
    // default lights (sun, sky and area light, seen from a few blocks above) at sRGB 118.
    float ev100 = 14.7f;
    // Metered: from each ray-traced frame's log-average luminance (every 4th pixel in x and y;
    // pixels without any light are not counted, so a frame of black rock keeps its exposure),
    // the exposure that shows it at mid-grey (key 0.18: tonemap.h's kMidGreyInput), adapted
    // over time: after dt seconds the gap in EV shrinks by exp(-adapt_speed * dt). The first
    // frame of a renderer (or after manual frames) meets its target at once: render() traces
    // it twice (one to meter); present() reads a frame's meter kFramesInFlight frames later and
    // draws with ev100 until then. The raster pipeline meters nothing: it uses the last adapted
    // value, or ev100.
    bool automatic = false;
    float adapt_speed = 1.5f; // Per second (1.5: 78% of a change within a second).
};

// Aerial perspective of the ray tracer's Full shading (shaders/shared/haze.glsl): haze towards
// the sky colour with distance, on the primary ray and on mirror bounces. The extinction is
// 3.912 / visibility per block (Koschmieder: contrast falls to 2% at the visibility) at and below
// base_height, and falls off as exp(-height_falloff * height) above it. The defaults, clear air
// (20 km; aerosol scale height 1.2 km), change terrain within 100 blocks by under 2% and veil
// 55% of it at 4,096. The haze is lit by the sky term's light (sky * sky_light); without it
// (sky_light 0, sky_access false) it only absorbs. Flat and Visibility modes and the raster
// pipeline have no haze.
struct Haze {
    bool enabled = true;
    float visibility = 20000.f;            // Blocks, > 0; +infinity: clear (no haze).
    float height_falloff = 1.f / 1200.f;   // Per block, >= 0; 0: the same density at every height.
    double base_height = 0.0;              // World y (blocks) at and below which the density is constant.
};

// Which pipeline draws the image.
enum class PipelineKind : uint8_t {
    RayTraced, // The ray tracer (render/rt_pipeline.h).
    Raster,    // The raster baseline (render/raster_pipeline.h): the same chunks and camera, a
               // depth buffer, see-through blocks (glass, water) drawn as solid; Flat as the ray
               // tracer's elsewhere, Full is Phong with the area light's centre as a point light and
               // no shadows, reflections or haze, Visibility all lit.
};

// The denoiser's a-trous passes (RenderSettings::denoise_passes): SVGF's 5 by default (Schied et
// al. 2017); at most 8, a reach of 510 pixels.
constexpr uint32_t kDefaultDenoisePasses = 5, kMaxDenoisePasses = 8;

// The light cache's cell widths, pixels (RenderSettings::light_cache_pixels): the renderer clamps
// to them; the facade and `vx render` refuse others (light_cache_pixels_valid, false for NaN).
inline constexpr float kMinLightCachePixels = 1.f / 64.f, kMaxLightCachePixels = 4096.f;
constexpr bool light_cache_pixels_valid(float pixels) {
    return pixels >= kMinLightCachePixels && pixels <= kMaxLightCachePixels;
}

// The deepest mirror reflection the renderer traces (RenderSettings::max_bounces above it counts
// as this; the facade and `vx render` refuse it): between two facing perfect mirrors a path
// ends only there, and 2^32 bounces would hang the GPU.
inline constexpr uint32_t kMaxMirrorBounces = 16;

// RenderSettings::weight_exponent's range, (0, 1]; false for NaN. The renderer takes any other
// value as 1; the facade and `vx render` refuse it.
constexpr bool weight_exponent_valid(float exponent) { return exponent > 0.f && exponent <= 1.f; }

struct RenderSettings {
    uint32_t width = 64, height = 64;
    PipelineKind pipeline = PipelineKind::RayTraced;
    ShadingMode mode = ShadingMode::Full;
    // At the first hit, per pixel (stratified, shaders/shared/sampling.h): shadow samples of the
    // area light, of the sun, and as many sky rays. 0: no shadows (lights unoccluded, the sky
    // unoccluded).
    uint32_t shadow_samples = 4;
    // The same on each reflection bounce; unset: shadow_samples (0: unshadowed on bounces).
    // Bounces cost most (25 samples, 5 mirror bounces, seed scene at 1080p: about two thirds of
    // the 48 ms frame were the bounces' shadow samples); 1 keeps them cheap.
    std::optional<uint32_t> bounce_shadow_samples;
    // Light samples in proportion to each hit's weight in the pixel, its path's throughput
    // (luminance: the mirrors' reflectivity and tint before it, the haze's transmittance) times
    // its diffuse share (1 - reflectivity): ceil(shadow_samples x weight), at
    // least 1, in place of shadow_samples and bounce_shadow_samples. For a given ray count,
    // n_k proportional to w_k minimises the pixel's variance sum(w_k^2 s^2 / n_k) (equal s). A
    // matte first hit without haze keeps shadow_samples; behind a glazed block (reflectivity 0.25) the
    // bounces take 3/16, 3/64, ... of them. Not worth it where every hit weighs alike (a field of
    // 0.9 mirrors: docs/render_report.md, stop 22).
    bool samples_by_weight = false;
    // With samples_by_weight: ceil(shadow_samples x weight^weight_exponent) in place of
    // ceil(shadow_samples x weight), in (0, 1]. Stratified samples' variance falls as n^-1.5 where
    // a light is partly hidden (H200, glazed blocks, stop 29's fixed counts: bounce variance as
    // n^-1.49); the allocation that minimises sum(w_k^2 v n_k^-1.5) for a ray count is n_k
    // proportional to w_k^0.8, so 0.8 gives the weak bounces more of the rays than 1 does.
    float weight_exponent = 1.0f;
    // Full shading with reflections (the light cache on or off): trace the first split_hits hits
    // of every path (the primary hit, then its mirror bounces) each in a dispatch of its own and
    // the rest in one more. Each later dispatch continues only the paths the last listed as going on
    // (88 bytes a pixel for the paths and lists, made at the first such frame).
    // The first hit's many coherent shadow rays run apart from the bounces' scattered ones, and
    // no warp waits on ended paths (H200, 5 bounces: 1 spp -23%, 56 by weight -31%;
    // docs/render_report.md, stop 29). Same image; with the light cache nearly (its cells' float
    // sums take the hits in another order: on the H100's seed mirror scene 0.2% of the channels
    // moved, by up to 8 steps, at the same RMSE; stop 65). 0: one dispatch; ignored where it
    // cannot apply; at most max_bounces (and gpu::kMaxSplitHits) count.
    uint32_t split_hits = 0;
    // Where some drawn chunk holds a see-through block and the eye is in none: trace the image
    // with the pipeline variant that has no see-through code first, marking every pixel any of
    // whose rays meets a see-through face, then trace those pixels again with the variant that
    // has it (gpu::kCheckMark, shaders/shared/render_types.h). Same image as the one dispatch
    // with the see-through code; that code runs only where a ray needs it (the terrain's view:
    // 10% of its trace on the H100, docs/render_report.md, stop 56). 4 bytes a pixel for the
    // marks, made at the first such frame. Not with split_hits or the light cache, nor in Flat
    // mode (those trace with the see-through code throughout). Where many pixels' rays meet such
    // faces (a view over a lake) two dispatches cost more than one: while the share of view rays
    // that did in the last frame read back (RenderStats::see_through_view_pixels) is above
    // see_through_check_share, frames trace in one dispatch and count them; a checked frame that
    // marked over that share holds them so for 8 frames, then 16, up to 128 (a glass roof whose
    // shadow rays every pixel sends). 1: always check.
    // kAuto: on a GPU, not on a CPU device (lavapipe), where code a ray does not run costs
    // nothing and the second dispatch only adds (docs/render_report.md, stop 57).
    enum class SeeThroughCheck : uint8_t { kOff, kOn, kAuto };
    SeeThroughCheck see_through_check = SeeThroughCheck::kAuto;
    float see_through_check_share = 0.25f;
    uint32_t max_bounces = 2;    // Reflection depth (mirrors, water and glass surfaces); clamped to kMaxMirrorBounces.
    uint32_t seed = 1;           // Same seed, same image.
    glm::vec3 sky{0.55f, 0.7f, 0.95f}; // Linear RGB radiance of the sky (seen by missed rays).
    // Sky term: sky rays that escape see sky * sky_light (ambient light with occlusion). 0: none.
    float sky_light = 1.f;
    // Whether the view can see the sky at all. The caller decides (the renderer holds meshes, not
    // the world): false when it knows the camera is sealed off from the open air, e.g. the
    // engine's camera is in a cave below its column's surface. Then no sun or sky ray is traced
    // (they could only hit rock); sky rays still run near emissive blocks, to find them.
    // true is always correct, only slower underground. Per pixel, the sun is also skipped where
    // its disc lies behind the face.
    bool sky_access = true;
    // The block the camera's eye lies in (the caller knows the world; the renderer holds meshes).
    // Where it is see-through (the player swims), every view ray starts inside it and leaves
    // through one face or none: the block absorbs along the ray's path in it (Beer-Lambert,
    // shared/rt_common.glsl vx_absorb; shared/raygen_common.glsl g_inside). Ray traced only: the
    // raster baseline shows no tint of it. Air or an opaque block: none.
    world::BlockId eye_block = world::kAir;
    // Emissive blocks' light by shadow rays aimed at their faces (next-event estimation, one
    // face per sample chosen by resampled importance among kEmitterCandidates; render/
    // emitter_quads.h): the faces of the nearest emissive chunks, up to gpu::kMaxEmitterQuads.
    // Off: only sky rays that happen to hit an emitter see its light (noisier, same mean).
    bool emitter_sampling = true;
    // The light cache (render/light_cache.h): the light of every hit but the sun's (the primary
    // hit's and up to gpu::kMaxCachedBounces mirror bounces') is averaged within the frame over
    // all hits on the same patch of a face, light_cache_pixels wide at its distance (to the next
    // power of two blocks), so pixels share their shadow and sky rays. Far less noise, a bias of
    // the light's change over a patch (docs/render_report.md). Full mode on the ray tracer
    // only. Off: each hit keeps its own samples (unbiased). Its GPU memory (render/
    // light_cache.h) is not in check_frame_size's estimate; running out is a frame's error.
    bool light_cache = false;
    float light_cache_pixels = 3.f; // Pixels, clamped to kMin/kMaxLightCachePixels (not finite: the default).
    SunLight sun;
    AreaLight light;
    Exposure exposure;
    Haze haze;
    // The guided denoiser (render/denoiser.h) on the ray tracer's Full-mode radiance; other
    // modes and the raster pipeline ignore these two. denoise: the edge-aware a-trous filter.
    // accumulate: frames of a still (or moving: reprojected) camera the temporal pass averages at
    // most; 1: none. While it is above 1 each frame traces with seed + frame number, so frames
    // differ and the average converges. A change of mode, sample counts, bounces, accumulate or
    // denoise restarts the history.
    bool denoise = false;
    // The a-trous passes of the denoiser (steps 1, 2, 4, ... pixels: 2 (2^n - 1) pixels of reach),
    // 1..kMaxDenoisePasses; the renderer clamps. With the light cache fewer suffice: on issue 18's
    // lavapipe scene 3 passes had the error of 5 at 1.6 ms less (docs/render_report.md, stops 64-65).
    uint32_t denoise_passes = kDefaultDenoisePasses;
    uint32_t accumulate = 1;
    // Clamp the temporal history so changed light leaves no ghost (DenoiseSettings::
    // history_clamp); off: plain accumulation, for comparisons.
    bool history_clamp = true;
    // Filter the first mirror bounce's diffuse lighting in the reflected surface's terms
    // (render/denoiser.h); off: it is only accumulated, like the rest of the reflected part, for
    // comparisons.
    bool denoise_reflections = true;
};

// 8-bit RGBA pixels, row 0 at the top.
struct RenderImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
    glm::u8vec4 at(uint32_t x, uint32_t y) const {
        const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
        return {p[0], p[1], p[2], p[3]};
    }
};

// The ray tracer's G-buffer of one frame, read back (render/gbuffer.h describes the images).
// Row 0 at the top; width x height values each, converted to float.
struct GBufferImage {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec4> radiance;     // Linear HDR radiance, before tone mapping (RGBA16F).
    std::vector<glm::vec4> albedo;       // Linear first-hit albedo as seen (times the tint of see-through
                                         // blocks before it); a = 1 on a hit, 0 on a miss (RGBA8).
    std::vector<glm::vec4> normal_depth; // World normal xyz, w: distance along the primary ray; 0 on a miss.
    std::vector<glm::vec4> reflected;    // The unfiltered part, rgb; a: occluder distance, sun flag (RGBA16F).
    // The output before its rounding to 8 bits, rgb: Full mode, vx_display (shaders/shared/
    // tonemap.h) of the final radiance (the denoiser's output when it ran, else `radiance`) at the
    // frame's exposure, 0..1; Flat and Visibility modes, `radiance` as the output holds it. The
    // radiance passed through half floats (relative rounding 2^-11). No UI overlay. Error
    // metrics below a tenth of an 8-bit step need it (docs/render_report.md, stop 27).
    std::vector<glm::vec3> display;
    glm::vec4 at(const std::vector<glm::vec4>& image, uint32_t x, uint32_t y) const { return image[size_t(y) * width + x]; }
};

// Device memory the scene's acceleration structures hold, bytes by kind (buffer sizes as
// created, before the allocator's rounding to 16 bytes), after the last frame's builds.
struct GpuMemoryStats {
    uint64_t blas = 0;       // Bottom-level acceleration structures.
    uint64_t vertices = 0;   // Build-input vertices (kept by hot chunks only).
    uint64_t quads = 0;      // Quad records the hit shader reads (one per slot, spares included).
    uint64_t tlas = 0;       // TLASes, instance buffers and chunk tables of every frame slot.
    uint64_t scratch = 0;    // Shared build scratch.
    uint64_t indices = 0;    // The shared slot index pattern.
    uint64_t quad_count = 0; // Real quads of the drawn chunks.
    uint64_t total() const { return blas + vertices + quads + tlas + scratch + indices; }
    // Per-chunk memory (BLAS + vertices + quad records) per real quad; 0 without quads.
    double bytes_per_quad() const { return quad_count ? double(blas + vertices + quads) / double(quad_count) : 0.0; }
};

struct RenderStats {
    uint32_t blas_builds = 0, blas_refits = 0, instances = 0;
    uint32_t blas_compactions = 0; // Cold BLASes copied into their compacted size this frame.
    uint32_t hot_chunks = 0;       // Chunks kept refittable (edited within hot_frames frames).
    uint32_t failed_chunks = 0;    // Chunks not drawn: their GPU memory could not be allocated.
    uint64_t triangles = 0;  // Of the drawn chunks, including spare (degenerate) slots.
    uint32_t raster_chunks = 0; // Raster pipeline: chunks drawn (inside the view frustum); 0 when ray traced.
    uint32_t raster_transparent_chunks = 0; // Of those, drawn again for their transparent blocks.
    // The ray tracer's pipeline probed for coincident transparent faces: two different transparent
    // blocks touch somewhere in the chunks set (render/touching_pairs.h); else it traces the
    // variant with no probe.
    bool touching_probes = false;
    // The ray tracer's pipeline had the see-through code (the walk through see-through blocks, their
    // tints and surfaces): some chunk set holds a see-through block, or the eye is in one
    // (RenderSettings::eye_block); else it traces the variant without (render/rt_pipeline.h).
    bool see_through_code = true;
    // The frame traced with RenderSettings::see_through_check; of its pixels, those any of whose
    // rays met a see-through face, traced again (0 where not checked), and those whose view ray's
    // first walk met one (where the check applied, checked or not; 0 where it did not). Of this
    // frame in render(); in present(), of the frame whose GPU times these are (kFramesInFlight
    // back).
    bool see_through_checked = false;
    uint32_t see_through_pixels = 0, see_through_view_pixels = 0;
    uint64_t upload_bytes = 0; // Chunk vertices + quad records copied to the GPU this frame.
    uint32_t instance_writes = 0; // TLAS instances written this frame (changed ones: not every chunk).
    uint64_t rebases = 0;      // Render-origin moves that rewrote every TLAS instance, since creation.
    GpuMemoryStats memory;
    // Per LOD level (index = level): drawn chunks (TLAS instances; they sum to `instances`), and
    // the device memory their chunks hold, bytes: BLAS + vertices (hot chunks) + quad records,
    // drawn or not (they sum to memory.blas + memory.vertices + memory.quads). Kept as chunks
    // are set and removed: no per-frame cost per chunk.
    std::array<uint32_t, world::kMaxLodLevel + 1> level_instances{};
    std::array<uint64_t, world::kMaxLodLevel + 1> level_gpu_bytes{};
    double cpu_ms = 0;       // Recording, including CPU-side geometry work (present(): and submit).
    double gpu_ms = 0;       // Submit to fence (builds + trace + copy), wall clock.
    // GPU time of each phase from timestamp queries, milliseconds; -1 where the queue has no
    // timestamps. Upload + BLAS builds/refits, the TLAS build, the trace (or the raster pass),
    // the image read-back copy.
    // The read-back copy for render(), the blit into the swapchain image for present().
    double gpu_blas_ms = -1, gpu_tlas_ms = -1, gpu_trace_ms = -1, gpu_copy_ms = -1;
    double gpu_denoise_ms = -1; // The denoiser's passes (0 when it did not run).
    double gpu_frame_ms = -1; // The whole frame on the GPU (first to last timestamp).
    float ev100 = 0;          // The exposure value the frame was drawn with (Exposure).
    // present() only (-1 after render()). Nothing waits for the frame just submitted, so its gpu_*
    // fields are those of the frame kFramesInFlight (2) presents back, read once its fence has
    // signalled; gpu_ms is -1. frame_ms: wall time from the previous present() call's start to
    // this one's (the frame period the caller sees). wait_ms: the part of this call spent blocked
    // on the GPU or the presentation engine (the fence two frames back, swapchain acquire and
    // any recreation). cpu_ms: recording and submitting. present_ms: time in vkQueuePresentKHR
    // (a software WSI, lavapipe's on X11, copies the image out there, so it waits for the frame).
    double frame_ms = -1, wait_ms = -1, present_ms = -1;
    uint32_t present_width = 0, present_height = 0; // present(): the frame's (swapchain's) size, pixels.
};

// What present() did.
enum class PresentResult : uint8_t {
    Presented, // A frame was traced and queued for presentation.
    Skipped,   // Minimised (0x0 framebuffer) or the swapchain was out of date: nothing drawn.
};

// A whole scene for the one-call API: chunk meshes (not owned) plus the materials.
struct Scene {
    std::vector<std::pair<world::ChunkCoord, const world::ChunkMesh*>> chunks; // Level 0.
    // Coarse chunks (any level; level 0 here is the same as in `chunks`): meshes in cells of
    // 2^level blocks, drawn at lod_origin() scaled by 2^level.
    std::vector<std::pair<world::LodCoord, const world::ChunkMesh*>> lod_chunks;
    const world::BlockRegistry* registry = nullptr; // Null: the default registry.
};

// GPU memory of the renderer's sub-allocator, bytes (all of the renderer's buffers and images).
struct GpuHeapStats {
    uint64_t held_bytes = 0; // Device memory blocks allocated from the driver.
    uint64_t used_bytes = 0; // Of them, handed out to resources.
};

// A game's 2D UI (a HUD, menus: Dear ImGui's output or any triangles), drawn over every later
// frame after the trace and the denoiser, before the read-back (render()) or the present
// (present(): so captures include it). See render/ui_pass.h.
// Pixels: framebuffer coordinates, (0, 0) the top-left corner of the top-left pixel, y down.
struct UiVertex {
    glm::vec2 pos{0.f}; // Pixels.
    glm::vec2 uv{0.f};  // Texture coordinates, 0..1 over the UI texture (bilinear, clamped).
    uint32_t rgba = 0;  // Colour, R in the low byte (Dear ImGui's IM_COL32), straight alpha.
};
// Triangles indices[index_offset, + index_count) clipped to clip_rect = (x0, y0, x1, y1), pixels.
struct UiDrawCmd {
    uint32_t index_offset = 0, index_count = 0;
    glm::ivec4 clip_rect{0};
};
struct UiDrawList {
    std::vector<UiVertex> vertices;
    std::vector<uint32_t> indices; // Into vertices; a multiple of 3 per command.
    std::vector<UiDrawCmd> cmds;   // Drawn in order, each blended over what is below.
};
// Why `list` cannot be drawn (an index past the vertices, a command past the indices or not a
// whole number of triangles), or "" when it can. Thread-safe.
std::string ui_draw_list_error(const UiDrawList& list);

struct RendererCreateInfo {
    bool validation = false;
    bool sync_validation = false; // With validation: synchronization validation too (slow).
    DeviceChoice device{};
    // BLASes allow updates, so edits that fit their slots refit; false: no ALLOW_UPDATE (the
    // driver may build a faster-to-trace BVH) and every edit rebuilds its chunk's BLAS.
    bool allow_refit = true;
    // Frames an edited ("hot": spare slots, ALLOW_UPDATE) chunk stays hot after its last edit
    // before it is rebuilt cold (exact size, compacted). See render/scene_accel.h.
    uint32_t hot_frames = 600;
    // Refits of a hot chunk in a row before its next edit rebuilds it (render/scene_accel.h).
    // 0: every edit of a hot chunk rebuilds it (benchmarks: refit against rebuild).
    uint32_t max_refits = 8;
    // Test knob: chunk geometry and BLAS allocations fail once they would hold more than this
    // many bytes, as on a full device (those chunks are not drawn and are counted in
    // RenderStats::failed_chunks). 0: no limit.
    uint64_t gpu_memory_budget_bytes = 0;
    // Test knob: Context::fail_allocations from the start, so resources made by create() fail
    // as out of memory (create returns an error). Empty: none.
    std::string fail_allocations{};
    // A GLFWwindow* to present() to, or null for a headless renderer. The caller has called
    // glfwInit, created the window with GLFW_CLIENT_API = GLFW_NO_API, polls its events, and
    // keeps GLFW and the window alive until the Renderer is destroyed. The device must present
    // from its graphics+compute queue.
    void* glfw_window = nullptr;
    bool vsync = true; // With a window: FIFO; false: MAILBOX, else IMMEDIATE, else FIFO.
    // Keep the driver's statistics of the ray-tracing pipelines for pipeline_report() (where the
    // device offers VK_KHR_pipeline_executable_properties). Off for games: a driver may skip its
    // caches for pipelines made so.
    bool pipeline_statistics = false;
};

class Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const RendererCreateInfo& info);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Materials come from `registry` (copied); unknown ids get the registry's fallback colours.
    // Colours, reflectivity and emission apply at the next frame. A block's opacity is part of its
    // chunks' BLAS flags and face marks, made when the chunk was set: returns the chunks set
    // before whose blocks changed opacity (sorted), which keep the old opacity until set again.
    // Main thread only.
    std::vector<world::LodCoord> set_registry(const world::BlockRegistry& registry);
    // Incremental scene edits, applied at the next render() (past a frame's build budget, 2 GiB
    // of uploads, at a later one; the old mesh is drawn meanwhile). `changed_slices` (slice_index()
    // values, as MeshSink::on_mesh gives them) marks an edit: only those slices' slots are
    // uploaded and the BLAS refitted when they fit (else the chunk is rebuilt). Empty: the whole
    // mesh is new (a chunk not edited lately is rebuilt exact-size and compacted).
    // Levels of detail: chunk c.chunk of level c.level (0..world::kMaxLodLevel; asserted), its
    // mesh in chunk-local cell units (cells of 2^level blocks, as the mesher makes it from a
    // level-k Chunk), drawn scaled by 2^level at world::lod_origin(c). Entries are keyed by the
    // whole LodCoord: a level-0 chunk and a level-k chunk with the same chunk coordinates are
    // different entries, both drawn (the caller decides which levels cover what). An empty mesh
    // removes the entry. Main thread only.
    void set_chunk(world::LodCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices = {});
    // Removes exactly that level's entry (no-op when absent). Main thread only.
    void remove_chunk(world::LodCoord c);
    // Level 0: the same as set_chunk(LodCoord{0, c}, ...) and remove_chunk(LodCoord{0, c}).
    void set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices = {});
    void remove_chunk(world::ChunkCoord c);
    void clear_chunks(); // Every entry of every level.
    // Blocks [lo, hi] (inclusive, world blocks) were edited: the next frame's denoiser starts
    // the history again on surfaces within render::kEditReach blocks of them (render/
    // edit_marks.h), where the light changed but normal and depth may not have. Call with the
    // edit's set_chunk calls. Main thread only.
    void note_edit(world::BlockPos lo, world::BlockPos hi);
    // Boxes noted since the last traced frame (0..gpu::kMaxEditBoxes). Main thread only.
    size_t noted_edits() const;

    // Renders one image and reads it back (waits for the GPU). With `gbuffer`, also reads back
    // that frame's G-buffer into *gbuffer (tests, tools; costs four more copies).
    // Errors, each one line, the renderer kept usable: out of GPU memory for a frame resource
    // (render target, G-buffer, read-backs, materials, emitter list, denoiser images, UI, AS
    // scratch, staging, TLAS, raster depth): nothing is drawn, the scene's edits are kept, and a later call
    // (or a smaller size) tries again; the device was lost (device_lost()): every later frame
    // fails the same way until the renderer is recreated.
    Result<RenderImage> try_render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer = nullptr);
    // try_render for tests and tools that own the device: aborts with its error line instead.
    RenderImage render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer = nullptr);
    // One call: makes `scene` the renderer's scene (chunks and lod_chunks), then renders. Chunks
    // absent from `scene` are dropped; every chunk in it is re-sent (a refit when its slots fit),
    // so for small edits prefer set_chunk + render.
    RenderImage render(const RenderSettings& settings, const Camera& camera, const Scene& scene);

    // Traces a frame and presents it to the window (a renderer created with glfw_window; an
    // error otherwise). The render extent follows the window: settings.width/height are ignored,
    // the frame is the swapchain's size, and a resized window gets a new swapchain at its next
    // present(). Two frames in flight: the only CPU wait is on the frame two presents back (and
    // on the presentation engine in acquire, e.g. with vsync). A minimised window returns
    // Skipped without drawing. The window shows exactly the bytes render() would return for the
    // same settings, camera and size (Full mode sRGB encoded once).
    // `capture` (tests, screenshots): also reads the presented image back into *capture as RGBA
    // and waits for this frame (written only when Presented); needs a surface whose images
    // allow TRANSFER_SRC.
    // Errors: as try_render's (out of memory: nothing presented, a later call tries again; device
    // lost), and no window.
    Result<PresentResult> present(const RenderSettings& settings, const Camera& camera, RenderImage* capture = nullptr);
    // Window renderers: the present mode of the next swapchain (FIFO with vsync; else MAILBOX,
    // IMMEDIATE or FIFO, what the surface offers); a change recreates the swapchain at the next
    // present(). vsync(): whether the current mode waits for the display (FIFO).
    void set_vsync(bool vsync);
    bool vsync() const;
    // The UI drawn over later frames of render() and present() (see UiDrawList; an empty list
    // removes it). `list` must be valid (ui_draw_list_error() empty).
    void set_ui(UiDrawList list);
    // The UI's texture: width x height RGBA8 texels (straight alpha, what the screen shows), row 0
    // at the top; uploaded at the next frame. Until one is set the texture is one white texel.
    // Needs rgba.size() == width * height * 4 and both sizes in 1..16384. Allocates now: an error
    // when GPU memory runs out (the previous texture stays) or the device was lost.
    Status set_ui_texture(uint32_t width, uint32_t height, std::vector<uint8_t> rgba);

    // The device was lost (VK_ERROR_DEVICE_LOST from a submit, a wait, an acquire or a present):
    // frames fail; the scene, being the caller's, is kept by the caller and sent to a new
    // Renderer. Destroying this one is safe.
    bool device_lost() const;
    // What the driver made of each ray-tracing pipeline variant (render/pipeline_report.h),
    // making those not yet made: stack sizes always, executable statistics with
    // RendererCreateInfo::pipeline_statistics on a device that keeps them. Errors: out of memory
    // for a variant (the ones made stay usable), the device lost. Main thread only.
    Result<PipelineReport> pipeline_report();
    // Whether width x height frames can fit this device: an error naming the size and the
    // estimate when the frame resources (frame_bytes_per_pixel) exceed the largest device-local
    // heap or one image exceeds the device's largest allocation.
    Status check_frame_size(uint32_t width, uint32_t height) const;
    // Test hooks (Context::simulate_device_loss, Context::fail_allocations): the next submission
    // reads as a lost device; resources whose debug name starts with `name_prefix` ("render
    // target", "gbuffer", "render readback", "TLAS", "AS scratch", "ui texture", "denoise",
    // "light cache") fail to allocate until called again with ""; with `above_bytes` > 0 only
    // those larger than that.
    void simulate_device_loss();
    void fail_allocations(std::string name_prefix, uint64_t above_bytes = 0);
    // Test hook: the light cache's table has at most `cells` cells (a power of two, >= 4; 0: as
    // sized for the frame), so that hits find their probes taken (LightCache).
    void limit_light_cache_cells(uint32_t cells);

    const DeviceReport& device() const;
    uint32_t validation_errors() const;
    const RenderStats& last_stats() const;
    GpuHeapStats memory_stats() const;
    Context& context();

private:
    Renderer();
    struct Impl;
    std::unique_ptr<Impl> m;
};

// Device memory per pixel of a frame's resources at their largest: the target and G-buffer of
// every frame slot, the read-back, and the denoiser's images. Thread-safe.
uint64_t frame_bytes_per_pixel();

// Writes an image as PNG (stb_image_write encodes it). Errors: the file cannot be opened or a
// write fails (a full disk: a cut file is removed). Thread-safe (stb keeps no state while encoding).
Status write_png(const std::string& path, const RenderImage& image);

} // namespace vx::render
