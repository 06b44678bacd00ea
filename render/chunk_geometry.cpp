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
