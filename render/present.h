#pragma once
// Presentation of traced frames to the window: the swapchain, a per-frame-slot "image acquired"
// semaphore, and the blit of the frame's trace target into the acquired image.
//
// Colour: the trace writes display-ready 8-bit values (what the headless PNG holds: sRGB encoded
// in Full mode) through an R8G8B8A8_UNORM storage view. With an _SRGB swapchain the target image
// itself is R8G8B8A8_SRGB (MUTABLE_FORMAT, the UNORM view for storage), so the blit decodes and
// re-encodes, an identity on 8-bit values, and only reorders channels (RGBA -> BGRA): the window
// shows the PNG's bytes, never encoded twice. With a UNORM swapchain the target stays UNORM.
//
// Frame order (Renderer::present): prepare() -> Context::begin_frame -> acquire() -> record the
// trace -> record_blit() -> Context::end_frame(submit_sync()) -> present(). Main thread only.

#include <optional>

#include "render/renderer.h"
#include "render/resources.h"
#include "render/swapchain.h"

namespace vx::render {

class Presenter {
public:
    // `ctx` must have been created with a window.
    Presenter(Context& ctx, bool vsync);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;
    // Its surface was queried and its semaphores made; false (out of memory, a lost surface:
    // logged, Context::last_create_failure): destroy it.
    bool valid() const { return m_valid; }

    // Format of the trace target whose bytes reach the screen unchanged (see the top).
    VkFormat target_format() const;
    // Before Context::begin_frame: the extent (pixels) to render this frame, recreating the
    // swapchain when the window's framebuffer changed or it went out of date. nullopt: the
    // window is minimised (0x0): skip the frame.
    std::optional<VkExtent2D> prepare();
    // After Context::begin_frame: acquires an image, signalling this slot's semaphore (free: the
    // slot's last submission, which waited on it, has finished). False: the swapchain was out of
    // date or the device was lost (Context::lost()) and nothing was acquired; end the frame
    // without sync and skip it.
    bool acquire();
    // Before acquire(), for a frame recorded with capture: the host buffer. False: out of memory.
    bool prepare_capture();
    // Present mode for the swapchains made from now on (FIFO with vsync); the next prepare()
    // recreates the swapchain when the mode changes.
    void set_vsync(bool vsync) { m_swapchain.set_vsync(vsync); }
    // Records target -> acquired image. `target` is in TRANSFER_SRC_OPTIMAL with the trace's
    // writes made visible to transfers, sized extent() with format target_format(). The image
    // ends in PRESENT_SRC_KHR. With `capture`, also copies the presented image into a host buffer
    // (the swapchain must allow it: can_capture()).
    void record_blit(VkCommandBuffer cmd, VkImage target, bool capture);
    // Semaphores of the frame's submission: wait for the acquire before the blit, signal the
    // image's "done" semaphore.
    FrameSubmitSync submit_sync() const;
    // After Context::end_frame(submit_sync()): queues the acquired image for presentation.
    // False: the device was lost.
    bool present();
    // After a frame recorded with capture has completed: its presented pixels as RGBA, row 0 at
    // the top (empty for swapchain formats other than 8-bit RGBA/BGRA).
    RenderImage read_capture() const;

    const Swapchain& swapchain() const { return m_swapchain; }
    VkExtent2D extent() const { return m_swapchain.extent(); }
    bool can_capture() const { return m_swapchain.can_capture(); }

private:
    Context* m_ctx;
    Swapchain m_swapchain;
    std::array<VkSemaphore, kFramesInFlight> m_acquired{};
    bool m_valid = false;
    uint32_t m_image = 0; // Acquired this frame.
    Buffer m_capture;
    VkExtent2D m_capture_extent{0, 0};
};

} // namespace vx::render
