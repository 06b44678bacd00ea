#pragma once
// SceneAccel's per-frame build budget, shared by its constructor (scene_accel.cpp) and the frame's
// builds (scene_accel_builds.cpp). Private to vx_render.

#include <algorithm>

#include "render/context.h"

namespace vx::render {

// At most this much staging and BLAS build scratch per frame; the rest of the pending chunks
// waits for later frames. It bounds the two shared buffers: a scene sent whole (as after
// Engine::recreate_renderer) asked for a staging buffer and a scratch buffer each as large as the
// whole scene's. 2 GiB keeps the seed scene (15.4 million quads, 56 bytes each: 0.87 GB of
// staging) in one frame, as the benchmarks' warm-up frames assume; failures shrink it.
constexpr VkDeviceSize kMaxFrameBuildBytes = 2048ull << 20;

inline VkDeviceSize frame_build_cap(const Context& ctx) {
    return ctx.max_buffer_size() ? std::min(kMaxFrameBuildBytes, ctx.max_buffer_size()) : kMaxFrameBuildBytes;
}

} // namespace vx::render
