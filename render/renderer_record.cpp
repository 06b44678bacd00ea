// A frame's commands (Renderer::Impl): the scene's builds, the trace or raster pass, the denoiser
// and the read-backs, and render_frame(), which records, submits and reads back one frame.
#include <algorithm>
#include <cstring>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "render/commands.h"
#include "render/renderer_impl.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {

// The stages that write the target and the G-buffer in a traced frame: the ray generation, then
// the light cache's resolve pass (a compute shader) when the frame caches.
constexpr VkPipelineStageFlags2 kTraceStages =
    VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

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
    slot_denoised[ctx->frame_slot()] = denoised_last_frame;
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
    if (frame_check != gpu::kCheckOff) { // The see-through check's two counts start at 0.
        vkCmdFillBuffer(cmd, check_marks.handle(), 0, 2 * sizeof(uint32_t), 0u);
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    const bool checked = frame_check == gpu::kCheckMark;
    if (checked)
        record_checked_trace(cmd, width, height);
    const VkDeviceAddress marks = frame_check == gpu::kCheckCount ? check_marks.address() : 0;
    for (uint32_t hit = 0; !checked && hit <= split; ++hit) {
        const bool first = hit == 0;
        pipeline->trace(cmd, first ? width : width * height, first ? height : 1u, flat, frame_samples_faces,
                        frame_see_through,
                        {states, hit, hit < split ? hit : gpu::kTraceToEnd, marks, marks ? gpu::kCheckCount : gpu::kCheckOff, 0});
        if (hit < split)
            memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    if (frame_check != gpu::kCheckOff)
        record_check_count(cmd);
    if (frame_cached) // Part of the trace's time (stamp 3).
        light_cache->record_resolve(cmd, sets[ctx->frame_slot()], width, height);
    stamp(cmd, 3);
    image_barrier(cmd, target().handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  kTraceStages, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
}

// RenderSettings::see_through_check: the variant without the see-through code over the image,
// marking the pixels whose rays met a see-through face, then the frame's own variant over the
// image again, where all but the marked pixels return at once.
void Renderer::Impl::record_checked_trace(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
    const VkDeviceAddress marks = check_marks.address();
    pipeline->trace(cmd, width, height, false, frame_samples_faces, SeeThrough::kNone,
                    {0, 0, gpu::kTraceToEnd, marks, gpu::kCheckMark, 0});
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    pipeline->trace(cmd, width, height, false, frame_samples_faces, frame_see_through,
                    {0, 0, gpu::kTraceToEnd, marks, gpu::kCheckMarked, 0});
}

void Renderer::Impl::record_check_count(VkCommandBuffer cmd) {
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    const uint32_t slot = ctx->frame_slot();
    const VkBufferCopy count{0, 0, 2 * sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, check_marks.handle(), check_counts[slot].handle(), 1, &count);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
    check_modes[slot] = frame_check;
    check_pixels[slot] = check_marks.size() / sizeof(uint32_t) - 2;
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
    ds.iterations = s.denoise ? std::clamp(s.denoise_passes, 1u, kMaxDenoisePasses) : 0u;
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
    d.read_check(d.stats);
    return img;
}

} // namespace vx::render
