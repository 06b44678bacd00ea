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

// Writes the quad's four corners; returns corner 2.
static glm::vec3 write_quad(const world::Quad& q, float* v) {
    glm::ivec3 c[4];
    world::quad_corners(q, c);
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k)
            v[i * 3 + k] = float(c[i][k]);
    return glm::vec3(c[2]);
}

// A vertex of the first quad of the mesh (the anchor of spares before any real quad).
static glm::vec3 first_vertex(const world::ChunkMesh& mesh) {
    for (int s = 0; s < world::kSliceCount; ++s)
        if (!mesh.slice(s).empty()) {
            glm::ivec3 c[4];
            world::quad_corners(mesh.slice(s)[0], c);
            return glm::vec3(c[0]);
        }
    return glm::vec3(0.f);
}

void fill_slots(const SlotLayout& layout, const world::ChunkMesh& mesh, float* vertices, world::Quad* quads) {
    VX_ASSERT(layout.fits(mesh));
    // Spares collapse onto the last real vertex before them in slot order: builders that split by
    // primitive order (lavapipe) would otherwise stretch node bounds out to wherever spares sit
    // (measured: spares at the chunk origin traced 3x slower).
    glm::vec3 anchor = first_vertex(mesh);
    for (int s = 0; s < world::kSliceCount; ++s) {
        const std::span<const world::Quad> quads_of = mesh.slice(s);
        float* v = vertices + size_t(layout.start[s]) * 12;
        world::Quad* q = quads + layout.start[s];
        for (const world::Quad& quad : quads_of) {
            anchor = write_quad(quad, v);
            *q++ = quad;
            v += 12;
        }
        for (size_t k = quads_of.size(); k < layout.capacity[s]; ++k) {
            for (int i = 0; i < 4; ++i)
                v[i * 3 + 0] = anchor.x, v[i * 3 + 1] = anchor.y, v[i * 3 + 2] = anchor.z;
            *q++ = world::Quad{};
            v += 12;
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
