#pragma once
// The emissive faces a frame samples directly (next-event estimation,
// shaders/shared/finite_light.glsl finite_light()): each emissive chunk's emissive quads, kept by
// the Renderer as chunks are set, and the frame's list of the nearest chunks' faces
// (shaders/shared/render_types.h, EmitterQuad). A lamp a few blocks away covers a hundredth of the
// sky rays' hemisphere, so rays that must hit it by chance leave the lit floor mostly noise; a
// shadow ray aimed at a point on its face is unbiased at every sample. Main thread (the
// Renderer's), no GPU calls.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "shaders/shared/render_types.h"
#include "world/lod/lod_coords.h"
#include "world/mesh/chunk_mesh.h"

namespace vx::render {

// Appends to `out` the quads of `mesh` whose block emits: emissive[id] (ids past its end do
// not: unregistered ids draw with a fallback material that does not emit).
void collect_emissive_quads(const world::ChunkMesh& mesh, const std::vector<bool>& emissive,
                            std::vector<world::Quad>& out);

// Quad q of chunk c as an EmitterQuad in blocks relative to `origin` (the render origin,
// render/tlas_instances.h: 64-bit difference first, then float, as the TLAS's translations),
// scaled by the chunk's cell size (2^level blocks), emitting `emission`.
gpu::EmitterQuad emitter_quad(world::LodCoord c, const world::Quad& q, world::BlockPos origin, glm::vec3 emission);

struct EmitterListSize {
    uint32_t quads = 0;          // Entries written.
    uint32_t covered_chunks = 0; // The first this many chunks have all their faces there.
};

// The faces of chunks[0], chunks[1], ... (nearest first) into `dst` while each chunk's faces fit
// whole, and each such chunk's bound (the box around its faces, their power) into `bounds`.
// Stops at the first chunk that does not fit or whose faces are unknown (quads_of returns
// nullptr: it was meshed before the materials changed): that chunk and the rest are left to the
// sky rays that hit them, as before direct sampling, so nothing is counted twice or lost.
EmitterListSize write_emitter_quads(std::span<const world::LodCoord> chunks,
                                    const std::function<const std::vector<world::Quad>*(world::LodCoord)>& quads_of,
                                    const std::function<glm::vec3(world::BlockId)>& emission_of,
                                    world::BlockPos origin, std::span<gpu::EmitterQuad> dst,
                                    std::span<gpu::EmitterBound> bounds);

} // namespace vx::render
