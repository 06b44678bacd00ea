#pragma once
// Renderer::Impl, the renderer's private state, and what its files share: renderer.cpp (creation,
// the public API), renderer_frame.cpp (a frame's resources and parameters) and renderer_record.cpp
// (its commands). Internal to vx_render: only render/renderer*.cpp include it.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "render/context.h"
#include "render/denoiser.h"
#include "render/edit_marks.h"
#include "render/gpu_layouts.h"
#include "render/light_cache.h"
#include "render/present.h"
#include "render/raster_pipeline.h"
#include "render/renderer.h"
#include "render/resources.h"
#include "render/rt_pipeline.h"
#include "render/scene_accel.h"
#include "render/touching_pairs.h"
#include "render/ui_pass.h"

namespace vx::render {

// The G-buffer read-back buffer: per pixel, radiance, normal_depth, reflected and the denoiser's
// output (8 bytes each: RGBA16F), then albedo (4: RGBA8). Section k starts at pixels *
// kGBufferSectionAt[k]. The 8-byte texels come first so every copy's bufferOffset is a multiple
// of its texel size at any pixel count (VUID-vkCmdCopyImageToBuffer-bufferOffset-01558: albedo
// second left the later sections 4 bytes off whenever width x height was odd).
enum GBufferSection { kRadianceSection, kNormalDepthSection, kReflectedSection, kDenoisedSection, kAlbedoSection };
inline constexpr VkDeviceSize kGBufferSectionAt[5] = {0, 8, 16, 24, 32};
inline constexpr VkDeviceSize kGBufferReadbackPixelBytes = 36;

// An exponent outside (0, 1] (NaN too) counts as 1: pow() of NaN would make every count
// undefined. The facade and `vx render` refuse such values (weight_exponent_valid).
inline float effective_weight_exponent(const RenderSettings& s) {
    return weight_exponent_valid(s.weight_exponent) ? s.weight_exponent : 1.f;
}

// The light cache's cell width, clamped; not finite: the default (renderer.h).
inline float effective_cell_pixels(const RenderSettings& s) {
    return std::isfinite(s.light_cache_pixels) ? std::clamp(s.light_cache_pixels, kMinLightCachePixels, kMaxLightCachePixels)
                                               : RenderSettings{}.light_cache_pixels;
}

struct Renderer::Impl {
    std::unique_ptr<Context> ctx;
    std::unique_ptr<SceneAccel> accel;
    std::unique_ptr<RtPipeline> pipeline;
    std::unique_ptr<RasterPipeline> raster; // Made at the first raster frame.
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::array<VkDescriptorSet, kFramesInFlight> sets{};
    std::array<Buffer, kFramesInFlight> params;
    world::BlockRegistry registry;
    Buffer materials;
    uint32_t material_count = 0;
    bool materials_dirty = true;
    uint32_t max_block_id = 0;
    // Trace targets, one per frame slot (the previous frame may still blit its own). With an
    // sRGB swapchain they are R8G8B8A8_SRGB written through a UNORM view (present.h says why).
    std::array<Image, kFramesInFlight> targets;
    // The G-buffer of each frame slot (render/gbuffer.h), the size of its target.
    struct GBuffer {
        Image radiance, albedo, normal_depth, reflected;
        Image mirror_light, mirror_albedo, mirror_normal_depth; // The first mirror bounce's.
    };
    std::array<GBuffer, kFramesInFlight> gbuffers;
    // Emissive blocks light the scene only where they are: sky rays look for emitters when some
    // drawn chunk holds a block whose material emits. The block ids of each chunk's quads:
    std::unordered_map<world::LodCoord, std::vector<world::BlockId>, world::LodCoordHash> chunk_blocks;
    // Drawn chunks holding an emissive block: kept as chunks are set and removed, remade from
    // chunk_blocks only when the materials change (a frame never scans every chunk).
    std::unordered_set<world::LodCoord, world::LodCoordHash> emitter_set;
    std::vector<world::LodCoord> emitter_chunks; // emitter_set as a list (sorted by distance each frame).
    bool emitters_dirty = true; // The materials changed since emitter_set was made.
    bool emitter_list_dirty = true; // emitter_set changed since emitter_chunks was made.
    std::vector<bool> emissive; // Per registered block id (set_registry): its material emits.
    bool emits(const std::vector<world::BlockId>& ids) const {
        // Unregistered ids draw with a fallback material, which does not emit.
        return std::any_of(ids.begin(), ids.end(), [&](world::BlockId id) { return id < emissive.size() && emissive[id]; });
    }
    std::array<Buffer, kFramesInFlight> emitter_lists; // vec4[kMaxEmitterChunks] per frame slot.
    // The emissive quads of each chunk in emitter_set meshed under the current emissive flags
    // (render/emitter_quads.h); a chunk meshed before they changed has none until it is set again,
    // and sky rays keep finding its emitters.
    std::unordered_map<world::LodCoord, std::vector<world::Quad>, world::LodCoordHash> emissive_quads;
    std::array<Buffer, kFramesInFlight> emitter_quad_lists; // EmitterQuad[kMaxEmitterQuads] per frame slot.
    std::array<Buffer, kFramesInFlight> emitter_bound_lists; // EmitterBound[kMaxEmitterChunks] per frame slot.
    void update_emitters();
    struct EmitterCounts {
        uint32_t chunks = 0, quads = 0, covered = 0; // FrameParams flags.y, z, w.
    };
    EmitterCounts write_emitter_list(world::BlockPos camera_block, bool sample_faces);
    bool frame_samples_faces = false; // write_params() listed emitter faces: record_trace() picks that pipeline.
    // Where two different transparent blocks touch (render/touching_pairs.h): while nowhere, frames
    // trace the pipeline variant with no coincident-face probe (a world whose one see-through block
    // is water never probes, nor one whose glass touches no water).
    TouchingPairs touching;
    bool frame_probes = false; // This frame traces with the probing variant (prepare_frame).
    // Drawn chunks whose quads hold a see-through block under the current materials (chunk_traits
    // not opaque): while none is (and the eye is in none), frames trace the variant with no
    // see-through code (kSeeThrough).
    std::unordered_set<world::LodCoord, world::LodCoordHash> see_through_set;
    // The variant prepare_frame picked (rt_pipeline.h).
    SeeThrough frame_see_through = SeeThrough::kPlain;
    VkFormat target_format = VK_FORMAT_R8G8B8A8_UNORM;
    Buffer readback;
    Buffer gbuffer_readback; // The G-buffer's four images, one after another (render() with a GBufferImage).
    RenderStats stats;
    std::unique_ptr<Presenter> presenter; // With a window.
    std::unique_ptr<UiPass> ui; // The game's UI (set_ui), made at the first set_ui / set_ui_texture.
    UiPass& ui_pass() {
        if (!ui)
            ui = std::make_unique<UiPass>(*ctx, VK_FORMAT_R8G8B8A8_UNORM); // The target's view.
        return *ui;
    }
    void record_ui(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
        if (ui && !ui->empty())
            ui->record(cmd, target().handle(), target().view(), width, height);
    }
    // A frame that could not be recorded whole: what was recorded (uploads, builds) is submitted
    // so the scene's state stays true, and nothing is traced or read back.
    Status abandon_frame(Status why) {
        stamped[ctx->frame_slot()] = false;
        if (!ctx->end_frame())
            return lost_error();
        return why;
    }
    static Status lost_error() {
        return Error{"the GPU device was lost (a hang or a driver reset): frames fail until the renderer is "
                     "recreated"};
    }
    std::chrono::steady_clock::time_point last_present{};
    // Timestamps (kStamps per frame slot): frame start, after BLAS builds, after the TLAS, after
    // the trace, after the copy, after the denoiser (written between trace and copy, always).
    // Null when the queue family has no timestamps.
    static constexpr uint32_t kStamps = 6;
    // The denoiser (render/denoiser.h), made at the first frame that uses it, and the camera of
    // the last frame it ran on (its history's; reprojection).
    std::unique_ptr<Denoiser> denoiser;
    // The light cache (render/light_cache.h), made at the first frame that uses it;
    // whether the frame being recorded uses it.
    std::unique_ptr<LightCache> light_cache;
    bool frame_cached = false;
    uint32_t light_cache_cell_limit = 0; // Renderer::limit_light_cache_cells.
    // RenderSettings::split_hits: the paths between the passes and their lists (shaders/shared/
    // render_types.h, TracePush; made by prepare_frame). One for both frame slots: the
    // frame-start barrier (record_scene) ends the last frame's passes before this frame's start,
    // and a replaced buffer is retired with this frame. split_hits(s): the hits a
    // frame of `s` traces in passes of their own (0: one pass, no paths kept). A later pass runs
    // one row of an invocation per pixel: frames wider than the device allows in one row (the
    // compute limits bound a trace's width) take one pass.
    Buffer path_states;
    uint32_t split_hits(const RenderSettings& s) const {
        const VkPhysicalDeviceLimits& l = ctx->limits();
        const uint64_t row = uint64_t(l.maxComputeWorkGroupCount[0]) * l.maxComputeWorkGroupSize[0];
        const bool applies = s.pipeline == PipelineKind::RayTraced && s.mode == ShadingMode::Full &&
                             uint64_t(s.width) * s.height <= row;
        return applies ? std::min({s.split_hits, s.max_bounces, gpu::kMaxSplitHits}) : 0u;
    }
    static VkDeviceSize path_counters_offset(VkDeviceSize pixels) {
        return pixels * (sizeof(gpu::PathState) + 2 * sizeof(uint32_t));
    }
    // RenderSettings::see_through_check: the counts and the per-pixel marks of the pixels the
    // second dispatch traces again (gpu::kCheckMark; one for both frame slots, as path_states),
    // each slot's copy of its counts (read once the slot's fence has signalled: read_check), what
    // the slot's last frame did (gpu::kCheckOff, kCheckMark: checked, kCheckCount: counted) over
    // how many pixels. What read_check last read: the share of pixels whose view ray met a
    // see-through face (0 before any) and, of a checked frame, the share marked (-1: none since
    // prepare_check last looked). check_hold: frames left to trace in one dispatch after a checked
    // frame marked over the share (a glass roof: few view rays meet it, every shadow ray does),
    // each such frame holding twice as long as the last, up to kCheckHoldMax. frame_check: what
    // the frame being recorded does.
    Buffer check_marks;
    std::array<Buffer, kFramesInFlight> check_counts;
    std::array<uint32_t, kFramesInFlight> check_modes{};
    std::array<uint64_t, kFramesInFlight> check_pixels{};
    float view_share = 0.f, marked_share = -1.f;
    static constexpr uint32_t kCheckHoldFirst = 8, kCheckHoldMax = 128;
    uint32_t check_hold = 0, check_hold_next = kCheckHoldFirst;
    uint32_t frame_check = gpu::kCheckOff;
    // Whether a frame of `s` may trace with the check: asked for (kAuto: not on a CPU device),
    // see-through blocks drawn, the eye in none, the whole frame in one dispatch (no split hits,
    // no light cache), Full or Visibility mode.
    bool check_applies(const RenderSettings& s, bool eye_in) const {
        const bool on = s.see_through_check == RenderSettings::SeeThroughCheck::kOn ||
                        (s.see_through_check == RenderSettings::SeeThroughCheck::kAuto &&
                         ctx->report().type != DeviceType::Cpu);
        return on && frame_see_through != SeeThrough::kNone && !eye_in &&
               s.pipeline == PipelineKind::RayTraced && s.mode != ShadingMode::Flat && !cache_active(s) &&
               split_hits(s) == 0;
    }
    // The frame's check (kCheckMark where the view share read is at most
    // RenderSettings::see_through_check_share and no hold runs, else kCheckCount) and its marks,
    // count read-back and pipeline variants; kCheckOff where memory for one ran out: the frame
    // then traces in one dispatch with the see-through code (the same image), and a later frame
    // tries again.
    uint32_t prepare_check(const RenderSettings& s);
    void record_checked_trace(VkCommandBuffer cmd, uint32_t width, uint32_t height);
    void record_check_count(VkCommandBuffer cmd); // The counts into the slot's read-back.
    // The slot's last frame's check, once its fence has signalled: its RenderStats and shares.
    void read_check(RenderStats& out);
    EditMarks edit_marks; // Edits since the last traced frame (note_edit); write_params takes them.
    static bool cache_active(const RenderSettings& s) {
        return s.light_cache && s.pipeline == PipelineKind::RayTraced && s.mode == ShadingMode::Full;
    }
    // The mirror bounces a cached frame of `s` caches after its primary hit.
    static uint32_t cached_bounces(const RenderSettings& s) { return std::min(s.max_bounces, gpu::kMaxCachedBounces); }
    Camera denoised_camera;
    bool denoised_last_frame = false;
    // The sampling settings of the history: frames of other counts are not averaged together
    // (a sweep's accumulated rows would start from the previous configuration's frames).
    RenderSettings denoised_settings;
    VkQueryPool queries = VK_NULL_HANDLE;
    double ms_per_tick = 0;
    std::array<bool, kFramesInFlight> stamped{}; // The slot's last frame wrote its timestamps.
    std::array<bool, kFramesInFlight> slot_denoised{}; // The slot's last frame ran the denoiser (stamp 3..5).
    // Auto exposure (Exposure::automatic): each frame slot's meter (gpu::ExposureMeter, zeroed
    // when recorded, summed by raygen), whether the slot's last frame metered, the adapted EV100
    // (unset: no metered frame since the renderer was made or drew a manual frame) and when it
    // was last updated. frame_ev100: the exposure of the frame last recorded.
    std::array<Buffer, kFramesInFlight> meters;
    std::array<bool, kFramesInFlight> metering{};
    std::optional<float> adapted_ev100;
    std::chrono::steady_clock::time_point adapted_at{};
    float frame_ev100 = 0.f;
    static bool metered(const RenderSettings& s) {
        return s.exposure.automatic && s.mode == ShadingMode::Full && s.pipeline == PipelineKind::RayTraced;
    }
    void read_meter(float adapt_speed);
    Result<RenderImage> render_frame(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer);

    ~Impl() {
        if (!ctx)
            return;
        ctx->wait_idle();
        ui.reset();
        presenter.reset();
        vkDestroyDescriptorPool(ctx->device(), pool, nullptr);
        if (queries)
            vkDestroyQueryPool(ctx->device(), queries, nullptr);
    }
    bool create_descriptors(); // False: out of memory for the frame parameters.
    bool create_queries();     // False: out of memory for the timestamps' query pool.
    // Renderer::create's error for `what`, naming the call that failed when one did.
    Error create_error(const char* what) const {
        const std::string& call = ctx->last_create_failure();
        return Error{std::string("cannot create the renderer: out of GPU memory for ") + what +
                     (call.empty() ? "" : " (" + call + ")")};
    }
    void stamp(VkCommandBuffer cmd, uint32_t i) {
        if (queries)
            vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries, ctx->frame_slot() * kStamps + i);
    }
    void read_stamps(RenderStats& out);
    // The scene's counters of the last frame's builds (builds, refits, memory...).
    void fill_accel_stats(RenderStats& out) const {
        const AccelStats& a = accel->stats();
        out.blas_builds = a.blas_builds;
        out.blas_refits = a.blas_refits;
        out.instances = a.instances;
        out.blas_compactions = a.blas_compactions;
        out.hot_chunks = a.hot_chunks;
        out.failed_chunks = a.failed_chunks;
        out.triangles = a.triangles;
        out.upload_bytes = a.upload_bytes;
        out.instance_writes = a.instance_writes;
        out.rebases = a.rebases;
        out.level_instances = a.level_instances;
        out.level_gpu_bytes = a.level_gpu_bytes;
        out.memory = accel->memory();
        out.raster_chunks = raster_chunks;
        out.raster_transparent_chunks = raster_transparent_chunks;
        out.touching_probes = frame_probes;
        out.see_through_code = frame_see_through != SeeThrough::kNone;
    }
    bool update_materials();
    Image& target() { return targets[ctx->frame_slot()]; }
    bool ensure_target(uint32_t width, uint32_t height);
    // After begin_frame, before recording: every frame resource but the scene's acceleration
    // structures (target, G-buffer, materials, emitter list, read-backs, denoiser, UI). An
    // error names the one that could not be allocated; a later frame tries again.
    Status prepare_frame(const RenderSettings& s, bool readback, bool gbuffer);
    Status prepare_passes(const RenderSettings& s); // prepare_frame's second half.
    Error not_created(const char* what) const;
    void write_params(const RenderSettings& s, const Camera& cam);
    void write_descriptors();
    Status record_scene(VkCommandBuffer cmd, const Camera& cam);
    void record_shading(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam);
    void record_trace(VkCommandBuffer cmd, const RenderSettings& s);
    void record_raster(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam);
    uint32_t raster_chunks = 0; // Chunks the last frame's raster pass drew.
    uint32_t raster_transparent_chunks = 0; // Of those, drawn again by its transparent pass.
    static bool denoise_active(const RenderSettings& s) {
        return s.pipeline == PipelineKind::RayTraced && s.mode == ShadingMode::Full && (s.denoise || s.accumulate > 1);
    }
    void record_denoise(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam);
    void record_readback(VkCommandBuffer cmd, uint32_t width, uint32_t height);
    void record_gbuffer_readback(VkCommandBuffer cmd, const RenderSettings& s);
    // After the frame `s` recorded with record_gbuffer_readback (frame_ev100 still its exposure).
    void read_gbuffer(GBufferImage& out, const RenderSettings& s) const;
};

} // namespace vx::render
