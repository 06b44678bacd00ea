#include "render/touching_pairs.h"

#include <algorithm>
#include <utility>

#include "world/coords.h"

namespace vx::render {
namespace {

constexpr int kN = world::kChunkSize;

int opposite(int side) { return side ^ 1; }

// The plane of chunk c's side `side` along the side's axis, blocks.
int64_t side_plane(world::LodCoord c, int side) {
    return world::lod_origin(c)[side / 2] + ((side & 1) ? world::lod_chunk_blocks(c.level) : 0);
}

} // namespace

bool border_faces_meet(world::LodCoord a, const std::vector<world::BlockId>& faces_a, world::LodCoord b,
                       const std::vector<world::BlockId>& faces_b, int axis) {
    if (faces_a.empty() || faces_b.empty())
        return false;
    // Each cell of the finer grid lies in one cell of the coarser (both aligned to their cells).
    const bool a_finer = a.level <= b.level;
    const world::LodCoord fine = a_finer ? a : b, coarse = a_finer ? b : a;
    const std::vector<world::BlockId>& fine_faces = a_finer ? faces_a : faces_b;
    const std::vector<world::BlockId>& coarse_faces = a_finer ? faces_b : faces_a;
    const int ua = world::plane_u_axis(axis), va = world::plane_v_axis(axis);
    const world::BlockPos fo = world::lod_origin(fine), co = world::lod_origin(coarse);
    const int shift = coarse.level; // Blocks to coarse cells.
    for (int v = 0; v < kN; ++v) {
        const int64_t cv = (fo[va] + (int64_t(v) << fine.level) - co[va]) >> shift;
        if (cv < 0 || cv >= kN)
            continue;
        for (int u = 0; u < kN; ++u) {
            const world::BlockId f = fine_faces[size_t(v * kN + u)];
            if (f == world::kAir)
                continue;
            const int64_t cu = (fo[ua] + (int64_t(u) << fine.level) - co[ua]) >> shift;
            if (cu < 0 || cu >= kN)
                continue;
            const world::BlockId g = coarse_faces[size_t(cv * kN + cu)];
            if (g != world::kAir && g != f)
                return true;
        }
    }
    return false;
}

std::vector<world::LodCoord> TouchingPairs::across(world::LodCoord c, int side) const {
    const int axis = side / 2, other = opposite(side);
    const bool high = (side & 1) != 0;
    const int64_t plane = side_plane(c, side);
    const world::BlockPos origin = world::lod_origin(c);
    const int ua = world::plane_u_axis(axis), va = world::plane_v_axis(axis);
    std::vector<world::LodCoord> out;
    auto consider = [&](world::LodCoord d) {
        const auto it = m_chunks.find(d);
        if (it != m_chunks.end() && !it->second.border[size_t(other)].empty() && side_plane(d, other) == plane)
            out.push_back(d);
    };
    for (int level = 0; level <= world::kMaxLodLevel; ++level) {
        if (m_per_level[size_t(level)] == 0)
            continue;
        if (level >= c.level) { // One chunk holds the block across the plane at c's corner.
            world::BlockPos b = origin;
            b[axis] = high ? plane : plane - 1;
            consider(world::lod_chunk_of(b, level));
            continue;
        }
        const int64_t cells = int64_t(1) << (c.level - level); // Finer chunks per axis of c's square.
        const int64_t edge = world::lod_chunk_blocks(level);
        if (cells * cells <= 256) {
            glm::i64vec3 d;
            d[axis] = (high ? plane : plane - edge) / edge; // Exact: the plane is a multiple of edge.
            for (int64_t j = 0; j < cells; ++j)
                for (int64_t i = 0; i < cells; ++i) {
                    d[ua] = origin[ua] / edge + i;
                    d[va] = origin[va] / edge + j;
                    consider({level, world::ChunkCoord(int32_t(d.x), int32_t(d.y), int32_t(d.z))});
                }
            continue;
        }
        const int64_t span = world::lod_chunk_blocks(c.level); // Far finer levels: scan the few held.
        for (const auto& [d, entry] : m_chunks) {
            if (d.level != level || entry.border[size_t(other)].empty() || side_plane(d, other) != plane)
                continue;
            const world::BlockPos o = world::lod_origin(d);
            if (o[ua] >= origin[ua] && o[ua] < origin[ua] + span && o[va] >= origin[va] && o[va] < origin[va] + span)
                out.push_back(d);
        }
    }
    return out;
}

void TouchingPairs::link(world::LodCoord a, world::LodCoord b) {
    std::vector<world::LodCoord>& pa = m_chunks[a].partners;
    if (std::find(pa.begin(), pa.end(), b) != pa.end())
        return;
    pa.push_back(b);
    m_chunks[b].partners.push_back(a);
    ++m_pairs;
}

void TouchingPairs::set(world::LodCoord c, bool inside, BorderFaces border) {
    remove(c);
    if (!inside && std::all_of(border.begin(), border.end(), [](const auto& f) { return f.empty(); }))
        return;
    Entry& e = m_chunks[c];
    e.inside = inside;
    e.border = std::move(border);
    m_inside += inside ? 1 : 0;
    ++m_per_level[size_t(c.level)];
    for (int side = 0; side < 6; ++side) {
        if (e.border[size_t(side)].empty())
            continue;
        // `e` and the partners stay put: links add no entry.
        for (world::LodCoord d : across(c, side)) {
            const std::vector<world::BlockId>& theirs = m_chunks.at(d).border[size_t(opposite(side))];
            if (border_faces_meet(c, e.border[size_t(side)], d, theirs, side / 2))
                link(c, d);
        }
    }
}

void TouchingPairs::remove(world::LodCoord c) {
    const auto it = m_chunks.find(c);
    if (it == m_chunks.end())
        return;
    for (world::LodCoord d : it->second.partners) {
        std::vector<world::LodCoord>& pd = m_chunks[d].partners;
        pd.erase(std::find(pd.begin(), pd.end(), c));
        --m_pairs;
    }
    m_inside -= it->second.inside ? 1 : 0;
    --m_per_level[size_t(c.level)];
    m_chunks.erase(it);
}

void TouchingPairs::clear() {
    m_chunks.clear();
    m_per_level.fill(0);
    m_inside = m_pairs = 0;
}

std::vector<world::LodCoord> TouchingPairs::chunks() const {
    std::vector<world::LodCoord> out;
    out.reserve(m_chunks.size());
    for (const auto& [c, e] : m_chunks)
        out.push_back(c);
    return out;
}

} // namespace vx::render
