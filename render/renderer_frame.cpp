// A frame's preparation (Renderer::Impl): its resources (target, G-buffer, materials, emitter
// lists, read-backs), its parameters and descriptors, and the last frame's timestamps and meter.
#include <bit>
#include <cstring>
#include <span>
#include <utility>

#include "render/commands.h"
#include "render/emitter_quads.h"
#include "render/gbuffer.h"
#include "render/renderer_impl.h"
#include "shaders/shared/tonemap.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

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
    // Without the denoiser the span holds a barrier's time: 0, as documented.
    out.gpu_denoise_ms = slot_denoised[slot] ? double(t[5] - t[3]) * ms_per_tick : 0.0;
    out.gpu_copy_ms = double(t[4] - t[5]) * ms_per_tick;
    out.gpu_frame_ms = double(t[4] - t[0]) * ms_per_tick;
}

// The see-through check's counts of the frame last submitted in this slot, once its fence has
// signalled.
void Renderer::Impl::read_check(RenderStats& out) {
    const uint32_t slot = ctx->frame_slot();
    out.see_through_checked = check_modes[slot] == gpu::kCheckMark;
    out.see_through_pixels = out.see_through_view_pixels = 0;
    if (check_modes[slot] == gpu::kCheckOff)
        return;
    uint32_t counts[2];
    std::memcpy(counts, check_counts[slot].mapped(), sizeof counts);
    const double pixels = double(std::max<uint64_t>(check_pixels[slot], 1));
    out.see_through_view_pixels = counts[1];
    view_share = float(counts[1] / pixels);
    if (out.see_through_checked) {
        out.see_through_pixels = counts[0];
        marked_share = float(counts[0] / pixels);
    }
    check_modes[slot] = gpu::kCheckOff; // Read once.
}

uint32_t Renderer::Impl::prepare_check(const RenderSettings& s) {
    if (marked_share > s.see_through_check_share) { // Marked over the share: hold, longer each time.
        check_hold = check_hold_next;
        check_hold_next = std::min(2 * check_hold_next, kCheckHoldMax);
    } else if (marked_share >= 0.f) {
        check_hold_next = kCheckHoldFirst;
    }
    marked_share = -1.f;
    uint32_t mode = gpu::kCheckCount;
    if (s.see_through_check_share >= 1.f) // Always.
        mode = gpu::kCheckMark;
    else if (check_hold > 0)
        --check_hold;
    else if (view_share <= s.see_through_check_share)
        mode = gpu::kCheckMark;
    // write_params picks the emitter faces' variant or not after this: both may be needed.
    if (mode == gpu::kCheckMark &&
        (!pipeline->ensure_variant(false, SeeThrough::kNone) ||
         (s.emitter_sampling && !emitter_set.empty() && !pipeline->ensure_variant(true, SeeThrough::kNone))))
        return gpu::kCheckOff;
    const VkDeviceSize bytes = (VkDeviceSize(s.width) * s.height + 2) * sizeof(uint32_t);
    if (!check_marks.valid() || check_marks.size() != bytes) {
        check_marks = Buffer::create(*ctx, {bytes,
                                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                                VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                            MemoryUse::Device, 0, "see-through check marks"});
        if (!check_marks.valid())
            return gpu::kCheckOff;
    }
    Buffer& count = check_counts[ctx->frame_slot()];
    if (!count.valid())
        count = Buffer::create(*ctx, {2 * sizeof(uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0,
                                      "see-through check count"});
    return count.valid() ? mode : gpu::kCheckOff;
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
                          return la != lb ? la < lb : world::lod_coord_less(a, b);
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

// A frame's resource that could not be allocated: nothing is drawn.
static Error frame_out_of_memory(const RenderSettings& s, const char* what) {
    return Error{std::string("out of GPU memory for ") + what + " of a " + std::to_string(s.width) + "x" +
                 std::to_string(s.height) + " frame: nothing drawn; a later frame (or a smaller size) tries again"};
}

// A pipeline made at its first frame that the device refused (it was a VK_CHECK abort): it is
// dropped, and the next frame that needs it makes it again.
Error Renderer::Impl::not_created(const char* what) const {
    return Error{std::string("out of GPU memory for ") + what + " (" + ctx->last_create_failure() +
                 "): nothing drawn; a later frame tries again"};
}

Status Renderer::Impl::prepare_frame(const RenderSettings& s, bool with_readback, bool with_gbuffer) {
    auto out_of_memory = [&](const char* what) { return frame_out_of_memory(s, what); };
    if (!ensure_target(s.width, s.height))
        return out_of_memory("the render target and G-buffer");
    check_modes[ctx->frame_slot()] = gpu::kCheckOff; // Until record_trace.
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
    frame_probes = touching.any();
    const bool eye_in = s.eye_block != world::kAir && !registry.is_opaque(s.eye_block);
    frame_see_through = frame_probes                              ? SeeThrough::kProbe
                        : !see_through_set.empty() || eye_in ? SeeThrough::kPlain
                                                                  : SeeThrough::kNone;
    if (s.emitter_sampling && !emitter_set.empty() && !pipeline->ensure_variant(true, frame_see_through))
        return out_of_memory("the emitter faces' pipeline");
    if (!pipeline->ensure_variant(false, frame_see_through)) // (false, kPlain) exists already.
        return out_of_memory("the pipeline of this frame's see-through blocks");
    frame_check = check_applies(s, eye_in) ? prepare_check(s) : gpu::kCheckOff;
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
    return prepare_passes(s);
}

// The passes' own resources, made at the first frame that needs them.
Status Renderer::Impl::prepare_passes(const RenderSettings& s) {
    auto out_of_memory = [&](const char* what) { return frame_out_of_memory(s, what); };
    const VkDeviceSize pixels = VkDeviceSize(s.width) * s.height;
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
    p.exposure = glm::vec4(gpu::vx_exposure_scale(frame_ev100), metering[slot] ? 1.f : 0.f,
                           denoise_active(s) ? 1.f : 0.f, 0.f);
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
    p.edits.y = s.eye_block; // The shader asks its material whether it is see-through.
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

} // namespace vx::render
