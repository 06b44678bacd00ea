#include "render/renderer.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include <glm/gtc/packing.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include "render/commands.h"
#include "render/context.h"
#include "render/denoiser.h"
#include "render/emitter_quads.h"
#include "render/gbuffer.h"
#include "render/gpu_layouts.h"
#include "render/edit_marks.h"
#include "render/light_cache.h"
#include "render/present.h"
#include "render/raster_pipeline.h"
#include "render/rt_pipeline.h"
#include "render/scene_accel.h"
#include "render/ui_pass.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {

// The stages that write the target and the G-buffer in a traced frame: the ray generation, then
// the light cache's resolve pass (a compute shader) when the frame caches.
constexpr VkPipelineStageFlags2 kTraceStages =
    VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
// The G-buffer read-back buffer: per pixel, radiance, normal_depth, reflected and the denoiser's
// output (8 bytes each: RGBA16F), then albedo (4: RGBA8). Section k starts at pixels *
// kGBufferSectionAt[k]. The 8-byte texels come first so every copy's bufferOffset is a multiple
// of its texel size at any pixel count (VUID-vkCmdCopyImageToBuffer-bufferOffset-01558: albedo
// second left the later sections 4 bytes off whenever width x height was odd).
enum GBufferSection { kRadianceSection, kNormalDepthSection, kReflectedSection, kDenoisedSection, kAlbedoSection };
constexpr VkDeviceSize kGBufferSectionAt[5] = {0, 8, 16, 24, 32};
constexpr VkDeviceSize kGBufferReadbackPixelBytes = 36;

// An exponent outside (0, 1] (NaN too) counts as 1: pow() of NaN would make every count
// undefined. The facade and `vx render` refuse such values (weight_exponent_valid).
static float effective_weight_exponent(const RenderSettings& s) {
    return weight_exponent_valid(s.weight_exponent) ? s.weight_exponent : 1.f;
}

// The light cache's cell width, clamped; not finite: the default (renderer.h).
static float effective_cell_pixels(const RenderSettings& s) {
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
                             !cache_active(s) && uint64_t(s.width) * s.height <= row;
        return applies ? std::min({s.split_hits, s.max_bounces, gpu::kMaxSplitHits}) : 0u;
    }
    static VkDeviceSize path_counters_offset(VkDeviceSize pixels) {
        return pixels * (sizeof(gpu::PathState) + 2 * sizeof(uint32_t));
    }
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
    }
    bool update_materials();
    Image& target() { return targets[ctx->frame_slot()]; }
    bool ensure_target(uint32_t width, uint32_t height);
    // After begin_frame, before recording: every frame resource but the scene's acceleration
    // structures (target, G-buffer, materials, emitter list, read-backs, denoiser, UI). An
    // error names the one that could not be allocated; a later frame tries again.
    Status prepare_frame(const RenderSettings& s, bool readback, bool gbuffer);
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

Renderer::Renderer() : m(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RendererCreateInfo& info) {
    ContextCreateInfo ci;
    ci.validation = info.validation;
    ci.sync_validation = info.sync_validation;
    ci.device = info.device;
    ci.window = info.glfw_window;
    ci.fail_allocations = info.fail_allocations;
    Result<std::unique_ptr<Context>> ctx = Context::create(ci);
    if (!ctx)
        return Error{ctx.error()};
    std::unique_ptr<Renderer> r(new Renderer());
    r->m->ctx = std::move(*ctx);
    r->m->ctx->allocator().set_budget(info.gpu_memory_budget_bytes);
    r->m->accel = std::make_unique<SceneAccel>(*r->m->ctx, SceneAccelCreateInfo{info.allow_refit, info.hot_frames, info.max_refits});
    r->m->pipeline = std::make_unique<RtPipeline>(*r->m->ctx);
    // Out of memory here is the device's state, not our bug: an error, as for a frame (it was
    // an assertion; a renderer recreated after a device loss meets a full device).
    if (!r->m->pipeline->valid())
        return r->m->create_error("the ray tracing pipeline");
    if (!r->m->create_descriptors())
        return r->m->create_error("the frame parameters");
    if (!r->m->create_queries())
        return r->m->create_error("the frame timestamps");
    r->set_registry(world::BlockRegistry::default_registry());
    if (info.glfw_window) {
        r->m->presenter = std::make_unique<Presenter>(*r->m->ctx, info.vsync);
        if (!r->m->presenter->valid())
            return Error{"cannot create the renderer: cannot present to the window (" +
                         r->m->ctx->last_create_failure() + ")"};
        r->m->target_format = r->m->presenter->target_format();
    }
    return r;
}

bool Renderer::Impl::create_descriptors() {
    const VkDescriptorPoolSize sizes[] = {
        {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, kFramesInFlight},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 8 * kFramesInFlight}, // Output + 7 G-buffer images.
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFramesInFlight},
    };
    VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    ci.maxSets = kFramesInFlight;
    ci.poolSizeCount = uint32_t(std::size(sizes));
    ci.pPoolSizes = sizes;
    if (ctx->create_call("vkCreateDescriptorPool (rt descriptor pool)",
                         [&] { return vkCreateDescriptorPool(ctx->device(), &ci, nullptr, &pool); }) != VK_SUCCESS)
        return false;
    ctx->set_name(pool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "rt descriptor pool");
    std::array<VkDescriptorSetLayout, kFramesInFlight> layouts;
    layouts.fill(pipeline->set_layout());
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = kFramesInFlight;
    ai.pSetLayouts = layouts.data();
    if (ctx->create_call("vkAllocateDescriptorSets (rt descriptor set)",
                         [&] { return vkAllocateDescriptorSets(ctx->device(), &ai, sets.data()); }) != VK_SUCCESS)
        return false; // The pool frees whatever was allocated.
    for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        ctx->set_name(sets[i], VK_OBJECT_TYPE_DESCRIPTOR_SET, "rt descriptor set");
        params[i] = Buffer::create(*ctx, {sizeof(gpu::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                          MemoryUse::Upload, 0, "frame params"});
        if (!params[i].valid())
            return false;
    }
    return true;
}

bool Renderer::Impl::create_queries() {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, families.data());
    if (families[ctx->queue_family()].timestampValidBits == 0 || ctx->limits().timestampPeriod <= 0.f)
        return true; // No timestamps on this queue: stats without GPU times.
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = kStamps * kFramesInFlight;
    if (ctx->create_call("vkCreateQueryPool (frame timestamps)",
                         [&] { return vkCreateQueryPool(ctx->device(), &ci, nullptr, &queries); }) != VK_SUCCESS)
        return false;
    ctx->set_name(queries, VK_OBJECT_TYPE_QUERY_POOL, "frame timestamps");
    ms_per_tick = double(ctx->limits().timestampPeriod) * 1e-6; // timestampPeriod: ns per tick.
    return true;
}

// The timestamps of the frame last submitted in this slot, once its fence has signalled.
void Renderer::Impl::read_stamps(RenderStats& out) {
    const uint32_t slot = ctx->frame_slot();
    if (!queries || !stamped[slot])
        return;
    uint64_t t[kStamps];
    if (!ctx->check_device(vkGetQueryPoolResults(ctx->device(), queries, ctx->frame_slot() * kStamps, kStamps, sizeof t,
                                                 t, sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
                           "vkGetQueryPoolResults"))
        return;
    auto ms = [&](int i) { return double(t[i + 1] - t[i]) * ms_per_tick; };
    out.gpu_blas_ms = ms(0);
    out.gpu_tlas_ms = ms(1);
    out.gpu_trace_ms = ms(2);
    out.gpu_denoise_ms = double(t[5] - t[3]) * ms_per_tick;
    out.gpu_copy_ms = double(t[4] - t[5]) * ms_per_tick;
    out.gpu_frame_ms = double(t[4] - t[0]) * ms_per_tick;
}

// EV100 that shows a frame of log-average luminance 2^log2_average (radiance units) at
// mid-grey: kNitsPerUnit * L / (1.2 * 2^EV100) = kMidGreyInput (tonemap.h).
static float metered_ev100(float log2_average) {
    return log2_average + std::log2(gpu::kNitsPerUnit / (1.2f * gpu::kMidGreyInput));
}

// The meter of the frame last submitted in this slot, once its fence has signalled: moves the
// adapted exposure towards it (Exposure::adapt_speed).
void Renderer::Impl::read_meter(float adapt_speed) {
    const uint32_t slot = ctx->frame_slot();
    if (!metering[slot])
        return;
    metering[slot] = false;
    gpu::ExposureMeter m;
    std::memcpy(&m, meters[slot].mapped(), sizeof m);
    if (m.count == 0)
        return;
    const float target =
        metered_ev100(float(double(m.log_sum) / m.count / gpu::kMeterScale) + gpu::kMeterLogMin);
    const auto now = std::chrono::steady_clock::now();
    if (!adapted_ev100) {
        adapted_ev100 = target;
    } else {
        const float dt = std::clamp(std::chrono::duration<float>(now - adapted_at).count(), 0.f, 1.f);
        *adapted_ev100 += (target - *adapted_ev100) * (1.f - std::exp(-std::max(adapt_speed, 0.f) * dt));
    }
    adapted_at = now;
}

bool Renderer::Impl::update_materials() {
    const uint32_t count = std::max<uint32_t>(uint32_t(registry.size()), max_block_id + 1);
    if (!materials_dirty && count <= material_count)
        return true;
    std::vector<gpu::Material> table(count);
    for (uint32_t id = 0; id < count; ++id) {
        const world::BlockInfo b = registry.info(world::BlockId(id));
        table[id].albedo_reflectivity = glm::vec4(b.albedo, b.reflectivity);
        // w: transparent (the shaders' vx_transparent); air never reaches a shader.
        table[id].emission = glm::vec4(b.emission, registry.is_opaque(world::BlockId(id)) ? 0.f : 1.f);
    }
    Buffer table_buffer = upload_buffer(*ctx, table.data(), table.size() * sizeof(gpu::Material),
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "materials");
    if (!table_buffer.valid())
        return false; // Logged by Buffer::create; the old table stays.
    materials = std::move(table_buffer);
    material_count = count;
    materials_dirty = false;
    return true;
}

void Renderer::Impl::update_emitters() {
    if (emitters_dirty) { // New materials: O(chunks), once.
        emitter_set.clear();
        for (const auto& [c, ids] : chunk_blocks)
            if (emits(ids))
                emitter_set.insert(c);
        emitters_dirty = false;
        emitter_list_dirty = true;
    }
    if (emitter_list_dirty) { // O(emissive chunks).
        emitter_chunks.assign(emitter_set.begin(), emitter_set.end());
        emitter_list_dirty = false;
    }
}

// The kMaxEmitterChunks emissive chunks nearest the camera (of any level: by the distance from
// the camera's block to the chunk's box), relative to the render origin (SceneAccel::origin()),
// into this frame slot's list; with sample_faces, the faces of as many of them, nearest first, as
// fit in the frame slot's face list (render/emitter_quads.h). Returns the counts.
Renderer::Impl::EmitterCounts Renderer::Impl::write_emitter_list(world::BlockPos camera_block, bool sample_faces) {
    Buffer& list = emitter_lists[ctx->frame_slot()]; // Allocated by prepare_frame.
    auto distance2 = [&](world::LodCoord c) {
        const world::LodBlockBox box = world::lod_block_box(c);
        const glm::dvec3 d = glm::dvec3(glm::max(box.min - camera_block, world::BlockPos(0))) +
                             glm::dvec3(glm::max(camera_block - box.max, world::BlockPos(0)));
        return glm::dot(d, d);
    };
    const size_t n = std::min<size_t>(emitter_chunks.size(), gpu::kMaxEmitterChunks);
    // Ties by coordinate: the list does not depend on the set's hash order.
    std::partial_sort(emitter_chunks.begin(), emitter_chunks.begin() + ptrdiff_t(n), emitter_chunks.end(),
                      [&](world::LodCoord a, world::LodCoord b) {
                          const double la = distance2(a), lb = distance2(b);
                          return la != lb ? la < lb
                                          : std::tie(a.level, a.chunk.x, a.chunk.y, a.chunk.z) <
                                                std::tie(b.level, b.chunk.x, b.chunk.y, b.chunk.z);
                      });
    auto* dst = static_cast<glm::vec4*>(list.mapped());
    for (size_t i = 0; i < n; ++i) // 64-bit difference, then float, as the TLAS's translations.
        dst[i] = glm::vec4(glm::vec3(world::lod_origin(emitter_chunks[i]) - accel->origin()),
                           float(world::lod_chunk_blocks(emitter_chunks[i].level)));
    EmitterCounts counts{uint32_t(n), 0, 0};
    if (!sample_faces)
        return counts;
    auto quads_of = [&](world::LodCoord c) -> const std::vector<world::Quad>* {
        const auto it = emissive_quads.find(c);
        return it == emissive_quads.end() ? nullptr : &it->second;
    };
    auto emission_of = [&](world::BlockId id) { return registry.info(id).emission; };
    auto* faces = static_cast<gpu::EmitterQuad*>(emitter_quad_lists[ctx->frame_slot()].mapped());
    auto* bounds = static_cast<gpu::EmitterBound*>(emitter_bound_lists[ctx->frame_slot()].mapped());
    const EmitterListSize written =
        write_emitter_quads(std::span(emitter_chunks.data(), n), quads_of, emission_of, accel->origin(),
                            std::span(faces, gpu::kMaxEmitterQuads), std::span(bounds, gpu::kMaxEmitterChunks));
    counts.quads = written.quads;
    counts.covered = written.covered_chunks;
    return counts;
}

bool Renderer::Impl::ensure_target(uint32_t width, uint32_t height) {
    Image& t = target();
    if (t.valid() && t.width() == width && t.height() == height)
        return true;
    // Resized: the old image goes to this frame's retire list; the slot's last frame is done.
    t = Image::create(*ctx, {width, height, target_format,
                             VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, // The raster pipeline draws into it.
                             "render target", VK_FORMAT_R8G8B8A8_UNORM});
    if (!t.valid())
        return false; // Logged by Image::create.
    GBuffer& g = gbuffers[ctx->frame_slot()];
    g.radiance = Image::create(*ctx, {width, height, kRadianceFormat, kGBufferUsage, "gbuffer radiance"});
    g.albedo = Image::create(*ctx, {width, height, kAlbedoFormat, kGBufferUsage, "gbuffer albedo"});
    g.normal_depth = Image::create(*ctx, {width, height, kNormalDepthFormat, kGBufferUsage, "gbuffer normal depth"});
    g.reflected = Image::create(*ctx, {width, height, kReflectedFormat, kGBufferUsage, "gbuffer reflected"});
    g.mirror_light = Image::create(*ctx, {width, height, kMirrorLightFormat, kGBufferUsage, "gbuffer mirror light"});
    g.mirror_albedo = Image::create(*ctx, {width, height, kMirrorAlbedoFormat, kGBufferUsage, "gbuffer mirror albedo"});
    g.mirror_normal_depth =
        Image::create(*ctx, {width, height, kMirrorNormalDepthFormat, kGBufferUsage, "gbuffer mirror normal depth"});
    if (g.radiance.valid() && g.albedo.valid() && g.normal_depth.valid() && g.reflected.valid() &&
        g.mirror_light.valid() && g.mirror_albedo.valid() && g.mirror_normal_depth.valid())
        return true;
    t.reset(); // The next frame makes the target and the whole G-buffer again.
    return false;
}

Status Renderer::Impl::prepare_frame(const RenderSettings& s, bool with_readback, bool with_gbuffer) {
    const std::string size = std::to_string(s.width) + "x" + std::to_string(s.height);
    auto out_of_memory = [&](const char* what) {
        return Error{std::string("out of GPU memory for ") + what + " of a " + size +
                     " frame: nothing drawn; a later frame (or a smaller size) tries again"};
    };
    // A pipeline made at its first frame that the device refused (it was a VK_CHECK abort): it is
    // dropped, and the next frame that needs it makes it again.
    auto not_created = [&](const char* what) {
        return Error{std::string("out of GPU memory for ") + what + " (" + ctx->last_create_failure() +
                     "): nothing drawn; a later frame tries again"};
    };
    if (!ensure_target(s.width, s.height))
        return out_of_memory("the render target and G-buffer");
    if (!update_materials())
        return out_of_memory("the material table");
    // The frame slot's emitter lists (written by write_emitter_list each frame), made once.
    auto upload_list = [&](Buffer& b, VkDeviceSize bytes, const char* name) {
        if (!b.valid())
            b = Buffer::create(*ctx, {bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload, 0, name});
        return b.valid();
    };
    const uint32_t slot = ctx->frame_slot();
    if (!upload_list(emitter_lists[slot], gpu::kMaxEmitterChunks * sizeof(glm::vec4), "emitter chunks"))
        return out_of_memory("the emitter list");
    if (!upload_list(emitter_quad_lists[slot], gpu::kMaxEmitterQuads * sizeof(gpu::EmitterQuad), "emitter faces"))
        return out_of_memory("the emitter faces");
    if (!upload_list(emitter_bound_lists[slot], gpu::kMaxEmitterChunks * sizeof(gpu::EmitterBound), "emitter bounds"))
        return out_of_memory("the emitter bounds");
    // The pipeline that samples emitter faces, once some drawn chunk emits (write_params may pick it).
    update_emitters();
    if (s.emitter_sampling && !emitter_set.empty() && !pipeline->ensure_faces_variant())
        return out_of_memory("the emitter faces' pipeline");
    const VkDeviceSize pixels = VkDeviceSize(s.width) * s.height;
    if (with_readback && (!readback.valid() || readback.size() != pixels * 4)) {
        readback = Buffer::create(*ctx, {pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0, "render readback"});
        if (!readback.valid())
            return out_of_memory("the image read-back");
    }
    const VkDeviceSize gbuffer_bytes = pixels * kGBufferReadbackPixelBytes;
    if (with_gbuffer && (!gbuffer_readback.valid() || gbuffer_readback.size() != gbuffer_bytes)) {
        gbuffer_readback =
            Buffer::create(*ctx, {gbuffer_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0, "gbuffer readback"});
        if (!gbuffer_readback.valid())
            return out_of_memory("the G-buffer read-back");
    }
    if (s.pipeline == PipelineKind::Raster) {
        if (!raster)
            raster = std::make_unique<RasterPipeline>(*ctx, VK_FORMAT_R8G8B8A8_UNORM); // The target's view.
        if (!raster->valid()) {
            raster.reset(); // Never recorded: its pipeline layout is destroyed at once.
            return not_created("the raster pipeline");
        }
        if (!raster->ensure_depth(s.width, s.height))
            return out_of_memory("the raster depth buffer");
    }
    if (denoise_active(s)) {
        if (!denoiser) {
            denoiser = std::make_unique<Denoiser>(*ctx, s.width, s.height);
            if (!denoiser->valid()) {
                denoiser.reset(); // Never recorded: its pool and layouts go at once.
                return not_created("the denoiser's pipelines");
            }
        } else if (!denoiser->ready() || denoiser->width() != s.width || denoiser->height() != s.height)
            denoiser->resize(s.width, s.height);
        if (!denoiser->ready())
            return out_of_memory("the denoiser's images");
    }
    if (split_hits(s) > 0) {
        const VkDeviceSize bytes = path_counters_offset(pixels) + gpu::kMaxSplitHits * sizeof(uint32_t);
        if (!path_states.valid() || path_states.size() != bytes) {
            path_states = Buffer::create(*ctx, {bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           MemoryUse::Device, 0,
                                           "path states between the trace passes"});
            if (!path_states.valid())
                return out_of_memory("the paths between the trace passes");
        }
    }
    if (cache_active(s)) {
        if (!light_cache)
            light_cache = std::make_unique<LightCache>(*ctx, pipeline->set_layout());
        if (!light_cache->valid()) {
            light_cache.reset();
            return not_created("the light cache's pipeline");
        }
        light_cache->limit_cells_for_testing(light_cache_cell_limit);
        if (!light_cache->ensure(s.width, s.height, cached_bounces(s)))
            return out_of_memory("the light cache");
    }
    if (ui && !ui->prepare())
        return out_of_memory("the UI");
    Buffer& meter = meters[ctx->frame_slot()];
    if (metered(s) && !meter.valid()) {
        meter = Buffer::create(*ctx, {sizeof(gpu::ExposureMeter), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                      MemoryUse::Readback, 0, "exposure meter"});
        if (!meter.valid())
            return out_of_memory("the exposure meter");
    }
    return {};
}

// FrameParams::haze (shaders/shared/haze.glsl) of a frame; zero (no haze) but in Full mode.
// Koschmieder's visibility, where contrast falls to 2%: extinction = ln(50) / visibility.
// `origin`: the render origin (SceneAccel::origin()), the frame of every shader position.
static glm::vec4 haze_params(const RenderSettings& s, world::BlockPos origin) {
    const Haze& h = s.haze;
    if (!h.enabled || s.mode != ShadingMode::Full || !(h.visibility > 0.f) || std::isinf(h.visibility))
        return glm::vec4(0.f);
    const double height = double(origin.y) - h.base_height; // Of origin-relative y = 0.
    return glm::vec4(float(std::log(50.0) / double(h.visibility)), std::max(h.height_falloff, 0.f), float(height), 0.f);
}

void Renderer::Impl::write_params(const RenderSettings& s, const Camera& cam) {
    gpu::FrameParams p{};
    const glm::vec3 fwd = glm::normalize(cam.forward);
    const glm::vec3 right = glm::normalize(glm::cross(fwd, cam.up));
    const glm::vec3 up = glm::cross(right, fwd);
    // Positions relative to the render origin (SceneAccel::origin(), the TLAS's): 64-bit
    // differences, then float. At the origin's block the camera is at cam.offset exactly.
    const world::BlockPos origin = accel->origin();
    p.camera_origin = glm::vec4(glm::vec3(cam.block - origin) + cam.offset, std::tan(glm::radians(cam.fov_y_degrees) * 0.5f));
    p.camera_forward = glm::vec4(fwd, float(s.width) / float(s.height));
    p.camera_right = glm::vec4(right, 0.f);
    p.camera_up = glm::vec4(up, 0.f);
    p.sky_color = glm::vec4(s.sky, 0.f);
    const world::BlockPos rel = s.light.block - origin;
    p.light_corner = glm::vec4(glm::vec3(rel) + s.light.offset, 0.f);
    p.light_edge_u = glm::vec4(s.light.edge_u, 0.f);
    p.light_edge_v = glm::vec4(s.light.edge_v, 0.f);
    p.light_emission = glm::vec4(s.light.emission, 0.f);
    // Normalised in double: a float length of {1e20, 1e20, 1e20} is infinite (the shader got a
    // zero direction and sampled a ring round the horizon), of {1e-25, ...} zero (no sun).
    const glm::dvec3 sun(s.sun.direction);
    const double sun_len = glm::length(sun);
    p.sun_direction = glm::vec4(sun_len > 0.0 ? glm::vec3(sun / sun_len) : glm::vec3(0, 1, 0),
                                std::cos(glm::radians(s.sun.angular_radius_degrees)));
    p.sun_irradiance = glm::vec4(sun_len > 0.f ? s.sun.irradiance : glm::vec3(0.f), 0.f);
    p.sky_light = glm::vec4(s.sky * std::max(s.sky_light, 0.f), 0.f);
    p.size_samples = glm::uvec4(s.width, s.height, s.shadow_samples, std::min(s.max_bounces, kMaxMirrorBounces));
    const uint32_t mode = s.mode == ShadingMode::Flat ? gpu::kModeFlat
                          : s.mode == ShadingMode::Full ? gpu::kModeFull
                                                        : gpu::kModeVisibility;
    p.mode_seed = glm::uvec4(mode, s.seed, material_count, s.bounce_shadow_samples.value_or(s.shadow_samples));
    const EmitterCounts emitters = write_emitter_list(cam.block, s.emitter_sampling);
    frame_samples_faces = emitters.quads > 0;
    p.flags = glm::uvec4(s.sky_access ? 1u : 0u, emitters.chunks, emitters.quads, emitters.covered);
    const float exponent = effective_weight_exponent(s);
    p.sampling = glm::uvec4(s.samples_by_weight ? 1u : 0u, glm::floatBitsToUint(exponent), 0u, 0u);
    const uint32_t slot = ctx->frame_slot();
    metering[slot] = metered(s);
    if (metering[slot]) {
        VX_ASSERT(meters[slot].valid()); // Made by prepare_frame.
        std::memset(meters[slot].mapped(), 0, sizeof(gpu::ExposureMeter)); // The slot's last frame is done.
        p.exposure_meter = meters[slot].address();
    }
    p.exposure = glm::vec4(gpu::vx_exposure_scale(frame_ev100), metering[slot] ? 1.f : 0.f, 0.f, 0.f);
    p.haze = haze_params(s, origin);
    p.emitter_chunks = emitter_lists[ctx->frame_slot()].address();
    p.emitter_quads = emitter_quad_lists[ctx->frame_slot()].address();
    p.emitter_bounds = emitter_bound_lists[ctx->frame_slot()].address();
    p.chunk_table = accel->chunk_table();
    p.materials = materials.address();
    frame_cached = cache_active(s);
    if (frame_cached) { // Made and sized by prepare_frame.
        const float cell_pixels = effective_cell_pixels(s);
        p.cache = glm::uvec4(light_cache->cells(), cached_bounces(s), std::bit_cast<uint32_t>(cell_pixels), 0u);
        p.cache_table = light_cache->table();
        p.cache_records = light_cache->records();
    }
    edit_marks.write(p, origin);
    edit_marks.clear(); // This frame's denoiser has them.
    std::memcpy(params[ctx->frame_slot()].mapped(), &p, sizeof p);
}

void Renderer::Impl::write_descriptors() {
    const uint32_t slot = ctx->frame_slot();
    VkAccelerationStructureKHR tlas = accel->tlas();
    VkWriteDescriptorSetAccelerationStructureKHR as_info{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
    as_info.accelerationStructureCount = 1;
    as_info.pAccelerationStructures = &tlas;
    const GBuffer& g = gbuffers[slot];
    const VkDescriptorImageInfo images[] = {
        {VK_NULL_HANDLE, target().view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.radiance.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.albedo.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.normal_depth.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.reflected.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.mirror_light.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.mirror_albedo.view(), VK_IMAGE_LAYOUT_GENERAL},
        {VK_NULL_HANDLE, g.mirror_normal_depth.view(), VK_IMAGE_LAYOUT_GENERAL},
    };
    const uint32_t image_bindings[] = {kBindingOutput,    kBindingRadiance,    kBindingAlbedo,
                                       kBindingNormalDepth, kBindingReflected, kBindingMirrorLight,
                                       kBindingMirrorAlbedo, kBindingMirrorNormalDepth};
    constexpr uint32_t kImages = uint32_t(std::size(image_bindings));
    VkDescriptorBufferInfo buffer_info{params[slot].handle(), 0, sizeof(gpu::FrameParams)};
    VkWriteDescriptorSet w[2 + kImages];
    for (uint32_t i = 0; i < 2 + kImages; ++i) {
        w[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w[i].dstSet = sets[slot];
        w[i].descriptorCount = 1;
    }
    w[0].dstBinding = kBindingTlas;
    w[0].pNext = &as_info;
    w[0].descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    w[1].dstBinding = kBindingParams;
    w[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w[1].pBufferInfo = &buffer_info;
    for (uint32_t i = 0; i < kImages; ++i) {
        w[2 + i].dstBinding = image_bindings[i];
        w[2 + i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        w[2 + i].pImageInfo = &images[i];
    }
    vkUpdateDescriptorSets(ctx->device(), 2 + kImages, w, 0, nullptr);
}

// What render() and present() share, after prepare_frame: uploads, BLAS and TLAS builds (an
// error when their memory runs out; the frame is then abandoned), then record_shading.
Status Renderer::Impl::record_scene(VkCommandBuffer cmd, const Camera& cam) {
    if (queries)
        vkCmdResetQueryPool(cmd, queries, ctx->frame_slot() * kStamps, kStamps);
    // The previous frame may still be running: it traces BLASes this frame refits, reads chunk
    // buffers this frame uploads into, and shares the build scratch. Its commands precede ours
    // on the one queue, so one barrier orders them; the CPU still records ahead of the GPU.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    stamp(cmd, 0);
    if (!accel->record_builds(cmd))
        return Error{"out of GPU memory for the acceleration-structure build (scratch, staging or index "
                     "pattern): nothing drawn; the next frame tries again"};
    stamp(cmd, 1);
    if (!accel->record_tlas_build(cmd, cam.block))
        return Error{"out of GPU memory for the TLAS or its scratch: nothing drawn; the next frame tries again"};
    stamp(cmd, 2);
    return {};
}

// The trace (or raster pass) and the denoiser. Leaves the target in TRANSFER_SRC_OPTIMAL,
// readable by transfers.
void Renderer::Impl::record_shading(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam) {
    raster_chunks = raster_transparent_chunks = 0;
    if (!s.exposure.automatic)
        adapted_ev100.reset();
    frame_ev100 = s.exposure.automatic && adapted_ev100 ? *adapted_ev100 : s.exposure.ev100;
    if (s.pipeline == PipelineKind::Raster) {
        record_raster(cmd, s, cam);
    } else {
        RenderSettings traced = s;
        if (denoise_active(s) && s.accumulate > 1) // Accumulated frames must differ.
            traced.seed = s.seed + uint32_t(ctx->frame_number());
        write_params(traced, cam);
        write_descriptors();
        record_trace(cmd, s);
        if (metering[ctx->frame_slot()])
            memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                           VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                           VK_ACCESS_2_HOST_READ_BIT);
    }
    if (denoise_active(s))
        record_denoise(cmd, s, cam);
    denoised_last_frame = denoise_active(s);
    stamp(cmd, 5);
    stamped[ctx->frame_slot()] = queries != VK_NULL_HANDLE;
}

void Renderer::Impl::record_trace(VkCommandBuffer cmd, const RenderSettings& s) {
    const uint32_t width = s.width, height = s.height;
    const bool flat = s.mode == ShadingMode::Flat;
    image_barrier(cmd, target().handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    // The G-buffer is rewritten whole each frame; readers of the slot's last frame are done
    // (the frame-start barrier orders all earlier commands before this one).
    const GBuffer& g = gbuffers[ctx->frame_slot()];
    for (VkImage im : {g.radiance.handle(), g.albedo.handle(), g.normal_depth.handle(), g.reflected.handle(),
                       g.mirror_light.handle(), g.mirror_albedo.handle(), g.mirror_normal_depth.handle()})
        image_barrier(cmd, im, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                      0, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    if (frame_cached)
        light_cache->record_clear(cmd);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline->layout(), 0, 1,
                            &sets[ctx->frame_slot()], 0, nullptr);
    // RenderSettings::split_hits: hit i < split in a pass of its own, each later pass going on
    // with the paths the last listed (one row of an invocation per pixel, those past the list's
    // end return at once); then the rest of every path. The lists' counters start at 0.
    const uint32_t split = split_hits(s);
    VkDeviceAddress states = 0;
    if (split > 0) {
        vkCmdFillBuffer(cmd, path_states.handle(), path_counters_offset(VkDeviceSize(width) * height),
                        gpu::kMaxSplitHits * sizeof(uint32_t), 0u);
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        states = path_states.address();
    }
    for (uint32_t hit = 0; hit <= split; ++hit) {
        const bool first = hit == 0;
        pipeline->trace(cmd, first ? width : width * height, first ? height : 1u, flat, frame_samples_faces,
                        {states, hit, hit < split ? hit : gpu::kTraceToEnd});
        if (hit < split)
            memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    if (frame_cached) // Part of the trace's time (stamp 3).
        light_cache->record_resolve(cmd, sets[ctx->frame_slot()], width, height);
    stamp(cmd, 3);
    image_barrier(cmd, target().handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  kTraceStages, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
}

// View matrix of `cam` in the frame of the block `origin` (double precision).
static glm::dmat4 view_from_world(const Camera& cam, world::BlockPos origin) {
    const glm::dvec3 eye = glm::dvec3(cam.block - origin) + glm::dvec3(cam.offset);
    return glm::lookAt(eye, eye + glm::dvec3(glm::normalize(cam.forward)), glm::dvec3(cam.up));
}

// Whether frames of `a` and `b` estimate the same image with the same samples (the history of
// one may be averaged with the other). Lights and sky may change under a kept history.
// The values the frame uses (a NaN compared unequal to itself, restarting the history every frame;
// a setting that is off does not count).
static bool same_sampling(const RenderSettings& a, const RenderSettings& b) {
    return a.mode == b.mode && a.shadow_samples == b.shadow_samples &&
           a.bounce_shadow_samples.value_or(a.shadow_samples) == b.bounce_shadow_samples.value_or(b.shadow_samples) &&
           a.samples_by_weight == b.samples_by_weight &&
           (!a.samples_by_weight || effective_weight_exponent(a) == effective_weight_exponent(b)) &&
           a.max_bounces == b.max_bounces &&
           a.accumulate == b.accumulate && a.denoise == b.denoise &&
           a.history_clamp == b.history_clamp && a.denoise_reflections == b.denoise_reflections &&
           a.light_cache == b.light_cache && (!a.light_cache || effective_cell_pixels(a) == effective_cell_pixels(b));
}

// The denoiser after the trace: reads the G-buffer (render/gbuffer.h), writes the target.
void Renderer::Impl::record_denoise(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam) {
    // Made or resized by prepare_frame (which dropped the history then).
    if (!denoised_last_frame || denoised_camera.fov_y_degrees != cam.fov_y_degrees || !same_sampling(denoised_settings, s))
        denoiser->reset_history();
    denoised_settings = s;
    const GBuffer& g = gbuffers[ctx->frame_slot()];
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    image_barrier(cmd, target().handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    DenoiseInputs in;
    in.colour = g.radiance.view();
    in.albedo = g.albedo.view();
    in.normal_depth = g.normal_depth.view();
    in.reflected = g.reflected.view();
    if (s.denoise_reflections) {
        in.mirror_light = g.mirror_light.view();
        in.mirror_albedo = g.mirror_albedo.view();
        in.mirror_normal_depth = g.mirror_normal_depth.view();
    }
    const glm::dmat4 prev_view = view_from_world(denoised_camera, cam.block);
    in.reproject = reprojection_matrix(prev_view, view_from_world(cam, cam.block), cam.fov_y_degrees, s.width, s.height);
    in.history_rotation = history_rotation(prev_view);
    in.fov_y_degrees = cam.fov_y_degrees;
    in.ldr_target = target().view();
    in.exposure = gpu::vx_exposure_scale(frame_ev100);
    in.first_hit_samples = s.samples_by_weight ? 0u : s.shadow_samples;
    DenoiseSettings ds;
    ds.iterations = s.denoise ? ds.iterations : 0;
    ds.max_history = std::max(s.accumulate, 1u);
    ds.history_clamp = s.history_clamp;
    denoiser->record(cmd, in, ds);
    denoised_camera = cam;
    image_barrier(cmd, target().handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
}

// The raster baseline in place of the trace: same target, same layout afterwards.
void Renderer::Impl::record_raster(VkCommandBuffer cmd, const RenderSettings& s, const Camera& cam) {
    RasterFrame f; // The pipeline and its depth buffer: made by prepare_frame.
    f.target = target().handle();
    f.target_view = target().view();
    f.width = s.width;
    f.height = s.height;
    f.camera_block = cam.block;
    f.camera_offset = cam.offset;
    f.clip_from_eye = raster_clip_from_eye(cam.forward, cam.up, cam.fov_y_degrees, float(s.width) / float(s.height));
    f.mode = s.mode == ShadingMode::Flat ? gpu::kModeFlat : s.mode == ShadingMode::Full ? gpu::kModeFull : gpu::kModeVisibility;
    // The area light's centre as a point light of the intensity it has face-on (radiance x area).
    const glm::vec3 centre = s.light.offset + 0.5f * (s.light.edge_u + s.light.edge_v);
    f.light_position = glm::dvec3(s.light.block - cam.block) + glm::dvec3(centre);
    f.light_power = s.light.emission * glm::length(glm::cross(s.light.edge_u, s.light.edge_v));
    f.exposure = gpu::vx_exposure_scale(frame_ev100);
    // The clear colour is written as is: Full mode's sky goes through the output transform here.
    f.sky = s.mode == ShadingMode::Full ? gpu::vx_display(s.sky, f.exposure) : s.sky;
    f.materials = materials.address();
    const RasterPipeline::Draws drawn = raster->record(cmd, f, accel->draw_list(), accel->index_buffer());
    raster_chunks = drawn.chunks;
    raster_transparent_chunks = drawn.transparent;
    stamp(cmd, 3);
}

// The copy of the target into the host-visible read-back buffer (render() waits for it). The
// copy is raw bytes whatever the target's format (UNORM or SRGB), so PNGs do not depend on it.
void Renderer::Impl::record_readback(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
    VX_ASSERT(readback.size() == VkDeviceSize(width) * height * 4); // prepare_frame made it.
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width, height, 1};
    vkCmdCopyImageToBuffer(cmd, target().handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.handle(), 1, &region);
    stamp(cmd, 4);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
}

void Renderer::Impl::record_gbuffer_readback(VkCommandBuffer cmd, const RenderSettings& s) {
    const VkDeviceSize pixels = VkDeviceSize(s.width) * s.height;
    VX_ASSERT(gbuffer_readback.size() == pixels * kGBufferReadbackPixelBytes);
    // Last use of the frame's G-buffer (the next frame starts it from UNDEFINED).
    const GBuffer& g = gbuffers[ctx->frame_slot()];
    const std::pair<VkImage, GBufferSection> images[4] = {{g.radiance.handle(), kRadianceSection},
                                                          {g.albedo.handle(), kAlbedoSection},
                                                          {g.normal_depth.handle(), kNormalDepthSection},
                                                          {g.reflected.handle(), kReflectedSection}};
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {s.width, s.height, 1};
    for (const auto& [image, section] : images) {
        image_barrier(cmd, image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      kTraceStages, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        region.bufferOffset = pixels * kGBufferSectionAt[section];
        vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, gbuffer_readback.handle(), 1,
                               &region);
    }
    // The denoiser's output stays in GENERAL (its next frame writes it again).
    if (denoise_active(s)) {
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        region.bufferOffset = pixels * kGBufferSectionAt[kDenoisedSection];
        vkCmdCopyImageToBuffer(cmd, denoiser->output().handle(), VK_IMAGE_LAYOUT_GENERAL, gbuffer_readback.handle(), 1,
                               &region);
    }
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
}

void Renderer::Impl::read_gbuffer(GBufferImage& out, const RenderSettings& s) const {
    const size_t pixels = size_t(s.width) * s.height;
    const auto* src = static_cast<const uint8_t*>(gbuffer_readback.mapped());
    auto halves = [&](std::vector<glm::vec4>& dst, const uint8_t* p) {
        dst.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            uint16_t h[4];
            std::memcpy(h, p + i * 8, sizeof h);
            dst[i] = {glm::unpackHalf1x16(h[0]), glm::unpackHalf1x16(h[1]), glm::unpackHalf1x16(h[2]),
                      glm::unpackHalf1x16(h[3])};
        }
    };
    out.width = s.width;
    out.height = s.height;
    auto section = [&](GBufferSection k) { return src + pixels * kGBufferSectionAt[k]; };
    halves(out.radiance, section(kRadianceSection));
    const uint8_t* albedo = section(kAlbedoSection);
    out.albedo.resize(pixels);
    for (size_t i = 0; i < pixels; ++i)
        out.albedo[i] = glm::vec4(albedo[i * 4], albedo[i * 4 + 1], albedo[i * 4 + 2], albedo[i * 4 + 3]) / 255.f;
    halves(out.normal_depth, section(kNormalDepthSection));
    halves(out.reflected, section(kReflectedSection));
    std::vector<glm::vec4> denoised;
    if (denoise_active(s))
        halves(denoised, section(kDenoisedSection));
    const std::vector<glm::vec4>& final_radiance = denoise_active(s) ? denoised : out.radiance;
    const bool tone_mapped = s.mode == ShadingMode::Full;
    const float exposure = gpu::vx_exposure_scale(frame_ev100);
    out.display.resize(pixels);
    for (size_t i = 0; i < pixels; ++i) {
        const glm::vec3 c(final_radiance[i]);
        out.display[i] = tone_mapped ? gpu::vx_display(c, exposure) : c;
    }
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer) {
    Result<RenderImage> img = try_render(settings, camera, gbuffer);
    VX_ASSERT_MSG(img, img ? "" : img.error().c_str());
    return std::move(*img);
}

Result<RenderImage> Renderer::try_render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer) {
    VX_ASSERT(settings.width > 0 && settings.height > 0);
    // Auto exposure without an adapted value yet: a frame to meter, then the frame itself.
    if (Impl::metered(settings) && !m->adapted_ev100)
        if (Result<RenderImage> first = m->render_frame(settings, camera, nullptr); !first)
            return first;
    return m->render_frame(settings, camera, gbuffer);
}

Result<RenderImage> Renderer::Impl::render_frame(const RenderSettings& settings, const Camera& camera,
                                         GBufferImage* gbuffer) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    Impl& d = *this;
    VkCommandBuffer cmd = d.ctx->begin_frame();
    if (!cmd)
        return Error{Impl::lost_error().error()};
    d.read_meter(settings.exposure.adapt_speed); // A frame present() left in this slot.
    Status ok = d.prepare_frame(settings, true, gbuffer != nullptr);
    if (ok)
        ok = d.record_scene(cmd, camera);
    if (!ok)
        return Error{d.abandon_frame(std::move(ok)).error()};
    d.record_shading(cmd, settings, camera);
    d.record_ui(cmd, settings.width, settings.height);
    d.record_readback(cmd, settings.width, settings.height);
    if (gbuffer)
        d.record_gbuffer_readback(cmd, settings);
    const auto t1 = Clock::now();
    if (!d.ctx->end_frame() || !d.ctx->wait_frame())
        return Error{Impl::lost_error().error()};
    const auto t2 = Clock::now();
    d.read_meter(settings.exposure.adapt_speed);

    RenderImage img;
    img.width = settings.width;
    img.height = settings.height;
    img.rgba.resize(size_t(settings.width) * settings.height * 4);
    std::memcpy(img.rgba.data(), d.readback.mapped(), img.rgba.size());
    if (gbuffer)
        d.read_gbuffer(*gbuffer, settings);

    d.stats = RenderStats{};
    d.fill_accel_stats(d.stats);
    d.stats.cpu_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    d.stats.gpu_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    d.stats.ev100 = d.frame_ev100;
    d.read_stamps(d.stats);
    return img;
}

void Renderer::set_ui(UiDrawList list) {
    VX_ASSERT_MSG(ui_draw_list_error(list).empty(), "set_ui: a malformed UI draw list");
    if (list.cmds.empty() && !m->ui)
        return;
    m->ui_pass().set(std::move(list));
}

Status Renderer::set_ui_texture(uint32_t width, uint32_t height, std::vector<uint8_t> rgba) {
    if (m->ctx->lost())
        return Impl::lost_error();
    if (!m->ui_pass().set_texture(width, height, std::move(rgba)))
        return Error{"out of GPU memory for a " + std::to_string(width) + "x" + std::to_string(height) +
                     " UI texture: the previous texture stays"};
    return {};
}

Result<PresentResult> Renderer::present(const RenderSettings& settings, const Camera& camera, RenderImage* capture) {
    using Clock = std::chrono::steady_clock;
    using Ms = std::chrono::duration<double, std::milli>;
    Impl& d = *m;
    if (!d.presenter)
        return Error{"present() needs a renderer created with a window (RendererCreateInfo::glfw_window)"};
    if (d.ctx->lost())
        return Error{Impl::lost_error().error()};
    const auto t0 = Clock::now();
    const std::optional<VkExtent2D> extent = d.presenter->prepare();
    if (d.ctx->lost()) // Recreating the swapchain waits for the device.
        return Error{Impl::lost_error().error()};
    if (!extent)
        return PresentResult::Skipped;
    // After prepare(): the first call creates the swapchain, whose usage decides this.
    if (capture && !d.presenter->can_capture())
        return Error{"present(): this surface's images cannot be read back (no TRANSFER_SRC usage)"};
    VkCommandBuffer cmd = d.ctx->begin_frame(); // Waits for the frame kFramesInFlight back.
    if (!cmd)
        return Error{Impl::lost_error().error()};
    RenderStats st;
    d.read_stamps(st);
    d.read_meter(settings.exposure.adapt_speed);
    const auto t_record = Clock::now();
    RenderSettings s = settings;
    s.width = extent->width;
    s.height = extent->height;
    // Everything that can run out of memory comes before the acquire: a failed frame then ends
    // without holding a swapchain image or a signalled semaphore.
    Status ok = d.prepare_frame(s, false, false);
    if (ok && capture && !d.presenter->prepare_capture())
        ok = Error{"out of GPU memory for the present capture: nothing drawn"};
    if (ok)
        ok = d.record_scene(cmd, camera);
    if (!ok)
        return Error{d.abandon_frame(std::move(ok)).error()};
    const auto t_acquire = Clock::now();
    if (!d.presenter->acquire()) {
        // Out of date (recreated next call) or lost: the scene's builds are submitted still.
        Status why = d.abandon_frame({});
        if (!why || d.ctx->lost())
            return Error{Impl::lost_error().error()};
        return PresentResult::Skipped;
    }
    const auto t1 = Clock::now();
    d.record_shading(cmd, s, camera);
    d.record_ui(cmd, s.width, s.height);
    d.presenter->record_blit(cmd, d.target().handle(), capture != nullptr);
    d.stamp(cmd, 4);
    if (!d.ctx->end_frame(d.presenter->submit_sync()))
        return Error{Impl::lost_error().error()};
    const auto t2 = Clock::now();
    if (!d.presenter->present())
        return Error{Impl::lost_error().error()};
    const auto t3 = Clock::now();

    d.fill_accel_stats(st);
    st.cpu_ms = Ms(t2 - t1).count() + Ms(t_acquire - t_record).count();
    st.gpu_ms = -1;
    st.wait_ms = Ms(t_record - t0).count() + Ms(t1 - t_acquire).count();
    st.present_ms = Ms(t3 - t2).count();
    st.present_width = s.width;
    st.present_height = s.height;
    st.ev100 = d.frame_ev100;
    if (d.last_present != Clock::time_point{})
        st.frame_ms = Ms(t0 - d.last_present).count();
    d.last_present = t0;
    d.stats = st;
    if (capture) {
        if (!d.ctx->wait_frame())
            return Error{Impl::lost_error().error()};
        *capture = d.presenter->read_capture();
    }
    return PresentResult::Presented;
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera, const Scene& scene) {
    set_registry(scene.registry ? *scene.registry : world::BlockRegistry::default_registry());
    std::unordered_set<world::LodCoord, world::LodCoordHash> keep;
    auto add = [&](world::LodCoord c, const world::ChunkMesh* mesh) {
        VX_ASSERT(mesh != nullptr);
        keep.insert(c);
        set_chunk(c, *mesh);
    };
    for (const auto& [c, mesh] : scene.chunks)
        add(world::LodCoord{0, c}, mesh);
    for (const auto& [c, mesh] : scene.lod_chunks)
        add(c, mesh);
    m->accel->retain_only(keep);
    std::erase_if(m->chunk_blocks, [&](const auto& kv) { return !keep.contains(kv.first); });
    std::erase_if(m->emissive_quads, [&](const auto& kv) { return !keep.contains(kv.first); });
    if (std::erase_if(m->emitter_set, [&](world::LodCoord c) { return !keep.contains(c); }) > 0)
        m->emitter_list_dirty = true;
    return render(settings, camera);
}

void Renderer::set_registry(const world::BlockRegistry& registry) {
    m->registry = registry;
    m->materials_dirty = true;
    m->emitters_dirty = true;
    std::vector<bool> emissive(registry.size(), false);
    for (size_t id = 0; id < registry.size(); ++id) {
        const glm::vec3 e = registry.info(world::BlockId(id)).emission;
        emissive[id] = e.r > 0.f || e.g > 0.f || e.b > 0.f;
    }
    // The chunks' emissive faces (render/emitter_quads.h) are stale where an id's flag changed;
    // ids appended that do not emit change nothing (an unregistered id did not emit either).
    bool stale = false;
    for (size_t id = 0; id < std::max(emissive.size(), m->emissive.size()); ++id) {
        const bool was = id < m->emissive.size() && m->emissive[id], is = id < emissive.size() && emissive[id];
        stale = stale || was != is;
    }
    if (stale)
        m->emissive_quads.clear();
    m->emissive = std::move(emissive);
}

void Renderer::set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) {
    set_chunk(world::LodCoord{0, c}, mesh, changed_slices);
}

void Renderer::remove_chunk(world::ChunkCoord c) { remove_chunk(world::LodCoord{0, c}); }

void Renderer::note_edit(world::BlockPos lo, world::BlockPos hi) { m->edit_marks.add(glm::min(lo, hi), glm::max(lo, hi)); }

size_t Renderer::noted_edits() const { return m->edit_marks.boxes().size(); }

void Renderer::set_chunk(world::LodCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) {
    VX_ASSERT_MSG(world::valid_lod_level(c.level), "set_chunk: LOD level outside 0..world::kMaxLodLevel");
    std::vector<world::BlockId>& ids = m->chunk_blocks[c];
    ids.clear();
    bool any = false;
    world::BlockId last = world::kAir;
    mesh.for_each_quad([&](const world::Quad& q) {
        if (any && q.block == last)
            return; // Runs of one block: most quads (the loop ran for every quad of every chunk streamed in).
        any = true;
        last = q.block;
        m->max_block_id = std::max<uint32_t>(m->max_block_id, q.block);
        if (std::find(ids.begin(), ids.end(), q.block) == ids.end()) // Few ids per chunk.
            ids.push_back(q.block);
    });
    const bool emits = m->emits(ids);
    if (emits ? m->emitter_set.insert(c).second : m->emitter_set.erase(c) > 0)
        m->emitter_list_dirty = true;
    if (emits) {
        std::vector<world::Quad>& faces = m->emissive_quads[c];
        faces.clear();
        collect_emissive_quads(mesh, m->emissive, faces);
    } else {
        m->emissive_quads.erase(c);
    }
    m->accel->set_chunk(c, mesh, changed_slices, chunk_traits(mesh, ids, m->registry));
}

void Renderer::remove_chunk(world::LodCoord c) {
    m->accel->remove_chunk(c);
    m->chunk_blocks.erase(c);
    m->emissive_quads.erase(c);
    if (m->emitter_set.erase(c) > 0)
        m->emitter_list_dirty = true;
}
void Renderer::clear_chunks() {
    m->accel->clear();
    m->chunk_blocks.clear();
    m->emissive_quads.clear();
    m->emitter_set.clear();
    m->emitter_list_dirty = true;
}
bool Renderer::device_lost() const { return m->ctx->lost(); }
void Renderer::simulate_device_loss() { m->ctx->simulate_device_loss(); }
void Renderer::fail_allocations(std::string name_prefix, uint64_t above_bytes) {
    m->ctx->fail_allocations(std::move(name_prefix), above_bytes);
}

void Renderer::limit_light_cache_cells(uint32_t cells) {
    VX_ASSERT(cells == 0 || (cells >= 4 && std::has_single_bit(cells)));
    m->light_cache_cell_limit = cells;
}

void Renderer::set_vsync(bool vsync) {
    if (m->presenter)
        m->presenter->set_vsync(vsync);
}

bool Renderer::vsync() const {
    return m->presenter && m->presenter->swapchain().present_mode() == VK_PRESENT_MODE_FIFO_KHR;
}

uint64_t frame_bytes_per_pixel() {
    // Per frame slot: the 8-bit target and the G-buffer (radiance, albedo, normal_depth,
    // reflected, mirror light, albedo and normal_depth: render/gbuffer.h); the 8-bit read-back;
    // the denoiser's sixteen RGBA16F images and its 8-bit output (render/denoiser.h).
    constexpr uint64_t kSlot = 4 + 8 + 4 + 8 + 8 + 8 + 4 + 8;
    constexpr uint64_t kDenoiser = 16 * 8 + 4;
    return kFramesInFlight * kSlot + 4 + kDenoiser;
}

Status Renderer::check_frame_size(uint32_t width, uint32_t height) const {
    const uint64_t pixels = uint64_t(width) * height;
    const uint64_t need = pixels * frame_bytes_per_pixel();
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(m->ctx->physical_device(), &mem);
    uint64_t heap = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            heap = std::max<uint64_t>(heap, mem.memoryHeaps[i].size);
    VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p11};
    vkGetPhysicalDeviceProperties2(m->ctx->physical_device(), &p2);
    const uint64_t largest_image = pixels * 8; // RGBA16F.
    auto gib = [](uint64_t b) { return std::to_string(double(b) / double(1ull << 30)).substr(0, 5) + " GiB"; };
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (need > heap)
        return Error{"a " + size + " target needs about " + gib(need) + " of GPU memory for its frame resources (" +
                     std::to_string(frame_bytes_per_pixel()) + " bytes per pixel), more than the device's " + gib(heap) +
                     ": choose a smaller size"};
    if (p11.maxMemoryAllocationSize && largest_image > p11.maxMemoryAllocationSize)
        return Error{"a " + size + " target needs " + gib(largest_image) + " images, more than the device allows in one "
                     "allocation (" + gib(p11.maxMemoryAllocationSize) + "): choose a smaller size"};
    return {};
}

const DeviceReport& Renderer::device() const { return m->ctx->report(); }
uint32_t Renderer::validation_errors() const { return m->ctx->validation_errors(); }
const RenderStats& Renderer::last_stats() const { return m->stats; }
GpuHeapStats Renderer::memory_stats() const {
    const AllocatorStats a = m->ctx->allocator().stats();
    return {uint64_t(a.block_bytes), uint64_t(a.used_bytes)};
}
Context& Renderer::context() { return *m->ctx; }

Camera Camera::look_at(glm::dvec3 eye, glm::dvec3 target, glm::vec3 up, float fov_y_degrees) {
    Camera c;
    const glm::dvec3 cell = glm::floor(eye);
    c.block = world::BlockPos(cell);
    c.offset = glm::vec3(eye - cell);
    c.forward = glm::vec3(target - eye);
    c.up = up;
    c.fov_y_degrees = fov_y_degrees;
    return c;
}

} // namespace vx::render
