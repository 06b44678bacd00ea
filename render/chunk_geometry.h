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

    // Capacity count + count / 4 + 2 per slice: room for the few quads a block edit adds (the
    // layout of a "hot" chunk, one that is being edited and refitted).
    static SlotLayout for_mesh(const world::ChunkMesh& mesh);
    // Capacity = count: no spare slot (the layout of a "cold" chunk, built once and compacted).
    static SlotLayout exact(const world::ChunkMesh& mesh);
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

// Writes only slice `s` of `mesh` into its slots, as fill_slots would: `vertices` points at the
// slice's first slot (12 * capacity[s] floats), `quads` likewise (capacity[s] Quads). Its spares
// collapse onto the last real vertex before them in slot order (earlier slices of `mesh`).
// Used to upload just the slices an edit changed before a refit.
void fill_slice(const SlotLayout& layout, const world::ChunkMesh& mesh, int s, float* vertices, world::Quad* quads);

// A 64-bit hash of the mesh's quads, slice by slice (order within a slice counts): tells an
// unchanged mesh sent again from an edit.
uint64_t mesh_hash(const world::ChunkMesh& mesh);

// The shared index pattern for `slots` slots.
std::vector<uint32_t> slot_indices(uint32_t slots);

} // namespace vx::render
