#pragma once
// The ray-tracing pipeline (two raygen groups: full shading and Flat, see raygen_flat.rgen; primary
// miss, shadow miss, one triangle hit group with a closest-hit shader and the shadow any-hit
// shader) and its shader binding table, with handle
// size and alignments read from the device. Descriptor set 0: binding 0 TLAS, 1 output storage
// image (rgba8), 2 FrameParams uniform, 3-5 the G-buffer storage images (render/gbuffer.h); the
// light cache's resolve pass (render/light_cache.h) binds the same set in a compute pipeline.
// Variants by specialization constants: full shading without and with the emissive faces'
// sampling (raygen.rgen's kSampleFaces), and three levels of see-through blocks (SeeThrough). Code
// a frame does not run still costs registers: without it a frame with no emitter faces (the thesis
// scene, terrain without lamps) traces as fast as before it existed, and one with no see-through
// block pays nothing for water. Made when first needed (ensure_variant). Main thread only.

#include <array>

#include "render/commands.h"
#include "render/gpu_layouts.h"
#include "render/pipeline_report.h"
#include "render/resources.h"

namespace vx::render {

// The shader binding table's regions: [raygen][raygen flat][primary miss, shadow miss][hit], each
// starting at a multiple of shaderGroupBaseAlignment in device-address space
// (VUID-vkCmdTraceRaysKHR-pRayGenShaderBindingTable-03682). The buffer's address need not be so
// aligned (only the allocation's offset within its memory block is), so `bytes` holds `base`
// bytes of slack and the table starts at sbt_start(): the buffer's address aligned up.
struct SbtLayout {
    VkDeviceSize stride = 0;      // One handle, aligned to shaderGroupHandleAlignment.
    VkDeviceSize raygen_size = 0; // Each raygen region (stride == size for raygen).
    VkDeviceSize miss_size = 0, hit_size = 0;
    VkDeviceSize raygen_flat_at = 0, miss_at = 0, hit_at = 0; // Offsets from the table's start.
    VkDeviceSize bytes = 0;       // Buffer size to allocate, slack included.
};
SbtLayout sbt_layout(uint32_t handle_size, uint32_t handle_alignment, uint32_t base_alignment);
// Where the table starts in a buffer at `buffer_address`: the first base-aligned address.
inline VkDeviceAddress sbt_start(VkDeviceAddress buffer_address, uint32_t base_alignment) {
    return align_up(buffer_address, base_alignment);
}

// What the walk through see-through blocks (shaders/shared/raygen_common.glsl) is compiled with:
// kNone, nothing (no see-through block drawn, the eye in none: every hit is opaque; kSeeThrough
// false); kPlain, the walk, tints and water and glass surfaces; kProbe, also the probe for a
// coincident face where two different see-through blocks touch, and the shadow rays' pairing of
// such faces (kProbeTouching).
enum class SeeThrough : uint8_t { kNone, kPlain, kProbe };

class RtPipeline {
public:
    // False when the device had no memory for the pipeline or its shader binding table (the
    // renderer's create() reports it).
    bool valid() const {
        const Variant& v = m_variants[variant_index(false, SeeThrough::kPlain)];
        return v.pipeline && v.sbt.valid();
    }
    explicit RtPipeline(Context& ctx);
    ~RtPipeline();
    RtPipeline(const RtPipeline&) = delete;
    RtPipeline& operator=(const RtPipeline&) = delete;

    VkPipelineLayout layout() const { return m_layout; }
    VkDescriptorSetLayout set_layout() const { return m_set_layout; }

    // Makes the variant that samples emitter faces or not, with see-through level `see_through`,
    // unless it exists; false: out of memory for it or its shader binding table (nothing made; a
    // later call tries again). The constructor makes (no faces, kPlain).
    bool ensure_variant(bool sample_faces, SeeThrough see_through);

    // Binds that variant (made by ensure_variant), pushes `push` (which pass, gpu::TracePush) and
    // records vkCmdTraceRaysKHR over width x height with its SBT regions; `flat` picks the Flat
    // raygen (FrameParams mode Flat), else the full-shading one. The caller binds the descriptor set.
    void trace(VkCommandBuffer cmd, uint32_t width, uint32_t height, bool flat, bool sample_faces,
               SeeThrough see_through, const gpu::TracePush& push) const;

    // What the driver made of that variant (render/pipeline_report.h), made first unless it exists;
    // an empty name when it could not be made (out of memory). Main thread only.
    PipelineVariantReport report(bool sample_faces, SeeThrough see_through);

private:
    struct Variant {
        VkPipeline pipeline = VK_NULL_HANDLE;
        std::string name; // Its debug name.
        Buffer sbt;
        VkStridedDeviceAddressRegionKHR raygen{}, raygen_flat{}, miss{}, hit{}, callable{};
    };
    void create_layouts();
    Variant create_variant(bool sample_faces, SeeThrough see_through); // Its SBT invalid when out of memory.
    static size_t variant_index(bool sample_faces, SeeThrough see_through) {
        return size_t(sample_faces) + 2 * size_t(see_through);
    }
    bool create_sbt(Variant& v, const char* name);

    Context* m_ctx;
    VkDescriptorSetLayout m_set_layout = VK_NULL_HANDLE;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    std::array<Variant, 6> m_variants; // [variant_index(sample_faces, see_through)]
};

// The statistics of each executable the driver compiled `pipeline` into, made with
// VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR (none unless ctx.pipeline_statistics()).
std::vector<PipelineExecutable> read_executables(const Context& ctx, VkPipeline pipeline);

} // namespace vx::render
