#pragma once
// A game's 2D UI over the frame (render::UiDrawList, e.g. Dear ImGui's output): a small graphics
// pipeline (shaders/ui.vert, ui.frag) draws the list's triangles into the frame's target after
// the trace and the denoiser, through the target's UNORM view, so blending mixes the bytes the
// screen shows (sRGB encoded), as Dear ImGui expects; straight alpha (src * a + dst * (1 - a)),
// the target's alpha kept; a scissor per command. Drawing into the target rather than into the
// swapchain image means render() (headless) shows the same UI as present(), and captures hold
// it. No vertex input state and no descriptors: the vertex shader pulls vertices and the
// fragment shader texels through buffer device addresses. The vertices and indices are copied
// each frame into a host-visible buffer of the frame slot; the texture into a device buffer when
// it changes (the old one retires with the frame). Main thread only.

#include <array>
#include <vector>

#include "render/context.h"
#include "render/renderer.h"
#include "render/resources.h"

namespace vx::render {

class UiPass {
public:
    // `color_format`: the format of the target views record() draws into.
    UiPass(Context& ctx, VkFormat color_format);
    ~UiPass();
    UiPass(const UiPass&) = delete;
    UiPass& operator=(const UiPass&) = delete;

    void set(UiDrawList list) { m_list = std::move(list); }
    // Allocates the texture and its staging now (copied at the next record()). False when GPU
    // memory runs out (logged): the previous texture stays.
    bool set_texture(uint32_t width, uint32_t height, std::vector<uint8_t> rgba);
    bool empty() const { return m_list.cmds.empty(); }

    // Records the UI over `target` (width x height, in TRANSFER_SRC_OPTIMAL after earlier writes
    // made visible to transfers); it ends in TRANSFER_SRC_OPTIMAL with the UI's writes visible to
    // transfers. `view`: a view of format color_format. Nothing is recorded for an empty list.
    // Call prepare() first, in the same frame.
    void record(VkCommandBuffer cmd, VkImage target, VkImageView view, uint32_t width, uint32_t height);
    // After Context::begin_frame, before record(): allocates what this frame's UI needs (the
    // default texture, the slot's geometry buffer, the pipeline at first) and copies the list in.
    // False when GPU memory runs out (logged): the frame must not record the UI.
    bool prepare();

private:
    bool create_pipeline(); // False: out of memory (logged); prepare() tries again.
    void upload_texture(VkCommandBuffer cmd);
    bool prepare_texture(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba);
    bool upload_geometry(VkDeviceSize* index_offset);

    Context* m_ctx;
    VkFormat m_color_format;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    UiDrawList m_list;
    uint32_t m_tex_width = 1, m_tex_height = 1;
    Buffer m_texture; // Device memory, RGBA8 texels.
    // The next texture (set_texture) and its texels in host memory, copied at the next record().
    Buffer m_next_texture, m_next_staging;
    VkDeviceSize m_index_offset = 0; // Of this frame's indices in its geometry buffer (prepare).
    uint32_t m_next_width = 1, m_next_height = 1;
    std::array<Buffer, kFramesInFlight> m_geometry; // Vertices, then indices (4-byte aligned).
};

} // namespace vx::render
