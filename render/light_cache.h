#pragma once
// The light cache: within one frame, the hits of all paths share their light estimates (all but
// the sun's) through a hash table of surface cells a few pixels wide (shaders/shared/
// light_cache.glsl has the cells and the papers). At a few samples a hit's light is a few
// shadow and sky rays' worth; the pixels that see the same patch of a face, directly or through
// mirrors, pool theirs. The ray generation records each hit's cell key, the path's weights and
// its own estimate per pixel and hit instead of adding it to the pixel; the gather pass
// (shaders/light_cache_gather.comp) adds the records to their cells, a subgroup's hits of one
// cell with one set of atomics; the resolve pass (shaders/light_cache.comp) adds each hit's own
// estimate moved towards its cell's mean as far as the cell's spread says that lowers the
// error, before the denoiser.
// Biased by the light's change across a cell, consistent as cells shrink with the pixels:
// docs/render_report.md measures both against the noise it removes.
//
// GPU memory: a table of 36 bytes per cell, two cells per pixel (a power of two), and 32 bytes
// per pixel per cached hit (the primary hit and up to gpu::kMaxCachedBounces mirror bounces),
// rewritten every frame. One table serves all frame slots: the renderer's frame-start barrier
// orders consecutive frames. Main thread only.

#include <cstdint>

#include "render/resources.h"

namespace vx::render {

class LightCache {
public:
    // `set_layout`: the ray-tracing descriptor set (render/rt_pipeline.h), which the resolve
    // pass binds too.
    LightCache(Context& ctx, VkDescriptorSetLayout set_layout);
    ~LightCache();
    LightCache(const LightCache&) = delete;
    LightCache& operator=(const LightCache&) = delete;
    // Its pipelines were made; false (out of memory, logged): destroy it, a later frame retries.
    bool valid() const { return m_pipeline != VK_NULL_HANDLE; }

    // Buffers for width x height frames whose paths cache the primary hit and `bounces`
    // (0..gpu::kMaxCachedBounces) mirror bounces; kept when large enough. false: out of GPU
    // memory (logged; the old buffers are gone and cells() is 0 until a later call succeeds).
    bool ensure(uint32_t width, uint32_t height, uint32_t bounces);

    uint32_t cells() const { return m_cells; } // Table size (a power of two); 0: none.
    VkDeviceAddress table() const { return m_table.address(); }
    VkDeviceAddress records() const { return m_records.address(); }

    // Before the trace: empties the table and orders that before the ray generation's use.
    void record_clear(VkCommandBuffer cmd) const;
    // After the trace (whose writes it waits for) over width x height pixels with the trace's
    // descriptor set: the gather pass (the records into the table), then the resolve; their
    // writes are ordered before later compute, transfer and host reads.
    void record_resolve(VkCommandBuffer cmd, VkDescriptorSet set, uint32_t width, uint32_t height) const;

    // Test hook: the table has at most `cells` cells (a power of two; 0: as sized), so that hits
    // find their probes taken and keep their own estimates.
    void limit_cells_for_testing(uint32_t cells) { m_cell_limit = cells; }

private:
    Context* m_ctx;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkPipeline m_gather = VK_NULL_HANDLE;   // shaders/light_cache_gather.comp.
    VkPipeline m_pipeline = VK_NULL_HANDLE; // The resolve (shaders/light_cache.comp); made last.
    Buffer m_table;   // uint keys[cells], vec4 values[cells], vec4 stats[cells] (light_cache.glsl).
    Buffer m_records; // Two uvec4 per pixel per cached hit (the cell and weights; the own estimate).
    uint32_t m_cells = 0;
    uint64_t m_record_count = 0;
    uint32_t m_cell_limit = 0;
};

} // namespace vx::render
