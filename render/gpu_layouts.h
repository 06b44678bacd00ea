#pragma once
// C++ view of shaders/shared/render_types.h, with its layout checked against std140/std430.

#include "shaders/shared/render_types.h"

namespace vx::render::gpu {

static_assert(sizeof(FrameParams) == 15 * 16 + 16, "FrameParams: 15 vec4 + 2 uint64");
static_assert(offsetof(FrameParams, sun_direction) == 9 * 16);
static_assert(offsetof(FrameParams, size_samples) == 12 * 16);
static_assert(offsetof(FrameParams, mode_seed) == 13 * 16);
static_assert(offsetof(FrameParams, flags) == 14 * 16);
static_assert(offsetof(FrameParams, chunk_table) == 15 * 16);
static_assert(offsetof(FrameParams, materials) == 15 * 16 + 8);
static_assert(sizeof(Material) == 32);
static_assert(offsetof(Material, emission) == 16);

} // namespace vx::render::gpu
