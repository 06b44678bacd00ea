#include "render/ui_pass.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

#include "render/commands.h"
#include "render/graphics_pipeline.h"
#include "render/shader_code.h"
#include "shaders/shared/ui_types.h"

namespace vx::render {

static_assert(sizeof(UiVertex) == 20 && offsetof(UiVertex, uv) == 8 && offsetof(UiVertex, rgba) == 16,
              "UiVertex: the 5-word layout ui.vert reads");
static_assert(sizeof(gpu::UiPush) == 32 && offsetof(gpu::UiPush, pixel_to_clip) == 16, "UiPush layout");

std::string ui_draw_list_error(const UiDrawList& list) {
    for (uint32_t i : list.indices)
        if (i >= list.vertices.size())
            return "UI draw list: index " + std::to_string(i) + " past its " + std::to_string(list.vertices.size()) +
                   " vertices";
    for (const UiDrawCmd& c : list.cmds)
        if (uint64_t(c.index_offset) + c.index_count > list.indices.size() || c.index_count % 3 != 0)
            return "UI draw list: a command's indices are past the index list or not whole triangles";
    return {};
}

UiPass::UiPass(Context& ctx, VkFormat color_format) : m_ctx(&ctx), m_color_format(color_format) {}

UiPass::~UiPass() {
    if (m_pipeline)
        m_ctx->retire_list().pipelines.push_back(m_pipeline);
    vkDestroyPipelineLayout(m_ctx->device(), m_layout, nullptr);
}

bool UiPass::create_pipeline() {
    if (!m_layout)
        m_layout = make_push_constant_layout(*m_ctx, sizeof(gpu::UiPush), "ui pipeline layout");
    // No culling: Dear ImGui's winding is not fixed.
    m_pipeline = make_graphics_pipeline(*m_ctx, {.vert = spirv::ui_vert(),
                                                 .frag = spirv::ui_frag(),
                                                 .vert_name = "ui.vert",
                                                 .frag_name = "ui.frag",
                                                 .name = "ui pipeline",
                                                 .layout = m_layout,
                                                 .color_format = m_color_format,
                                                 .blend = Blend::Alpha});
    return m_pipeline != VK_NULL_HANDLE;
}

bool UiPass::set_texture(uint32_t width, uint32_t height, std::vector<uint8_t> rgba) {
    VX_ASSERT(width > 0 && height > 0 && rgba.size() == size_t(width) * height * 4);
    return prepare_texture(width, height, rgba);
}

// A new device buffer and its filled staging buffer; frames in flight keep reading the current
// texture until the next record() copies this one in (the replaced buffers retire then).
bool UiPass::prepare_texture(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba) {
    const VkDeviceSize bytes = rgba.size();
    Buffer staging = Buffer::create(*m_ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, 0, "ui texture staging"});
    if (!staging.valid())
        return false; // Logged by Buffer::create.
    Buffer texture = Buffer::create(*m_ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             MemoryUse::Device, 0, "ui texture"});
    if (!texture.valid())
        return false; // Logged by Buffer::create.
    std::memcpy(staging.mapped(), rgba.data(), bytes);
    m_next_staging = std::move(staging);
    m_next_texture = std::move(texture);
    m_next_width = width;
    m_next_height = height;
    return true;
}

void UiPass::upload_texture(VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, m_next_texture.size()};
    vkCmdCopyBuffer(cmd, m_next_staging.handle(), m_next_texture.handle(), 1, &region);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    m_texture = std::move(m_next_texture); // The old one retires with this frame.
    m_next_staging.reset();                // Retires with this frame, after the copy.
    m_tex_width = m_next_width;
    m_tex_height = m_next_height;
}

// Copies the list's vertices and indices into this frame slot's buffer (grown when too small).
bool UiPass::upload_geometry(VkDeviceSize* index_offset) {
    const VkDeviceSize vbytes = m_list.vertices.size() * sizeof(UiVertex);
    const VkDeviceSize bytes = vbytes + m_list.indices.size() * sizeof(uint32_t);
    Buffer& g = m_geometry[m_ctx->frame_slot()];
    if (!g.valid() || g.size() < bytes) {
        g = Buffer::create(*m_ctx, {std::max<VkDeviceSize>(bytes * 3 / 2, 4096),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                    MemoryUse::Upload, 0, "ui geometry"});
        if (!g.valid())
            return false;
    }
    auto* dst = static_cast<uint8_t*>(g.mapped());
    std::memcpy(dst, m_list.vertices.data(), vbytes);
    std::memcpy(dst + vbytes, m_list.indices.data(), m_list.indices.size() * sizeof(uint32_t));
    *index_offset = vbytes;
    return true;
}

bool UiPass::prepare() {
    if (m_list.cmds.empty() || m_list.indices.empty())
        return true;
    if (!m_pipeline && !create_pipeline())
        return false;
    // Until the game sets one, the texture is one white texel.
    if (!m_texture.valid() && !m_next_texture.valid() && !prepare_texture(1, 1, {255, 255, 255, 255}))
        return false;
    return upload_geometry(&m_index_offset);
}

void UiPass::record(VkCommandBuffer cmd, VkImage target, VkImageView view, uint32_t width, uint32_t height) {
    if (m_list.cmds.empty() || m_list.indices.empty())
        return;
    const VkDeviceSize index_offset = m_index_offset;
    if (m_next_texture.valid())
        upload_texture(cmd);
    const Buffer& g = m_geometry[m_ctx->frame_slot()];
    // After the trace/denoiser/raster writes, which were made visible to transfers.
    image_barrier(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = view;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {width, height}};
    ri.layerCount = 1;
    ri.colorAttachmentCount = 1;
    ri.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m_pipeline);
    const VkViewport viewport{0.f, 0.f, float(width), float(height), 0.f, 1.f};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdBindIndexBuffer(cmd, g.handle(), index_offset, VK_INDEX_TYPE_UINT32);
    gpu::UiPush push{};
    push.vertices = g.address();
    push.texture = m_texture.address();
    push.pixel_to_clip = {2.f / float(width), 2.f / float(height)};
    push.texture_size = {m_tex_width, m_tex_height};
    vkCmdPushConstants(cmd, m_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push, &push);
    for (const UiDrawCmd& c : m_list.cmds) {
        const int32_t x0 = std::clamp(c.clip_rect.x, 0, int32_t(width)), y0 = std::clamp(c.clip_rect.y, 0, int32_t(height));
        const int32_t x1 = std::clamp(c.clip_rect.z, 0, int32_t(width)), y1 = std::clamp(c.clip_rect.w, 0, int32_t(height));
        if (x1 <= x0 || y1 <= y0 || c.index_count == 0)
            continue;
        const VkRect2D scissor{{x0, y0}, {uint32_t(x1 - x0), uint32_t(y1 - y0)}};
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdDrawIndexed(cmd, c.index_count, 1, c.index_offset, 0, 0);
    }
    vkCmdEndRendering(cmd);
    image_barrier(cmd, target, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
}

} // namespace vx::render
