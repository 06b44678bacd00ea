#include "render/touching_faces.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "shaders/shared/render_types.h"

namespace vx::render {
namespace {

constexpr int kN = world::kChunkSize;
using PlaneIds = std::array<world::BlockId, kN * kN>; // A transparent block per cell (kAir: none).

// Which block ids are transparent, indexed by id (ids past the end: opaque).
struct SeeThrough {
    std::vector<bool> ids;
    bool operator[](world::BlockId id) const { return id < ids.size() && ids[id]; }
};

// Writes `q`'s cells into `ids`.
void fill(PlaneIds& ids, const world::Quad& q) {
    for (int v = q.v0(); v < q.v0() + q.height(); ++v)
        std::fill_n(ids.begin() + v * kN + q.u0(), q.width(), q.block);
}

// True when a cell of `q` holds, in `other`, a transparent block other than q's own.
bool meets_another(const PlaneIds& other, const world::Quad& q) {
    for (int v = q.v0(); v < q.v0() + q.height(); ++v)
        for (int u = q.u0(); u < q.u0() + q.width(); ++u) {
            const world::BlockId id = other[size_t(v * kN + u)];
            if (id != world::kAir && id != q.block)
                return true;
        }
    return false;
}

// Appends to `marked` the indices within `quads` (one interior plane's) of the transparent quads
// that overlap a different transparent block's face of the other facing. Both faces between two
// cells lie on their shared plane, facing apart: such a pair is two touching blocks.
void mark_interior(std::span<const world::Quad> quads, const SeeThrough& see_through, PlaneIds (&by_facing)[2],
                   std::vector<uint32_t>& marked) {
    bool facing[2] = {false, false};
    for (const world::Quad& q : quads)
        facing[q.positive()] = facing[q.positive()] || see_through[q.block];
    if (!facing[0] || !facing[1])
        return;
    for (PlaneIds& ids : by_facing)
        ids.fill(world::kAir);
    for (const world::Quad& q : quads)
        if (see_through[q.block])
            fill(by_facing[q.positive()], q);
    for (uint32_t i = 0; i < quads.size(); ++i)
        if (see_through[quads[i].block] && meets_another(by_facing[!quads[i].positive()], quads[i]))
            marked.push_back(i);
}

} // namespace

bool mark_touching_faces(const world::ChunkMesh& mesh, std::span<const world::BlockId> ids,
                         const world::BlockRegistry& registry, world::ChunkMesh& out) {
    const auto transparent = [&](world::BlockId id) { return id != world::kAir && !registry.is_opaque(id); };
    const size_t kinds = size_t(std::count_if(ids.begin(), ids.end(), transparent));
    if (kinds == 0)
        return false;
    SeeThrough see_through{std::vector<bool>(size_t(*std::max_element(ids.begin(), ids.end())) + 1, false)};
    for (world::BlockId id : ids)
        see_through.ids[id] = transparent(id);
    PlaneIds by_facing[2];
    std::vector<std::pair<int, std::vector<uint32_t>>> slices; // Marked quads, by slice.
    std::vector<uint32_t> marked;
    for (int axis = 0; axis < 3; ++axis)
        for (int plane = 0; plane <= kN; ++plane) {
            const int s = world::slice_index(axis, plane);
            const std::span<const world::Quad> quads = mesh.slice(s);
            marked.clear();
            if (plane == 0 || plane == kN) {
                for (uint32_t i = 0; i < quads.size(); ++i)
                    if (see_through[quads[i].block])
                        marked.push_back(i);
            } else if (kinds >= 2) {
                mark_interior(quads, see_through, by_facing, marked);
            }
            if (!marked.empty())
                slices.emplace_back(s, marked);
        }
    if (slices.empty())
        return false;
    out = mesh;
    std::vector<world::Quad> quads;
    for (const auto& [s, indices] : slices) {
        const std::span<const world::Quad> slice = out.slice(s);
        quads.assign(slice.begin(), slice.end());
        for (uint32_t i : indices)
            quads[i].reserved = uint16_t(quads[i].reserved | gpu::kQuadMayTouch);
        out.replace_slice(s, quads); // The same count: in place.
    }
    return true;
}

} // namespace vx::render
