#pragma once
// The ray-tracing pipeline (two raygen groups: full shading and Flat, see raygen_flat.rgen; primary
// miss, shadow miss, one triangle hit group with a closest-hit shader and the shadow any-hit
// shader) and its shader binding table, with handle
// size and alignments read from the device. Descriptor set 0: binding 0 TLAS, 1 output storage
// image (rgba8), 2 FrameParams uniform, 3-5 the G-buffer storage images (render/gbuffer.h).
// Main thread only.

#include "render/resources.h"

namespace vx::render {

class RtPipeline {
public:
    explicit RtPipeline(Context& ctx);
    ~RtPipeline();
    RtPipeline(const RtPipeline&) = delete;
    RtPipeline& operator=(const RtPipeline&) = delete;

    VkPipeline pipeline() const { return m_pipeline; }
    VkPipelineLayout layout() const { return m_layout; }
    VkDescriptorSetLayout set_layout() const { return m_set_layout; }

    // Records vkCmdTraceRaysKHR over width x height with this pipeline's SBT regions; `flat`
    // picks the Flat raygen (FrameParams mode Flat), else the full-shading one.
    void trace(VkCommandBuffer cmd, uint32_t width, uint32_t height, bool flat) const;

private:
    void create_layouts();
    void create_pipeline();
    void create_sbt();

    Context* m_ctx;
    VkDescriptorSetLayout m_set_layout = VK_NULL_HANDLE;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    Buffer m_sbt;
    VkStridedDeviceAddressRegionKHR m_raygen{}, m_raygen_flat{}, m_miss{}, m_hit{}, m_callable{};
};

} // namespace vx::render
