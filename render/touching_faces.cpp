#include "render/touching_faces.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "shaders/shared/render_types.h"

namespace vx::render {
namespace {

constexpr int kN = world::kChunkSize;

// The transparent kinds of a chunk: `kind[id]` is 1 + the kind's index, 0 for opaque ids (and ids
// past the end).
struct SeeThrough {
    std::vector<uint16_t> kind;
    uint32_t kinds = 0;
    uint32_t operator[](world::BlockId id) const { return id < kind.size() ? kind[id] : 0; }
};

// One plane's transparent faces of one facing as bit rows (bit u of row v: cell (u, v)): per kind,
// then all kinds together.
struct PlaneBits {
    std::vector<uint32_t> rows; // (kinds + 1) * kN.
    uint32_t* of(uint32_t kind_index) { return rows.data() + size_t(kind_index) * kN; }
};

uint32_t row_bits(const world::Quad& q) {
    const uint32_t ones = q.width() == kN ? ~0u : (1u << q.width()) - 1u;
    return ones << q.u0();
}

// Appends to `marked` the indices within `quads` (one interior plane's) of the transparent quads
// that overlap a face of a different transparent kind of the other facing. Both faces between two
// cells lie on their shared plane, facing apart: such a pair is two touching blocks.
void mark_interior(std::span<const world::Quad> quads, const SeeThrough& see_through, PlaneBits (&by_facing)[2],
                   std::vector<uint32_t>& marked) {
    bool facing[2] = {false, false};
    for (const world::Quad& q : quads)
        facing[q.positive()] = facing[q.positive()] || see_through[q.block] != 0;
    if (!facing[0] || !facing[1])
        return;
    const uint32_t all = see_through.kinds;
    for (PlaneBits& b : by_facing)
        std::fill(b.rows.begin(), b.rows.end(), 0u);
    for (const world::Quad& q : quads)
        if (const uint32_t k = see_through[q.block]) {
            PlaneBits& b = by_facing[q.positive()];
            uint32_t *own = b.of(k - 1), *any = b.of(all);
            const uint32_t bits = row_bits(q);
            for (int v = q.v0(); v < q.v0() + q.height(); ++v) {
                own[v] |= bits;
                any[v] |= bits;
            }
        }
    for (uint32_t i = 0; i < quads.size(); ++i) {
        const world::Quad& q = quads[i];
        const uint32_t k = see_through[q.block];
        if (k == 0)
            continue;
        PlaneBits& other = by_facing[!q.positive()];
        const uint32_t *same = other.of(k - 1), *any = other.of(all);
        const uint32_t bits = row_bits(q);
        uint32_t meets = 0;
        for (int v = q.v0(); v < q.v0() + q.height(); ++v)
            meets |= any[v] & ~same[v] & bits;
        if (meets)
            marked.push_back(i);
    }
}

// Chunk-local cells of a border slice's transparent quads, by block (BorderFaces).
std::vector<world::BlockId> border_cells(std::span<const world::Quad> quads, const SeeThrough& see_through) {
    std::vector<world::BlockId> cells;
    for (const world::Quad& q : quads) {
        if (see_through[q.block] == 0)
            continue;
        if (cells.empty())
            cells.assign(size_t(kN) * kN, world::kAir);
        for (int v = q.v0(); v < q.v0() + q.height(); ++v)
            std::fill_n(cells.begin() + (v * kN + q.u0()), q.width(), q.block);
    }
    return cells;
}

} // namespace

TouchingFaces mark_touching_faces(const world::ChunkMesh& mesh, std::span<const world::BlockId> ids,
                                  const world::BlockRegistry& registry, world::ChunkMesh& out) {
    TouchingFaces result;
    const auto transparent = [&](world::BlockId id) { return id != world::kAir && !registry.is_opaque(id); };
    const size_t kinds = size_t(std::count_if(ids.begin(), ids.end(), transparent));
    if (kinds == 0)
        return result;
    SeeThrough see_through{std::vector<uint16_t>(size_t(*std::max_element(ids.begin(), ids.end())) + 1, 0)};
    for (world::BlockId id : ids)
        if (transparent(id) && see_through.kind[id] == 0)
            see_through.kind[id] = uint16_t(++see_through.kinds);
    PlaneBits by_facing[2];
    for (PlaneBits& b : by_facing)
        b.rows.resize((size_t(see_through.kinds) + 1) * kN);
    std::vector<std::pair<int, std::vector<uint32_t>>> slices; // Marked quads, by slice.
    std::vector<uint32_t> marked;
    for (int axis = 0; axis < 3; ++axis)
        for (int plane = 0; plane <= kN; ++plane) {
            const int s = world::slice_index(axis, plane);
            const std::span<const world::Quad> quads = mesh.slice(s);
            marked.clear();
            if (plane == 0 || plane == kN) {
                for (uint32_t i = 0; i < quads.size(); ++i)
                    if (see_through[quads[i].block] != 0)
                        marked.push_back(i);
                result.border[size_t(axis * 2 + (plane == kN))] = border_cells(quads, see_through);
            } else if (kinds >= 2) {
                mark_interior(quads, see_through, by_facing, marked);
                result.inside = result.inside || !marked.empty();
            }
            if (!marked.empty())
                slices.emplace_back(s, marked);
        }
    if (slices.empty())
        return result;
    result.marked = true;
    out = mesh;
    std::vector<world::Quad> quads;
    for (const auto& [s, indices] : slices) {
        const std::span<const world::Quad> slice = out.slice(s);
        quads.assign(slice.begin(), slice.end());
        for (uint32_t i : indices)
            quads[i].reserved = uint16_t(quads[i].reserved | gpu::kQuadMayTouch);
        out.replace_slice(s, quads); // The same count: in place.
    }
    return result;
}

} // namespace vx::render
