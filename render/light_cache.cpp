#include "render/light_cache.h"

#include <algorithm>
#include <bit>

#include "render/commands.h"
#include "render/gpu_layouts.h"
#include "render/graphics_pipeline.h"
#include "render/shader_code.h"

namespace vx::render {

namespace {
constexpr VkDeviceSize kCellBytes = sizeof(uint32_t) + 2 * sizeof(glm::vec4); // Key, value, statistics.
constexpr uint32_t kCellsPerPixel = 2; // Cells hold several hits: the table stays mostly empty, its probes short.
constexpr uint32_t kMinCells = 1024;
} // namespace

LightCache::LightCache(Context& ctx, VkDescriptorSetLayout set_layout) : m_ctx(&ctx) {
    VkPipelineLayoutCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    ci.setLayoutCount = 1;
    ci.pSetLayouts = &set_layout;
    if (ctx.create_call("vkCreatePipelineLayout (light cache layout)",
                        [&] { return vkCreatePipelineLayout(ctx.device(), &ci, nullptr, &m_layout); }) != VK_SUCCESS)
        return; // Out of memory: valid() is false.
    ctx.set_name(m_layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, "light cache layout");
    m_gather = make_compute_pipeline(ctx, m_layout, spirv::light_cache_gather(), "light_cache_gather.comp");
    if (m_gather != VK_NULL_HANDLE)
        m_pipeline = make_compute_pipeline(ctx, m_layout, spirv::light_cache_resolve(), "light_cache.comp");
}

LightCache::~LightCache() {
    m_ctx->retire_list().pipelines.push_back(m_gather); // Retire with the frame.
    m_ctx->retire_list().pipelines.push_back(m_pipeline);
    vkDestroyPipelineLayout(m_ctx->device(), m_layout, nullptr);
}

bool LightCache::ensure(uint32_t width, uint32_t height, uint32_t bounces) {
    VX_ASSERT(bounces <= gpu::kMaxCachedBounces);
    const uint64_t want = std::max<uint64_t>(uint64_t(width) * height * kCellsPerPixel, kMinCells);
    uint32_t cells = uint32_t(std::min<uint64_t>(std::bit_ceil(want), 1ull << 31));
    if (m_cell_limit)
        cells = std::min(cells, m_cell_limit);
    const uint64_t records = uint64_t(width) * height * (bounces + 1);
    if (m_table.valid() && m_cells == cells && m_records.valid() && m_record_count >= records)
        return true;
    m_table.reset();
    m_records.reset();
    m_cells = 0;
    m_record_count = 0;
    m_table = Buffer::create(*m_ctx, {cells * kCellBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      MemoryUse::Device, 0, "light cache table"});
    m_records = Buffer::create(*m_ctx, {records * 2 * sizeof(glm::uvec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                        MemoryUse::Device, 0, "light cache records"});
    if (!m_table.valid() || !m_records.valid()) {
        m_table.reset();
        m_records.reset();
        return false;
    }
    m_cells = cells;
    m_record_count = records;
    return true;
}

void LightCache::record_clear(VkCommandBuffer cmd) const {
    vkCmdFillBuffer(cmd, m_table.handle(), 0, VK_WHOLE_SIZE, 0u); // Empty keys, zero sums.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void LightCache::record_resolve(VkCommandBuffer cmd, VkDescriptorSet set, uint32_t width, uint32_t height) const {
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_layout, 0, 1, &set, 0, nullptr);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_gather);
    vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_pipeline);
    vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

} // namespace vx::render
