#pragma once
// The raster baseline (the thesis's comparison): the scene's chunks drawn with a graphics
// pipeline straight from their quad records (vertex pulling in shaders/raster.vert, no vertex
// buffers, so cold chunks that dropped their BLAS vertices draw too), a depth buffer, and Phong
// shading with one point light (shaders/raster.frag). Same camera model as the ray tracer's
// (pixel centres, y down), so a Flat image covers the pixels the ray tracer's does.
// Work kept proportionate: chunks outside the view frustum are skipped on the CPU; each chunk is
// one indexed draw over the shared slot index pattern (4 vertex shader runs per quad, not 6);
// the vertex shader drops spare slots and back faces of opaque blocks (never the first thing a
// ray from outside the blocks hits) before rasterisation.
// See-through blocks (registry opacity false) tint what lies behind them as the ray tracer's
// trace_through does (docs/architecture.md, Transparency): a first pass draws the opaque faces
// with depth writes, a second the transparent faces, both sides, depth tested against the first
// but not written, blended dst = dst x albedo^chord on the faces where the view enters a block
// (raster.frag: the view's path through that block; the ray tracer absorbs along the whole path in
// a body of blocks). A product does not depend on the order of its factors, so faces need no
// sorting (up to 8-bit rounding per face). The second
// pass skips chunks of opaque blocks only (DrawChunk::opaque) and Visibility mode. Unlike the
// ray tracer it has no kMaxTransparentLayers limit.
// Dynamic rendering (Vulkan 1.3). Main thread only.

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "render/renderer.h"
#include "render/resources.h"
#include "render/scene_accel.h"

namespace vx::render {

// What a raster frame needs besides the chunks.
struct RasterFrame {
    VkImage target = VK_NULL_HANDLE; // Colour target (any layout: its contents are cleared).
    VkImageView target_view = VK_NULL_HANDLE; // A view of format `color_format` (see the ctor).
    uint32_t width = 0, height = 0;
    world::BlockPos camera_block{0};
    glm::vec3 camera_offset{0.5f};
    glm::mat4 clip_from_eye{1.f}; // raster_clip_from_eye().
    uint32_t mode = 0;            // gpu::kModeFlat / kModeFull / kModeVisibility.
    glm::dvec3 light_position{0}; // Relative to the camera's block (the area light's centre).
    glm::vec3 light_power{0};     // Point-light intensity, linear RGB.
    float exposure = 1;           // Full mode: radiance to tone-curve input (vx_exposure_scale).
    glm::vec3 sky{0};             // Clear colour (the ray tracer's sky on a miss), written as is.
    VkDeviceAddress materials = 0;
};

class RasterPipeline {
public:
    // `color_format`: the format of the target views record() draws into.
    RasterPipeline(Context& ctx, VkFormat color_format);
    ~RasterPipeline();
    RasterPipeline(const RasterPipeline&) = delete;
    // Its pipelines were made; false (out of memory, logged): destroy it, a later frame retries.
    bool valid() const { return m_pipeline != VK_NULL_HANDLE && m_transparent != VK_NULL_HANDLE; }
    RasterPipeline& operator=(const RasterPipeline&) = delete;

    // Chunks record() drew: inside the view frustum; of those, with transparent blocks.
    struct Draws {
        uint32_t chunks = 0, transparent = 0;
    };
    // Records the clear and one draw per chunk inside the view frustum (a level-k chunk: its
    // quads scaled by 2^k at lod_origin, render/tlas_instances.h), then one more per such chunk
    // with transparent blocks, into `cmd`, leaving the target in TRANSFER_SRC_OPTIMAL (as the
    // ray tracer's trace does). The chunks' quad buffers must have been uploaded earlier in
    // `cmd` or before (SceneAccel::record_builds); `indices` is SceneAccel::index_buffer(),
    // covering every chunk's slots.
    Draws record(VkCommandBuffer cmd, const RasterFrame& frame, std::span<const SceneAccel::DrawChunk> chunks,
                    VkBuffer indices);
    // Before record(), after Context::begin_frame: this frame slot's depth buffer for width x
    // height frames. False when GPU memory runs out (logged): do not record().
    bool ensure_depth(uint32_t width, uint32_t height);

private:
    void create_pipeline(VkFormat color_format);

    Context* m_ctx;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;    // Opaque faces, depth written.
    VkPipeline m_transparent = VK_NULL_HANDLE; // Transparent faces, multiplied in.
    std::array<Image, kFramesInFlight> m_depth;
    std::vector<uint32_t> m_see_through; // record(): drawn chunks with transparent blocks (capacity kept).
};

// Whether the axis-aligned box [lo, hi] (positions relative to the eye) may intersect the view
// volume of `clip_from_eye` (its planes; conservative: a box near a frustum corner may pass).
bool raster_box_visible(const glm::mat4& clip_from_eye, glm::vec3 lo, glm::vec3 hi);

// Vulkan clip space (y down) of a camera looking along `forward` with `up` and a vertical field of
// view in degrees, for positions relative to the eye. Rows of pixels match the ray tracer's
// primary rays (shaders/raygen.rgen). Depth is reversed with no far plane: 1 at `near_plane`
// blocks, near_plane / distance beyond, compared GREATER. Float depth then keeps its relative
// precision at any distance; the standard 0..1 mapping to a far plane of 8192 let surfaces 24
// blocks apart swap at 2,000 blocks and dropped everything past about 7,900 (Reed, "Depth
// Precision Visualized", 2015; Lapidous and Jiao 1999).
glm::mat4 raster_clip_from_eye(glm::vec3 forward, glm::vec3 up, float fov_y_degrees, float aspect,
                               float near_plane = 0.02f);

} // namespace vx::render
