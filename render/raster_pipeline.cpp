#include "render/raster_pipeline.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "render/commands.h"
#include "render/graphics_pipeline.h"
#include "render/shader_code.h"
#include "shaders/shared/raster_types.h"
#include "shaders/shared/render_types.h"

namespace vx::render {

static_assert(sizeof(gpu::RasterPush) == 128, "RasterPush: the guaranteed push-constant size");

namespace {

constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

} // namespace

RasterPipeline::RasterPipeline(Context& ctx, VkFormat color_format) : m_ctx(&ctx) { create_pipeline(color_format); }

RasterPipeline::~RasterPipeline() {
    for (VkPipeline p : {m_pipeline, m_transparent})
        if (p)
            m_ctx->retire_list().pipelines.push_back(p);
    vkDestroyPipelineLayout(m_ctx->device(), m_layout, nullptr);
}

void RasterPipeline::create_pipeline(VkFormat color_format) {
    m_layout = make_push_constant_layout(*m_ctx, sizeof(gpu::RasterPush), "raster pipeline layout");
    // No face culling here, as the ray tracer's rays (only its coincident-face probes cull):
    // raster.vert drops the back faces of opaque blocks itself, and each pass's faces the other's.
    const VkBool32 transparent_pass[2] = {VK_FALSE, VK_TRUE};
    const VkSpecializationMapEntry entry{0, 0, sizeof(VkBool32)}; // kTransparentPass.
    for (uint32_t pass = 0; pass < 2; ++pass) {
        const VkSpecializationInfo spec{1, &entry, sizeof(VkBool32), &transparent_pass[pass]};
        const VkPipeline p = make_graphics_pipeline(
            *m_ctx, {.vert = spirv::raster_vert(),
                     .frag = spirv::raster_frag(),
                     .vert_name = "raster.vert",
                     .frag_name = "raster.frag",
                     .name = pass ? "raster transparent pipeline" : "raster pipeline",
                     .layout = m_layout,
                     .color_format = color_format,
                     .depth_format = kDepthFormat,
                     .depth_write = !pass, // Faces behind a transparent one still show through it.
                     .blend = pass ? Blend::Multiply : Blend::None,
                     .specialization = &spec});
        if (!p)
            return; // Logged; valid() is false.
        (pass ? m_transparent : m_pipeline) = p;
    }
}

bool RasterPipeline::ensure_depth(uint32_t width, uint32_t height) {
    Image& d = m_depth[m_ctx->frame_slot()];
    if (d.valid() && d.width() == width && d.height() == height)
        return true;
    ImageCreateInfo ci;
    ci.width = width;
    ci.height = height;
    ci.format = kDepthFormat;
    ci.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    ci.name = "raster depth";
    ci.aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
    d = Image::create(*m_ctx, ci); // Out of memory: logged.
    return d.valid();
}

static void depth_barrier(VkCommandBuffer cmd, VkImage image) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    b.srcAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    b.dstStageMask = b.srcStageMask;
    b.dstAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    b.newLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1};
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &di);
}

RasterPipeline::Draws RasterPipeline::record(VkCommandBuffer cmd, const RasterFrame& f,
                                             std::span<const SceneAccel::DrawChunk> chunks, VkBuffer indices) {
    const bool have_depth = ensure_depth(f.width, f.height); // A renderer made it already.
    VX_ASSERT_MSG(have_depth, "out of GPU memory for the raster depth buffer");
    const Image& depth = m_depth[m_ctx->frame_slot()];
    image_barrier(cmd, f.target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    depth_barrier(cmd, depth.handle());
    // Quad records uploaded this frame (transfer) are read by the vertex shader.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = f.target_view;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{f.sky.x, f.sky.y, f.sky.z, 1.f}};
    VkRenderingAttachmentInfo depth_info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth_info.imageView = depth.view();
    depth_info.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth_info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth_info.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth_info.clearValue.depthStencil = {0.f, 0}; // Reversed depth: 0 is infinitely far.
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {f.width, f.height}};
    ri.layerCount = 1;
    ri.colorAttachmentCount = 1;
    ri.pColorAttachments = &color;
    ri.pDepthAttachment = &depth_info;
    vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m_pipeline);
    const VkViewport viewport{0.f, 0.f, float(f.width), float(f.height), 0.f, 1.f};
    const VkRect2D scissor{{0, 0}, {f.width, f.height}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);

    gpu::RasterPush push{};
    push.clip_from_eye = f.clip_from_eye;
    push.light_position = glm::vec4(glm::vec3(f.light_position - glm::dvec3(f.camera_offset)), float(f.mode));
    push.light_power = glm::vec4(f.light_power, f.exposure);
    push.materials = f.materials;
    Draws drawn;
    if (!chunks.empty())
        vkCmdBindIndexBuffer(cmd, indices, 0, VK_INDEX_TYPE_UINT32);
    const auto draw = [&](const SceneAccel::DrawChunk& c, glm::vec3 origin) {
        push.chunk_origin = glm::vec4(origin, float(world::lod_cell_size(c.coord.level)));
        push.quads = c.quads;
        vkCmdPushConstants(cmd, m_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                           &push);
        vkCmdDrawIndexed(cmd, 6 * c.slots, 1, 0, 0, 0); // Slot k: vertices 4k..4k+3 (raster.vert).
    };
    // 64-bit difference first, then float, as the TLAS transforms.
    const auto origin_of = [&](const SceneAccel::DrawChunk& c) {
        return glm::vec3(world::lod_origin(c.coord) - f.camera_block) - f.camera_offset;
    };
    // Visibility mode has no tint to show (the ray tracer's reports the first opaque hit's).
    const bool see_through = f.mode != gpu::kModeVisibility;
    m_see_through.clear();
    for (uint32_t i = 0; i < chunks.size(); ++i) {
        const SceneAccel::DrawChunk& c = chunks[i];
        const glm::vec3 origin = origin_of(c);
        if (!raster_box_visible(f.clip_from_eye, origin, origin + float(world::lod_chunk_blocks(c.coord.level))))
            continue;
        draw(c, origin);
        ++drawn.chunks;
        if (see_through && !c.opaque)
            m_see_through.push_back(i);
    }
    // Transparent faces over the finished opaque image: each multiplies in its tint, so their
    // order does not matter (the product commutes) and they need no sorting.
    if (!m_see_through.empty()) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m_transparent);
        for (uint32_t i : m_see_through)
            draw(chunks[i], origin_of(chunks[i]));
        drawn.transparent = uint32_t(m_see_through.size());
    }
    vkCmdEndRendering(cmd);
    image_barrier(cmd, f.target, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    return drawn;
}

bool raster_box_visible(const glm::mat4& m, glm::vec3 lo, glm::vec3 hi) {
    // Planes of the clip volume -w <= x, y <= w, 0 <= z <= w as rows of m (Gribb and Hartmann,
    // "Fast extraction of viewing frustum planes", 2001): a point p is inside plane n when
    // dot(n, (p, 1)) >= 0. A box is outside when its corner furthest along n is outside. With
    // reversed infinite depth z <= w is the near plane and 0 <= z holds everywhere (no far plane).
    const glm::vec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]), r1(m[0][1], m[1][1], m[2][1], m[3][1]),
        r2(m[0][2], m[1][2], m[2][2], m[3][2]), r3(m[0][3], m[1][3], m[2][3], m[3][3]);
    const glm::vec4 planes[6] = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2};
    for (const glm::vec4& n : planes) {
        const glm::vec3 far_corner(n.x >= 0.f ? hi.x : lo.x, n.y >= 0.f ? hi.y : lo.y, n.z >= 0.f ? hi.z : lo.z);
        if (glm::dot(glm::vec3(n), far_corner) + n.w < 0.f)
            return false;
    }
    return true;
}

glm::mat4 raster_clip_from_eye(glm::vec3 forward, glm::vec3 up, float fov_y_degrees, float aspect, float near_plane) {
    // The ray tracer's basis (renderer_frame.cpp write_params): right = fwd x up, up' = right x fwd.
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.f), glm::normalize(forward), up);
    // Reversed, infinite (raster_pipeline.h): clip z = near, w = distance along the view axis.
    const float f = 1.f / std::tan(glm::radians(fov_y_degrees) * 0.5f);
    glm::mat4 proj(0.f);
    proj[0][0] = f / aspect;
    proj[1][1] = -f; // Vulkan's y points down, as the image rows.
    proj[2][3] = -1.f;
    proj[3][2] = near_plane;
    return proj * view;
}

} // namespace vx::render
