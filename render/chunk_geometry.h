#pragma once
// CPU side of a chunk's bottom-level acceleration structure. Quads go into "slots", two triangles
// each, laid out slice by slice with spare capacity, so an edit whose slices still fit keeps the
// topology (same primitive count, same index values; unused slots are degenerate triangles) and
// can be applied by a BLAS update (refit) instead of a rebuild. Slot k uses vertices 4k..4k+3 and
// indices (4k, 4k+1, 4k+2), (4k, 4k+2, 4k+3), so every chunk shares one index buffer.
// Vertex positions are chunk-local integers (exact in float). Not thread-safe (plain values).

#include <array>
#include <cstdint>
#include <vector>

#include "world/mesh/chunk_mesh.h"

namespace vx::render {

struct SlotLayout {
    std::array<uint32_t, world::kSliceCount> start{};    // First slot of each slice.
    std::array<uint32_t, world::kSliceCount> capacity{}; // Slots of each slice.
    uint32_t total = 0;                                  // Slots in all.

    // Capacity count + count / 4 + 2 per slice: room for the few quads a block edit adds.
    static SlotLayout for_mesh(const world::ChunkMesh& mesh);
    // True when every slice of `mesh` fits its capacity (the edit can be a refit).
    bool fits(const world::ChunkMesh& mesh) const;
    uint32_t triangle_count() const { return 2 * total; }
};

// Bytes of one slot: 4 vertices of 3 floats, then (in a second array) its Quad.
inline constexpr size_t kSlotVertexBytes = 12 * sizeof(float);
inline constexpr size_t kSlotQuadBytes = sizeof(world::Quad);

// Writes the mesh into its slots: `vertices` gets 12 floats per slot (chunk-local block units),
// `quads` one Quad per slot (Quad{}, block air, in unused slots). Each unused slot gets four
// copies of one nearby real vertex: zero-area triangles, which rays never hit, which stay active
// (so a later refit may reuse them) and which do not stretch BVH nodes. Writes each output byte
// once, in order (the outputs may be write-combined mapped memory).
void fill_slots(const SlotLayout& layout, const world::ChunkMesh& mesh, float* vertices, world::Quad* quads);

// The shared index pattern for `slots` slots.
std::vector<uint32_t> slot_indices(uint32_t slots);

} // namespace vx::render
