#pragma once
// C++ view of shaders/shared/render_types.h, with its layout checked against std140/std430.

#include "shaders/shared/render_types.h"
#include "world/coords.h"

namespace vx::render::gpu {

constexpr size_t kParamsTail = (20 + 2 * kMaxEditBoxes) * 16; // The vec4s, then the uint64 addresses.
static_assert(sizeof(FrameParams) == kParamsTail + 64, "FrameParams: 36 vec4 + 8 uint64");
static_assert(offsetof(FrameParams, sampling) == 18 * 16);
static_assert(offsetof(FrameParams, edits) == 19 * 16);
static_assert(offsetof(FrameParams, edit_boxes) == 20 * 16);
static_assert(offsetof(FrameParams, emitter_quads) == kParamsTail + 32);
static_assert(sizeof(EmitterQuad) == 64);
static_assert(sizeof(EmitterBound) == 32);
static_assert(offsetof(FrameParams, emitter_bounds) == kParamsTail + 40);
static_assert(offsetof(FrameParams, emitter_chunks) == kParamsTail + 16);
static_assert(offsetof(FrameParams, exposure_meter) == kParamsTail + 24);
static_assert(offsetof(FrameParams, sun_direction) == 9 * 16);
static_assert(offsetof(FrameParams, size_samples) == 12 * 16);
static_assert(offsetof(FrameParams, mode_seed) == 13 * 16);
static_assert(offsetof(FrameParams, flags) == 14 * 16);
static_assert(offsetof(FrameParams, exposure) == 15 * 16);
static_assert(offsetof(FrameParams, haze) == 16 * 16);
static_assert(offsetof(FrameParams, cache) == 17 * 16);
static_assert(offsetof(FrameParams, chunk_table) == kParamsTail);
static_assert(offsetof(FrameParams, cache_records) == kParamsTail + 56);
static_assert(offsetof(FrameParams, materials) == kParamsTail + 8);
static_assert(sizeof(ExposureMeter) == 8);
static_assert(sizeof(TracePush) == 32 && offsetof(TracePush, first_hit) == 8 && offsetof(TracePush, last_hit) == 12);
static_assert(offsetof(TracePush, check_marks) == 16 && offsetof(TracePush, check) == 24);
static_assert(sizeof(PathState) == 80); // raygen.rgen's path_list_address() counts on it.
static_assert(sizeof(Material) == 32);
static_assert(offsetof(Material, emission) == 16);
static_assert(kChunkCells == float(world::kChunkSize), "kChunkCells: cells per chunk edge");

} // namespace vx::render::gpu
