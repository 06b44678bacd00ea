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

SlotLayout SlotLayout::exact(const world::ChunkMesh& mesh) {
    SlotLayout l;
    for (int s = 0; s < world::kSliceCount; ++s) {
        l.start[s] = l.total;
        l.capacity[s] = uint32_t(mesh.slice(s).size());
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

// Writes slice s at v/q and returns the anchor after it (its last real vertex, or `anchor`).
static glm::vec3 write_slice(const SlotLayout& layout, const world::ChunkMesh& mesh, int s, glm::vec3 anchor,
                             float* v, world::Quad* q) {
    const std::span<const world::Quad> quads_of = mesh.slice(s);
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
    return anchor;
}

void fill_slots(const SlotLayout& layout, const world::ChunkMesh& mesh, float* vertices, world::Quad* quads) {
    VX_ASSERT(layout.fits(mesh));
    // Spares collapse onto the last real vertex before them in slot order: builders that split by
    // primitive order (lavapipe) would otherwise stretch node bounds out to wherever spares sit
    // (measured: spares at the chunk origin traced 3x slower).
    glm::vec3 anchor = first_vertex(mesh);
    for (int s = 0; s < world::kSliceCount; ++s)
        anchor = write_slice(layout, mesh, s, anchor, vertices + size_t(layout.start[s]) * 12, quads + layout.start[s]);
}

void fill_slice(const SlotLayout& layout, const world::ChunkMesh& mesh, int s, float* vertices, world::Quad* quads) {
    VX_ASSERT(s >= 0 && s < world::kSliceCount && mesh.slice(s).size() <= layout.capacity[s]);
    glm::vec3 anchor = first_vertex(mesh);
    for (int p = s - 1; p >= 0; --p)
        if (!mesh.slice(p).empty()) {
            glm::ivec3 c[4];
            world::quad_corners(mesh.slice(p).back(), c);
            anchor = glm::vec3(c[2]); // What write_quad returned for that quad in fill_slots.
            break;
        }
    write_slice(layout, mesh, s, anchor, vertices, quads);
}

uint64_t mesh_hash(const world::ChunkMesh& mesh) {
    // splitmix64's finaliser over (slice, count) and each quad's 8 bytes, in four chains that
    // take every fourth quad of a slice, combined at the end: the chains' multiplies overlap
    // (one chain waited on each in turn), and every chunk streamed in is hashed in update().
    auto mix = [](uint64_t h, uint64_t v) {
        uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2));
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    };
    auto key = [](const world::Quad& q) { return uint64_t(q.packed) << 32 | uint64_t(q.block) << 16 | q.reserved; };
    uint64_t h[4] = {0, 1, 2, 3};
    for (int s = 0; s < world::kSliceCount; ++s) {
        const std::span<const world::Quad> quads = mesh.slice(s);
        if (quads.empty())
            continue;
        h[0] = mix(h[0], uint64_t(s) << 32 | quads.size());
        size_t i = 0;
        for (; i + 4 <= quads.size(); i += 4)
            for (size_t k = 0; k < 4; ++k)
                h[k] = mix(h[k], key(quads[i + k]));
        for (; i < quads.size(); ++i)
            h[i & 3] = mix(h[i & 3], key(quads[i]));
    }
    return mix(mix(mix(h[0], h[1]), h[2]), h[3]);
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
