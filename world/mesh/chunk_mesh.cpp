#include "world/mesh/chunk_mesh.h"

#include <algorithm>
#include <vector>

#include "world/base/assert.h"

namespace vx::world {

std::vector<BlockId> ChunkMesh::block_ids() const {
    std::vector<BlockId> ids;
    bool any = false;
    BlockId last = kAir;
    for_each_quad([&](const Quad& q) { // Slices only: their spare capacity holds stale quads.
        if (any && q.block == last)
            return; // A run of one block.
        any = true;
        last = q.block;
        if (std::find(ids.begin(), ids.end(), q.block) == ids.end())
            ids.push_back(q.block);
    });
    return ids;
}

void quad_corners(const Quad& q, glm::ivec3 out[4]) {
    const int a = q.axis(), ua = plane_u_axis(a), va = plane_v_axis(a);
    glm::ivec3 c[4];
    for (glm::ivec3& p : c)
        p[a] = q.plane();
    const int u0 = q.u0(), v0 = q.v0(), u1 = u0 + q.width(), v1 = v0 + q.height();
    c[0][ua] = u0, c[0][va] = v0;
    c[1][ua] = u1, c[1][va] = v0;
    c[2][ua] = u1, c[2][va] = v1;
    c[3][ua] = u0, c[3][va] = v1;
    // (e_u x e_v) is +X for X planes, -Y for Y planes (u = x, v = z) and +Z for Z planes.
    const bool uv_normal_positive = a != 1;
    if (uv_normal_positive == q.positive()) {
        for (int i = 0; i < 4; ++i)
            out[i] = c[i];
    } else {
        out[0] = c[0], out[1] = c[3], out[2] = c[2], out[3] = c[1];
    }
}

void ChunkMesh::clear() {
    m_quads.clear();
    m_start.fill(0);
    m_count.fill(0);
    m_capacity.fill(0);
    m_total = 0;
}

void ChunkMesh::begin(size_t expected_quads) {
    m_quads.clear();
    if (m_quads.capacity() < expected_quads)
        m_quads.reserve(expected_quads);
    m_total = 0;
}

void ChunkMesh::end() {
    // Slices were written in order; each ends where the next begins.
    uint32_t end_of = uint32_t(m_quads.size());
    for (int s = kSliceCount - 1; s >= 0; --s) {
        m_count[s] = end_of - m_start[s];
        m_capacity[s] = m_count[s];
        end_of = m_start[s];
    }
    m_total = uint32_t(m_quads.size());
}

void ChunkMesh::replace_slice(int s, std::span<const Quad> quads) {
    VX_ASSERT(s >= 0 && s < kSliceCount);
    replace_slice_range(s, 0, m_count[s], quads);
}

void ChunkMesh::replace_slice_range(int s, uint32_t first, uint32_t last, std::span<const Quad> quads) {
    VX_ASSERT(s >= 0 && s < kSliceCount && first <= last && last <= m_count[s]);
    const uint32_t k = uint32_t(quads.size()), n = m_count[s] - (last - first) + k;
    if (n > m_capacity[s])
        relayout(s, n);
    Quad* at = m_quads.data() + m_start[s];
    if (first + k < last) // The quads after `last` move left or right (overlapping ranges).
        std::copy(at + last, at + m_count[s], at + first + k);
    else if (first + k > last)
        std::copy_backward(at + last, at + m_count[s], at + m_count[s] + (first + k - last));
    std::copy(quads.begin(), quads.end(), at + first);
    m_total = m_total - m_count[s] + n;
    m_count[s] = n;
}

void ChunkMesh::relayout(int grow_slice, uint32_t grow_to) {
    // Headroom: 25% plus 8 quads per slice, so a burst of edits rarely lays out again.
    std::vector<Quad> out;
    std::array<uint32_t, kSliceCount> start{}, cap{};
    size_t total = 0;
    for (int s = 0; s < kSliceCount; ++s) {
        const uint32_t need = std::max(m_count[s], s == grow_slice ? grow_to : 0u);
        cap[s] = need + need / 4 + 8;
        total += cap[s];
    }
    out.resize(total);
    uint32_t at = 0;
    for (int s = 0; s < kSliceCount; ++s) {
        start[s] = at;
        std::copy_n(m_quads.begin() + m_start[s], m_count[s], out.begin() + at);
        at += cap[s];
    }
    m_quads = std::move(out);
    m_start = start;
    m_capacity = cap;
}

bool operator==(const ChunkMesh& a, const ChunkMesh& b) {
    if (a.m_total != b.m_total)
        return false;
    for (int s = 0; s < kSliceCount; ++s) {
        auto sa = a.slice(s), sb = b.slice(s);
        if (std::equal(sa.begin(), sa.end(), sb.begin(), sb.end()))
            continue;
        // Same quads in another order still describe the same surface.
        std::vector<Quad> qa(sa.begin(), sa.end()), qb(sb.begin(), sb.end());
        auto key = [](const Quad& q) { return (uint64_t(q.packed) << 16) | q.block; };
        auto less = [&](const Quad& x, const Quad& y) { return key(x) < key(y); };
        std::sort(qa.begin(), qa.end(), less);
        std::sort(qb.begin(), qb.end(), less);
        if (qa != qb)
            return false;
    }
    return true;
}

} // namespace vx::world
