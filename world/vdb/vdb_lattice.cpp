#include "world/vdb/vdb_lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "world/vdb/vdb_common.h"

namespace vx::vdb::detail {
namespace {

double snap(double v, double unit, double tolerance) {
    const double r = std::round(v / unit) * unit;
    return std::abs(v - r) <= tolerance ? r : v;
}

bool finite(const glm::dmat3& m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(m[c][r]))
                return false;
    return true;
}

} // namespace

Result<BlockLattice> BlockLattice::create(const glm::dmat3& index_to_world, const glm::dvec3& origin, double block_size) {
    if (!(block_size > 0) || !std::isfinite(block_size))
        return Error{"block_size " + format_length(block_size) + " is not a positive, finite length"};
    if (!finite(index_to_world) || !std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z))
        return Error{"the grid's transform holds non-finite values"};
    // Degenerate: the voxel's volume is negligible against its edges' (a flat or collapsed map).
    const double edges = glm::length(index_to_world[0]) * glm::length(index_to_world[1]) * glm::length(index_to_world[2]);
    if (!(std::abs(glm::determinant(index_to_world)) > 1e-12 * edges))
        return Error{"the grid's transform is degenerate (its voxels have no volume)"};
    const glm::dmat3 world_to_index = glm::inverse(index_to_world);
    BlockLattice l;
    l.m_g = world_to_index * block_size;
    l.m_c = -(world_to_index * origin);
    double largest = 0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            largest = std::max(largest, std::abs(l.m_g[c][r]));
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            l.m_g[c][r] = snap(l.m_g[c][r], 1.0, 1e-9 * largest);
    for (int a = 0; a < 3; ++a)
        l.m_c[a] = snap(l.m_c[a], 0.5, 1e-9 * std::max(1.0, std::abs(l.m_c[a])));
    l.m_g_inv = glm::inverse(l.m_g);
    if (!finite(l.m_g) || !finite(l.m_g_inv) || !(std::abs(glm::determinant(l.m_g)) > 0))
        return Error{"block_size " + format_length(block_size) + " is out of range for this grid's voxel size"};
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 3; ++k) {
            l.m_extent_lo[a] += std::min(0.0, l.m_g[k][a]);
            l.m_extent_hi[a] += std::max(0.0, l.m_g[k][a]);
        }
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
            for (int sz = -1; sz <= 1; sz += 2)
                l.m_half_diagonal = std::max(l.m_half_diagonal, 0.5 * glm::length(l.m_g * glm::dvec3(sx, sy, sz)));
    return l;
}

void BlockLattice::cell_bounds(const glm::i64vec3& b, glm::dvec3& min, glm::dvec3& max) const {
    const glm::dvec3 o = index_of(glm::dvec3(b));
    min = o + m_extent_lo;
    max = o + m_extent_hi;
}

void BlockLattice::blocks_meeting(const glm::dvec3& lo, const glm::dvec3& hi, glm::i64vec3& out_lo,
                                  glm::i64vec3& out_hi) const {
    glm::dvec3 bmin(std::numeric_limits<double>::infinity()), bmax(-std::numeric_limits<double>::infinity());
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 corner(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
        const glm::dvec3 b = block_of(corner);
        bmin = glm::min(bmin, b);
        bmax = glm::max(bmax, b);
    }
    // Clamped so that tiny blocks on a large grid cannot overflow int64; the caller's block count
    // limit refuses such ranges.
    const glm::dvec3 lim(std::ldexp(1.0, 61));
    out_lo = glm::i64vec3(glm::clamp(glm::floor(bmin), -lim, lim));
    out_hi = glm::i64vec3(glm::clamp(glm::floor(bmax), -lim, lim));
}

} // namespace vx::vdb::detail
