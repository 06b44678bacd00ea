#pragma once
// Which quad each slot of a hot chunk's BLAS holds (chunk_geometry.h for slots), so that the
// refit after an edit keeps every quad the edit did not change in the slot it had.
//
// Why: a BLAS update keeps the tree built for the old primitives and only refits its boxes
// (Vulkan spec, "Acceleration Structure Update Rules": same primitives, new positions). Writing
// a changed slice in mesh order shifts every quad after the first change by a slot, so each
// primitive takes its scan-order neighbour's position and the leaves, grouped by the builder for
// the old positions, stretch across the plane: measured on the H200 (seed scene, one block
// toggled per chunk), the traced frame was 2.2x slower after one such refit and 3.4x after 100.
// Here unchanged quads stay put, a removed quad's slot collapses to a point inside its old box,
// and a new quad takes the free slot whose point lies nearest to it. Not thread-safe (a value).

#include <cstdint>
#include <vector>

#include "render/chunk_geometry.h"

namespace vx::render {

class SlotMap {
public:
    // Slots laid out as fill_slots() does (mesh order; spares collapsed onto the last real vertex
    // before them); write_all() then writes fill_slots()' bytes.
    void assign(const SlotLayout& layout, const world::ChunkMesh& mesh);
    // Re-assigns slice `s` to `mesh`'s quads of that slice (which fit its capacity) as above.
    void update_slice(const SlotLayout& layout, const world::ChunkMesh& mesh, int s);
    // Writes slice `s`'s slots: 12 * capacity[s] floats (chunk-local block units) and
    // capacity[s] Quads (Quad{} in unused slots), as fill_slice() lays them out.
    void write_slice(const SlotLayout& layout, int s, float* vertices, world::Quad* quads) const;
    // Writes every slot (layout.total of each).
    void write_all(const SlotLayout& layout, float* vertices, world::Quad* quads) const;
    void clear() { m_slots = {}; }
    bool empty() const { return m_slots.empty(); }

private:
    struct Slot {
        world::Quad quad;       // Quad{} when unused.
        uint8_t point[3] = {};  // Unused: the point its degenerate triangles sit on (0..32).
        bool live = false;
    };
    static void write(const Slot& slot, float* v, world::Quad* q);

    std::vector<Slot> m_slots;
};

} // namespace vx::render
