#include "render/chunk_geometry.h"

#include <algorithm>

#include "world/base/assert.h"

namespace vx::render {

SlotLayout SlotLayout::for_mesh(const world::ChunkMesh& mesh) {
    SlotLayout l;
    for (int s = 0; s < world::kSliceCount; ++s) {
        const uint32_t n = uint32_t(mesh.slice(s).size());
        l.start[s] = l.total;
        l.capacity[s] = n + n / 4 + 2;
        l.total += l.capacity[s];
    }
    return l;
}

bool SlotLayout::fits(const world::ChunkMesh& mesh) const {
    for (int s = 0; s < world::kSliceCount; ++s)
        if (mesh.slice(s).size() > capacity[s])
            return false;
    return true;
}

// Spare slots collapse onto a real vertex near them in slot order: builders that split by
// primitive order (lavapipe) would otherwise stretch node bounds out to wherever the spares sit
// (measured: spares at the chunk origin made tracing several times slower).
static void collapse_spares(const SlotLayout& layout, const world::ChunkMesh& mesh, SlotGeometry& out) {
    std::vector<uint8_t> used(layout.total, 0);
    for (int s = 0; s < world::kSliceCount; ++s)
        std::fill_n(used.begin() + layout.start[s], mesh.slice(s).size(), uint8_t(1));
    const float* anchor = nullptr;
    for (uint32_t k = 0; k < layout.total && !anchor; ++k)
        if (used[k])
            anchor = out.vertices.data() + size_t(k) * 12;
    if (!anchor)
        return; // No quads: all spares stay at the origin.
    for (uint32_t k = 0; k < layout.total; ++k) {
        float* v = out.vertices.data() + size_t(k) * 12;
        if (used[k]) {
            anchor = v + 6; // Corner 2 of the last real quad.
            continue;
        }
        for (int i = 0; i < 4; ++i)
            std::copy_n(anchor, 3, v + i * 3);
    }
}

void fill_slots(const SlotLayout& layout, const world::ChunkMesh& mesh, SlotGeometry& out) {
    VX_ASSERT(layout.fits(mesh));
    out.vertices.assign(size_t(layout.total) * 12, 0.f);
    out.quads.assign(layout.total, world::Quad{});
    for (int s = 0; s < world::kSliceCount; ++s) {
        uint32_t slot = layout.start[s];
        for (const world::Quad& q : mesh.slice(s)) {
            glm::ivec3 c[4];
            world::quad_corners(q, c);
            float* v = out.vertices.data() + size_t(slot) * 12;
            for (int i = 0; i < 4; ++i)
                for (int k = 0; k < 3; ++k)
                    v[i * 3 + k] = float(c[i][k]);
            out.quads[slot] = q;
            ++slot;
        }
    }
    collapse_spares(layout, mesh, out);
}

std::vector<uint32_t> slot_indices(uint32_t slots) {
    std::vector<uint32_t> idx(size_t(slots) * 6);
    for (uint32_t k = 0; k < slots; ++k) {
        const uint32_t b = 4 * k;
        const uint32_t tri[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        std::copy(tri, tri + 6, idx.begin() + ptrdiff_t(k) * 6);
    }
    return idx;
}

} // namespace vx::render
