#include "render/denoiser.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "render/commands.h"
#include "render/graphics_pipeline.h"
#include "render/shader_code.h"
#include "shaders/shared/denoise_types.h"

namespace vx::render {

static_assert(sizeof(gpu::DenoisePush) == 128, "DenoisePush must match its std430 layout");

namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// The running means (illumination, reflected part, mirror light, moments) are 32-bit: a half
// float's 11-bit mantissa loses a mean's updates once (sample - mean) / frames falls under half
// an ulp, which biased long accumulations by the samples' skew (lavapipe, the hidden-style
// overview: 1 spp x 1024 frames 6.8 8-bit steps darker than 8 spp x 128; docs/render_report.md).
constexpr VkFormat kHistoryFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr uint32_t kTemporalBindings = 22, kAtrousBindings = 11;
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

VkDescriptorSetLayout make_set_layout(Context& ctx, uint32_t bindings, const char* name) {
    std::vector<VkDescriptorSetLayoutBinding> b(bindings);
    for (uint32_t i = 0; i < bindings; ++i)
        b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    ci.bindingCount = bindings;
    ci.pBindings = b.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    auto create = [&] { return vkCreateDescriptorSetLayout(ctx.device(), &ci, nullptr, &layout); };
    if (ctx.create_call("vkCreateDescriptorSetLayout", name, create) != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(layout, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, name);
    return layout;
}

VkPipelineLayout make_pipeline_layout(Context& ctx, VkDescriptorSetLayout set, const char* name) {
    if (!set)
        return VK_NULL_HANDLE; // Its creation failed (logged).
    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::DenoisePush)};
    VkPipelineLayoutCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    ci.setLayoutCount = 1;
    ci.pSetLayouts = &set;
    ci.pushConstantRangeCount = 1;
    ci.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    auto create = [&] { return vkCreatePipelineLayout(ctx.device(), &ci, nullptr, &layout); };
    if (ctx.create_call("vkCreatePipelineLayout", name, create) != VK_SUCCESS)
        return VK_NULL_HANDLE;
    ctx.set_name(layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, name);
    return layout;
}

void write_images(Context& ctx, VkDescriptorSet set, std::span<const VkImageView> views) {
    std::vector<VkDescriptorImageInfo> infos(views.size());
    std::vector<VkWriteDescriptorSet> writes(views.size());
    for (size_t i = 0; i < views.size(); ++i) {
        infos[i] = {VK_NULL_HANDLE, views[i], VK_IMAGE_LAYOUT_GENERAL};
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = set;
        writes[i].dstBinding = uint32_t(i);
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        writes[i].pImageInfo = &infos[i];
    }
    vkUpdateDescriptorSets(ctx.device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
}

// Compute writes -> compute reads (the next pass).
void compute_barrier(VkCommandBuffer cmd) {
    memory_barrier(cmd, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, kCompute,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

} // namespace

Denoiser::Denoiser(Context& ctx, uint32_t width, uint32_t height) : m_ctx(&ctx), m_width(width), m_height(height) {
    VX_ASSERT(width > 0 && height > 0);
    create_images();
    m_valid = create_pipelines();
}

Denoiser::~Denoiser() {
    // Pipelines retire with the frame; the pool (its sets) must be idle: see the header.
    m_ctx->retire_list().pipelines.push_back(m_temporal);
    m_ctx->retire_list().pipelines.push_back(m_atrous);
    const VkDevice d = m_ctx->device();
    vkDestroyDescriptorPool(d, m_pool, nullptr);
    vkDestroyPipelineLayout(d, m_temporal_pl, nullptr);
    vkDestroyPipelineLayout(d, m_atrous_pl, nullptr);
    vkDestroyDescriptorSetLayout(d, m_temporal_layout, nullptr);
    vkDestroyDescriptorSetLayout(d, m_atrous_layout, nullptr);
}

void Denoiser::resize(uint32_t width, uint32_t height) {
    VX_ASSERT(width > 0 && height > 0);
    m_width = width;
    m_height = height;
    create_images(); // The old images retire with this frame.
    m_initialised = false;
    m_history_valid = false;
}

void Denoiser::create_images() {
    auto make = [&](const char* name, VkFormat format = kHdrFormat) {
        ImageCreateInfo ci;
        ci.width = m_width;
        ci.height = m_height;
        ci.format = format;
        ci.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        ci.name = name;
        if (!m_ready)
            return Image{}; // One failure (one log line) is enough.
        Image img = Image::create(*m_ctx, ci); // Out of memory: logged, ready() false.
        m_ready = m_ready && img.valid();
        return img;
    };
    m_ready = true;
    m_history = {make("denoise history 0", kHistoryFormat), make("denoise history 1", kHistoryFormat)};
    m_history_nd = {make("denoise history normal_depth 0"), make("denoise history normal_depth 1")};
    m_ping = {make("denoise ping"), make("denoise pong")};
    m_moments = {make("denoise moments 0", kHistoryFormat), make("denoise moments 1", kHistoryFormat)};
    m_history_reflected = {make("denoise history reflected 0", kHistoryFormat),
                           make("denoise history reflected 1", kHistoryFormat)};
    m_history_mirror = {make("denoise history mirror 0", kHistoryFormat),
                        make("denoise history mirror 1", kHistoryFormat)};
    m_mirror_ping = {make("denoise mirror ping"), make("denoise mirror pong")};
    m_reflected = make("denoise reflected");
    m_output = make("denoise output");
    ImageCreateInfo ldr;
    ldr.width = m_width;
    ldr.height = m_height;
    ldr.format = VK_FORMAT_R8G8B8A8_UNORM;
    ldr.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    ldr.name = "denoise ldr output";
    m_ldr = m_ready ? Image::create(*m_ctx, ldr) : Image{};
    m_ready = m_ready && m_ldr.valid();
}

bool Denoiser::create_pipelines() {
    m_temporal_layout = make_set_layout(*m_ctx, kTemporalBindings, "denoise temporal set layout");
    m_atrous_layout = make_set_layout(*m_ctx, kAtrousBindings, "denoise atrous set layout");
    m_temporal_pl = make_pipeline_layout(*m_ctx, m_temporal_layout, "denoise temporal layout");
    m_atrous_pl = make_pipeline_layout(*m_ctx, m_atrous_layout, "denoise atrous layout");
    m_temporal = make_compute_pipeline(*m_ctx, m_temporal_pl, spirv::denoise_temporal(), "denoise_temporal.comp");
    m_atrous = make_compute_pipeline(*m_ctx, m_atrous_pl, spirv::denoise_atrous(), "denoise_atrous.comp");
    if (!m_temporal || !m_atrous)
        return false; // Out of memory (logged); the destructor frees what was made.
    constexpr uint32_t kSets = kFramesInFlight * 4;
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kFramesInFlight * 2 * (kTemporalBindings + kAtrousBindings)};
    VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    ci.maxSets = kSets;
    ci.poolSizeCount = 1;
    ci.pPoolSizes = &size;
    auto create_pool = [&] { return vkCreateDescriptorPool(m_ctx->device(), &ci, nullptr, &m_pool); };
    if (m_ctx->create_call("vkCreateDescriptorPool (denoise descriptor pool)", create_pool) != VK_SUCCESS)
        return false;
    m_ctx->set_name(m_pool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "denoise descriptor pool");
    for (uint32_t slot = 0; slot < kFramesInFlight; ++slot)
        for (uint32_t i = 0; i < 2; ++i) {
            VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
            ai.descriptorPool = m_pool;
            ai.descriptorSetCount = 1;
            ai.pSetLayouts = &m_temporal_layout;
            if (!allocate_set(ai, m_temporal_sets[slot][i]))
                return false; // The pool frees the sets made.
            ai.pSetLayouts = &m_atrous_layout;
            if (!allocate_set(ai, m_atrous_sets[slot][i]))
                return false;
            char name[64];
            std::snprintf(name, sizeof name, "denoise temporal set %u.%u", slot, i);
            m_ctx->set_name(m_temporal_sets[slot][i], VK_OBJECT_TYPE_DESCRIPTOR_SET, name);
            std::snprintf(name, sizeof name, "denoise atrous set %u.%u", slot, i);
            m_ctx->set_name(m_atrous_sets[slot][i], VK_OBJECT_TYPE_DESCRIPTOR_SET, name);
        }
    return true;
}

bool Denoiser::allocate_set(const VkDescriptorSetAllocateInfo& ai, VkDescriptorSet& set) {
    return m_ctx->create_call("vkAllocateDescriptorSets (denoise)",
                              [&] { return vkAllocateDescriptorSets(m_ctx->device(), &ai, &set); }) == VK_SUCCESS;
}

void Denoiser::write_sets(const DenoiseInputs& in, uint32_t slot) {
    const VkImageView ldr = in.ldr_target ? in.ldr_target : m_ldr.view();
    // Without mirror inputs the shaders read none of them (kDenoiseMirror): any view of the
    // format keeps the sets valid.
    const bool mirror = in.mirror_light != VK_NULL_HANDLE;
    const VkImageView mirror_light = mirror ? in.mirror_light : m_reflected.view();
    const VkImageView mirror_albedo = mirror ? in.mirror_albedo : m_ldr.view();
    const VkImageView mirror_nd = mirror ? in.mirror_normal_depth : m_reflected.view();
    for (uint32_t p = 0; p < 2; ++p) {
        const uint32_t q = 1 - p; // History read from [p], written to [q].
        const VkImageView temporal[kTemporalBindings] = {
            in.colour, in.albedo, in.normal_depth, m_history[p].view(), m_history_nd[p].view(),
            m_history[q].view(), m_history_nd[q].view(), m_ping[0].view(), m_output.view(), ldr,
            m_moments[p].view(), m_moments[q].view(), in.reflected, m_history_reflected[p].view(),
            m_history_reflected[q].view(), m_reflected.view(), mirror_light, mirror_albedo, mirror_nd,
            m_history_mirror[p].view(), m_history_mirror[q].view(), m_mirror_ping[0].view()};
        write_images(*m_ctx, m_temporal_sets[slot][p], temporal);
        const VkImageView atrous[kAtrousBindings] = {m_ping[p].view(), in.albedo, in.normal_depth, m_ping[q].view(),
                                                     m_output.view(), ldr, m_reflected.view(),
                                                     m_mirror_ping[p].view(), mirror_nd,
                                                     m_mirror_ping[q].view(), mirror_albedo};
        write_images(*m_ctx, m_atrous_sets[slot][p], atrous);
    }
}

void Denoiser::record(VkCommandBuffer cmd, const DenoiseInputs& inputs, const DenoiseSettings& settings) {
    VX_ASSERT_MSG(m_ready, "Denoiser::record without its images (out of memory: see ready())");
    VX_ASSERT(inputs.colour && inputs.albedo && inputs.normal_depth && inputs.reflected);
    const bool mirror = inputs.mirror_light != VK_NULL_HANDLE;
    VX_ASSERT_MSG(mirror == (inputs.mirror_albedo != VK_NULL_HANDLE) &&
                      mirror == (inputs.mirror_normal_depth != VK_NULL_HANDLE),
                  "Denoiser::record: the mirror images come all or none");
    const uint32_t slot = m_ctx->frame_slot();
    write_sets(inputs, slot);
    if (!m_initialised) {
        for (const Image* img : {&m_history[0], &m_history[1], &m_history_nd[0], &m_history_nd[1], &m_ping[0],
                                 &m_ping[1], &m_output, &m_ldr, &m_moments[0], &m_moments[1],
                                 &m_history_reflected[0], &m_history_reflected[1], &m_reflected,
                                 &m_history_mirror[0], &m_history_mirror[1], &m_mirror_ping[0], &m_mirror_ping[1]})
            image_barrier(cmd, img->handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                          VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, kCompute,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        m_initialised = true;
    }
    // A next frame reads the history exactly where this one writes it.
    const bool keep_history = settings.max_history > 1;
    gpu::DenoisePush push{};
    push.reproject = inputs.reproject;
    const bool many = float(inputs.first_hit_samples) >= gpu::kDenoiseManySamples;
    push.sigmas = {settings.sigma_normal, settings.sigma_depth,
                   many ? settings.sigma_luminance_many : settings.sigma_luminance,
                   float(std::max(settings.max_history, 1u))};
    push.params = {m_width, m_height, 1,
                   (m_history_valid ? gpu::kDenoiseHistoryValid : 0u) |
                       (settings.iterations == 0 ? gpu::kDenoiseLastPass : 0u) |
                       (settings.history_clamp ? gpu::kDenoiseHistoryClamp : 0u) |
                       (mirror ? gpu::kDenoiseMirror : 0u) |
                       (keep_history ? gpu::kDenoiseKeepHistory : 0u)};
    push.camera = {std::tan(glm::radians(inputs.fov_y_degrees) * 0.5f), float(m_width) / float(m_height),
                   inputs.exposure, float(inputs.first_hit_samples)};
    const glm::quat r = inputs.history_rotation;
    push.history_rotation = {r.x, r.y, r.z, r.w};
    const uint32_t gx = (m_width + gpu::kDenoiseGroupSize - 1) / gpu::kDenoiseGroupSize;
    const uint32_t gy = (m_height + gpu::kDenoiseGroupSize - 1) / gpu::kDenoiseGroupSize;
    // Earlier work on these images (the previous frame's passes, a read-back copy) finishes first.
    memory_barrier(cmd, kCompute | VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                   kCompute, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_temporal);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_temporal_pl, 0, 1,
                            &m_temporal_sets[slot][m_parity], 0, nullptr);
    vkCmdPushConstants(cmd, m_temporal_pl, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, gx, gy, 1);
    m_parity = 1 - m_parity;
    m_history_valid = keep_history;

    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_atrous);
    for (uint32_t i = 0; i < settings.iterations; ++i) {
        compute_barrier(cmd);
        const uint32_t from = i % 2; // The temporal pass wrote m_ping[0].
        push.params.z = 1u << i;
        push.params.w = ((i + 1 == settings.iterations) ? gpu::kDenoiseLastPass : 0u) | (mirror ? gpu::kDenoiseMirror : 0u);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_atrous_pl, 0, 1, &m_atrous_sets[slot][from],
                                0, nullptr);
        vkCmdPushConstants(cmd, m_atrous_pl, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cmd, gx, gy, 1);
    }
}

glm::mat4 reprojection_matrix(const glm::dmat4& prev_view_from_world, const glm::dmat4& view_from_world,
                              float fov_y_degrees, uint32_t width, uint32_t height) {
    // The ray tracer's pinhole (shaders/raygen.rgen primary_dir): the pixel centre (u, v) at
    // view depth d is d * (ndc.x th a, -ndc.y th, -1) in view space, ndc = 2 (u, v) / size - 1.
    const double th = std::tan(glm::radians(double(fov_y_degrees)) * 0.5);
    const double a = double(width) / double(height);
    glm::dmat4 view_from_pixel(0.0); // (u d, v d, d, 1) -> view-space point (column-major).
    view_from_pixel[0][0] = 2.0 * th * a / width;
    view_from_pixel[1][1] = -2.0 * th / height;
    view_from_pixel[2] = glm::dvec4(-th * a, th, -1.0, 0.0);
    view_from_pixel[3][3] = 1.0;
    const glm::dmat4 pixel_from_view = glm::inverse(view_from_pixel);
    return glm::mat4(pixel_from_view * prev_view_from_world * glm::inverse(view_from_world) * view_from_pixel);
}

glm::quat history_rotation(const glm::dmat4& prev_view_from_world) {
    return glm::quat(glm::quat_cast(glm::dmat3(prev_view_from_world)));
}

namespace {

// Packs float RGBA into half (RGBA16F) or UNORM8 (RGBA8) texel bytes.
std::vector<uint8_t> pack(const ImageF& img, bool half) {
    std::vector<uint8_t> out(img.rgba.size() * (half ? 2 : 1));
    for (size_t i = 0; i < img.rgba.size(); ++i) {
        if (half) {
            const uint16_t h = glm::packHalf1x16(img.rgba[i]);
            std::memcpy(&out[i * 2], &h, 2);
        } else {
            out[i] = uint8_t(std::lround(std::clamp(img.rgba[i], 0.f, 1.f) * 255.f));
        }
    }
    return out;
}

void copy_buffer_to_image(VkCommandBuffer cmd, VkBuffer src, VkDeviceSize offset, const Image& dst) {
    image_barrier(cmd, dst.handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.bufferOffset = offset;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {dst.width(), dst.height(), 1};
    vkCmdCopyBufferToImage(cmd, src, dst.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    image_barrier(cmd, dst.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kCompute,
                  VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

} // namespace

ImageF denoise_on_host(Context& ctx, Denoiser& denoiser, const ImageF& colour, const ImageF& albedo,
                       const ImageF& normal_depth, const DenoiseSettings& settings, const glm::mat4& reproject,
                       float fov_y_degrees, const ImageF* reflected, const MirrorImagesF* mirror,
                       const glm::quat& history_rotation, uint32_t first_hit_samples) {
    const uint32_t w = denoiser.width(), h = denoiser.height();
    const ImageF zero = reflected ? ImageF{} : ImageF::make(w, h);
    const ImageF& refl = reflected ? *reflected : zero;
    const int inputs_used = mirror ? 7 : 4;
    const ImageF* images[7] = {&colour, &albedo, &normal_depth, &refl, nullptr, nullptr, nullptr};
    if (mirror) {
        images[4] = &mirror->light;
        images[5] = &mirror->albedo;
        images[6] = &mirror->normal_depth;
    }
    for (int i = 0; i < inputs_used; ++i)
        VX_ASSERT_MSG(images[i]->width == w && images[i]->height == h && images[i]->rgba.size() == size_t(w) * h * 4,
                      "denoise_on_host: image size differs from the denoiser's");
    constexpr int kInputs = 7;
    const bool half[kInputs] = {true, false, true, true, true, false, true};
    std::vector<uint8_t> bytes[kInputs];
    VkDeviceSize in_bytes = 0;
    for (int i = 0; i < inputs_used; ++i) {
        bytes[i] = pack(*images[i], half[i]);
        in_bytes += bytes[i].size();
    }
    const VkFormat formats[kInputs] = {kHdrFormat, VK_FORMAT_R8G8B8A8_UNORM, kHdrFormat, kHdrFormat,
                                       kHdrFormat, VK_FORMAT_R8G8B8A8_UNORM, kHdrFormat};
    const char* names[kInputs] = {"denoise input colour", "denoise input albedo",
                                  "denoise input normal_depth", "denoise input reflected",
                                  "denoise input mirror light", "denoise input mirror albedo",
                                  "denoise input mirror normal_depth"};
    const VkDeviceSize out_bytes = VkDeviceSize(w) * h * 8;
    Buffer staging = Buffer::create(
        ctx, {in_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, 16, "denoise input staging"});
    Buffer readback =
        Buffer::create(ctx, {out_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, 0, "denoise readback"});
    VX_ASSERT_MSG(staging.valid() && readback.valid(), "out of memory for denoise_on_host's buffers");
    Image inputs[kInputs];
    VkDeviceSize offsets[kInputs], at = 0;
    for (int i = 0; i < inputs_used; ++i) {
        inputs[i] = Image::create(ctx, {w, h, formats[i], VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                        names[i]});
        VX_ASSERT_MSG(inputs[i].valid(), "out of GPU memory for denoise_on_host's images");
        offsets[i] = at;
        std::memcpy(static_cast<uint8_t*>(staging.mapped()) + at, bytes[i].data(), bytes[i].size());
        at += bytes[i].size();
    }
    VX_ASSERT_MSG(denoiser.ready(), "out of GPU memory for the denoiser's images");
    VkCommandBuffer cmd = ctx.begin_frame();
    for (int i = 0; i < inputs_used; ++i)
        copy_buffer_to_image(cmd, staging.handle(), offsets[i], inputs[i]);
    DenoiseInputs in{inputs[0].view(), inputs[1].view(), inputs[2].view(), inputs[3].view()};
    in.reproject = reproject;
    in.history_rotation = history_rotation;
    in.fov_y_degrees = fov_y_degrees;
    in.first_hit_samples = first_hit_samples;
    if (mirror) {
        in.mirror_light = inputs[4].view();
        in.mirror_albedo = inputs[5].view();
        in.mirror_normal_depth = inputs[6].view();
    }
    denoiser.record(cmd, in, settings);
    const VkImage output = denoiser.output().handle();
    image_barrier(cmd, output, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kCompute,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, output, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.handle(), 1, &region);
    image_barrier(cmd, output, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, kCompute,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
    ctx.end_frame();
    ctx.wait_frame();
    ImageF out = ImageF::make(w, h);
    const auto* src = static_cast<const uint16_t*>(readback.mapped());
    for (size_t i = 0; i < out.rgba.size(); ++i)
        out.rgba[i] = glm::unpackHalf1x16(src[i]);
    return out;
}

} // namespace vx::render
