#pragma once
// A 2D overlay over the presented frame (a game's HUD) without a graphics pipeline: the game
// draws its panels into one RGBA8 atlas on the CPU, and each frame a list of rectangles is blit
// from the atlas into the swapchain image after the trace's blit (nearest filtering, opaque: no
// blending). The atlas is uploaded only when its version changes, through a per-frame-slot
// staging buffer (the frame before may still be reading the other one). The atlas image has the
// trace target's format, so its bytes reach the screen unchanged (see present.h). Main thread.

#include <array>

#include "render/context.h"
#include "render/renderer.h"
#include "render/resources.h"

namespace vx::render {

class OverlayPass {
public:
    // `format`: the trace target's (Presenter::target_format()).
    OverlayPass(Context& ctx, VkFormat format) : m_ctx(&ctx), m_format(format) {}

    // Replaces the overlay for later frames (copies `data`).
    void set(OverlayData data) { m_data = std::move(data); }
    // Records the atlas upload (when changed) and the blits into `dst`, which is in
    // TRANSFER_DST_OPTIMAL with earlier transfer writes; it stays in that layout. Rectangles not
    // inside `extent` or the atlas are skipped (the game lays its HUD out for the framebuffer).
    void record(VkCommandBuffer cmd, VkImage dst, VkExtent2D extent);

private:
    bool upload(VkCommandBuffer cmd);

    Context* m_ctx;
    VkFormat m_format;
    OverlayData m_data;
    Image m_atlas;
    std::array<Buffer, kFramesInFlight> m_staging;
    uint64_t m_uploaded_version = ~uint64_t(0);
};

} // namespace vx::render
