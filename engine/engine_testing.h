#pragma once
// Fault injection into a vx::Engine's renderer, for vx's own tests (not installed; a game has no
// use for it). Main thread only, like the Engine.

#include <string>

#include <vx/vx.h>

namespace vx {

struct EngineTesting {
    // The next GPU submission reads as VK_ERROR_DEVICE_LOST (render::Context::simulate_device_loss).
    // False without a renderer.
    static bool lose_device(Engine& e);
    // Frame resources whose debug name starts with `name_prefix` fail to allocate until called
    // again with "" (render::Context::fail_allocations). False without a renderer.
    static bool fail_allocations(Engine& e, const std::string& name_prefix);
    // Boxes of edited blocks the renderer holds for its next frame's denoiser
    // (render::Renderer::noted_edits). -1 without a renderer.
    static int noted_edits(Engine& e);
};

} // namespace vx
