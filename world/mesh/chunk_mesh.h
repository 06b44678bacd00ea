#pragma once
// Meshes of a chunk as compact quads, grouped per slice.
// A slice is one boundary plane of the chunk: 33 planes per axis (plane p lies at coordinate p
// along its axis, chunk-local), 99 in all. Slice p of axis a holds the negative-facing faces of
// the blocks in layer p and the positive-facing faces of the blocks in layer p - 1.
// Plane (u, v) axes: X planes (u = y, v = z), Y planes (u = x, v = z), Z planes (u = x, v = y).
// Each slice keeps spare capacity, so replacing a slice in place stays O(slice) (the layout a
// BLAS with per-slice capacity mirrors). Not thread-safe.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "world/block_registry.h"
#include "world/coords.h"

namespace vx::world {

// One rectangle of faces: 8 bytes. Chunk-local block units.
struct Quad {
    uint32_t packed = 0; // u0:5 | v0:5 | (w-1):5 | (h-1):5 | plane:6 | axis:2 | positive:1
    BlockId block = kAir;
    uint16_t reserved = 0;

    static Quad make(int axis, int plane, bool positive, int u0, int v0, int w, int h, BlockId block) {
        Quad q;
        q.packed = uint32_t(u0) | uint32_t(v0) << 5 | uint32_t(w - 1) << 10 | uint32_t(h - 1) << 15 |
                   uint32_t(plane) << 20 | uint32_t(axis) << 26 | uint32_t(positive) << 28;
        q.block = block;
        return q;
    }
    int u0() const { return int(packed & 31); }
    int v0() const { return int((packed >> 5) & 31); }
    int width() const { return int((packed >> 10) & 31) + 1; }  // Along u, 1..32.
    int height() const { return int((packed >> 15) & 31) + 1; } // Along v, 1..32.
    int plane() const { return int((packed >> 20) & 63); }     // 0..32.
    int axis() const { return int((packed >> 26) & 3); }       // 0 = X, 1 = Y, 2 = Z.
    bool positive() const { return (packed >> 28) & 1; }       // Faces +axis.
    Face face() const { return make_face(axis(), positive()); }
    int area() const { return width() * height(); }

    friend bool operator==(const Quad& a, const Quad& b) { return a.packed == b.packed && a.block == b.block; }
};
static_assert(sizeof(Quad) == 8);

inline constexpr int slice_index(int axis, int plane) { return axis * kPlanesPerAxis + plane; }
// The u and v axes of a plane perpendicular to `axis`.
inline constexpr int plane_u_axis(int axis) { return axis == 0 ? 1 : 0; }
inline constexpr int plane_v_axis(int axis) { return axis == 2 ? 1 : 2; }

// The four corners of a quad in chunk-local block units, counter-clockwise seen from the side
// the face looks at (the air side), so (c1 - c0) x (c3 - c0) points along the face normal.
void quad_corners(const Quad& q, glm::ivec3 out[4]);

class ChunkMesh {
public:
    ChunkMesh() { clear(); }

    std::span<const Quad> slice(int s) const { return {m_quads.data() + m_start[s], m_count[s]}; }
    std::span<const Quad> slice(int axis, int plane) const { return slice(slice_index(axis, plane)); }
    uint32_t quad_count() const { return m_total; }
    uint32_t triangle_count() const { return 2 * m_total; }
    bool empty() const { return m_total == 0; }
    void clear();

    // Calls f(quad) for every quad, slice by slice.
    template <class F> void for_each_quad(F&& f) const {
        for (int s = 0; s < kSliceCount; ++s)
            for (const Quad& q : slice(s))
                f(q);
    }

    // The blocks of the quads, each once, in the order first met. Runs of one block (most quads)
    // cost a compare each; a chunk holds few blocks, so the list is searched linearly.
    std::vector<BlockId> block_ids() const;

    // Replaces one slice's quads. Fits in place when the slice's capacity allows; otherwise the
    // storage is laid out again with headroom in every slice.
    void replace_slice(int s, std::span<const Quad> quads);
    // Replaces quads [first, last) of slice s, keeping the others in order (those after last
    // move); grows like replace_slice.
    void replace_slice_range(int s, uint32_t first, uint32_t last, std::span<const Quad> quads);

    // Writing a whole mesh in slice order (used by meshers): begin, then per slice in order
    // begin_slice(s) + push(q) or append(quads)..., then end().
    void begin(size_t expected_quads);
    void begin_slice(int s) { m_start[s] = uint32_t(m_quads.size()); }
    void push(const Quad& q) { m_quads.push_back(q); }
    void append(std::span<const Quad> quads) { m_quads.insert(m_quads.end(), quads.begin(), quads.end()); }
    void end();

    // Every slice holds the same quads (in any order).
    friend bool operator==(const ChunkMesh& a, const ChunkMesh& b);

private:
    void relayout(int grow_slice, uint32_t grow_to);

    std::vector<Quad> m_quads;
    std::array<uint32_t, kSliceCount> m_start{};
    std::array<uint32_t, kSliceCount> m_count{};
    std::array<uint32_t, kSliceCount> m_capacity{};
    uint32_t m_total = 0;
};

} // namespace vx::world
