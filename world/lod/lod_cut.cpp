#include "world/lod/lod_cut.h"

#include <algorithm>
#include <cmath>

namespace vx::world {

namespace {
int ceil_half(int v) { return (v + 1) / 2; }

int64_t ceil_div(int64_t a, int64_t b) { return (a + b - 1) / b; }
} // namespace

LodView::LodView(const glm::dvec3& viewer, const LodViewSettings& settings) : m_settings(settings), m_viewer(viewer) {
    m_settings.radius0 = std::max(settings.radius0, 0);
    m_settings.vradius0 = std::max(settings.vradius0, 0);
    m_settings.ring = std::max(settings.ring, 1);
    m_settings.vertical_reach = std::max<int64_t>(settings.vertical_reach, 0);
    m_settings.view_distance = std::max<int64_t>(settings.view_distance, 0);
    m_settings.max_level = std::clamp(settings.max_level, 0, kMaxLodLevel);
    m_center0 = chunk_of(BlockPos(int64_t(std::floor(viewer.x)), int64_t(std::floor(viewer.y)),
                                  int64_t(std::floor(viewer.z))));
    m_half[0] = m_settings.radius0;
    m_half_v[0] = m_settings.vradius0;
    // The finest level whose box reaches the view distance: the viewer is in its centre chunk,
    // so the box's edge is at least half_width chunks away on every side.
    m_top = 0;
    while (m_top < m_settings.max_level && int64_t(m_half[size_t(m_top)]) * lod_chunk_blocks(m_top) <
                                               m_settings.view_distance) {
        const int k = ++m_top;
        // Nesting: each box holds the parents of the finer one (a parent index is at most
        // ceil(h / 2) from the coarser centre when the finer box is h wide).
        m_half[size_t(k)] = std::max(m_settings.ring, ceil_half(m_half[size_t(k - 1)]));
        const int reach = int(ceil_div(m_settings.vertical_reach, lod_chunk_blocks(k)));
        m_half_v[size_t(k)] = std::max(reach, ceil_half(m_half_v[size_t(k - 1)]));
    }
}

bool LodView::in_box(LodCoord c) const {
    if (c.level < 0 || c.level > m_top)
        return false;
    const glm::ivec3 d = glm::abs(glm::ivec3(c.chunk - center(c.level)));
    return std::max(d.x, d.z) <= m_half[size_t(c.level)] && d.y <= m_half_v[size_t(c.level)];
}

bool LodView::refines(LodCoord c) const {
    if (c.level < 1 || c.level > m_top)
        return false;
    // The children form a 2x2x2 block: its two extreme corners in the box put all 8 in it.
    return in_box(lod_child(c, 0)) && in_box(lod_child(c, kLodChildren - 1));
}

double LodView::distance(LodCoord c) const {
    const BlockPos o = lod_origin(c);
    const double size = double(lod_chunk_blocks(c.level));
    auto axis = [&](double v, double lo) { return std::max({lo - v, 0.0, v - (lo + size)}); };
    const double dx = axis(m_viewer.x, double(o.x)), dz = axis(m_viewer.z, double(o.z));
    return std::sqrt(dx * dx + dz * dz);
}

bool LodView::is_root(LodCoord c, double extra) const {
    return c.level == m_top && in_box(c) && distance(c) <= double(m_settings.view_distance) + extra;
}

void LodView::roots(std::vector<LodCoord>& out, double extra) const {
    const int h = m_half[size_t(m_top)], v = m_half_v[size_t(m_top)];
    const ChunkCoord c0 = center(m_top);
    for (int x = -h; x <= h; ++x)
        for (int z = -h; z <= h; ++z)
            for (int y = -v; y <= v; ++y) {
                const LodCoord c{m_top, c0 + ChunkCoord(x, y, z)};
                if (distance(c) <= double(m_settings.view_distance) + extra)
                    out.push_back(c);
            }
}

void LodView::cut_below(LodCoord c, std::vector<LodCoord>& out) const {
    if (distance(c) > double(m_settings.view_distance))
        return; // Beyond the view: nothing drawn, and no hole.
    if (!refines(c)) {
        out.push_back(c);
        return;
    }
    for (int i = 0; i < kLodChildren; ++i)
        cut_below(lod_child(c, i), out);
}

void LodView::cut(std::vector<LodCoord>& out) const {
    std::vector<LodCoord> top;
    roots(top);
    for (LodCoord r : top)
        cut_below(r, out);
}

void LodView::coarse_chunks(std::vector<LodCoord>& out, double extra) const {
    if (m_top == 0)
        return;
    std::vector<LodCoord> stack;
    roots(stack, extra);
    const double reach = double(m_settings.view_distance) + extra;
    while (!stack.empty()) {
        const LodCoord c = stack.back();
        stack.pop_back();
        out.push_back(c);
        if (c.level < 2)
            continue;
        // Every box chunk has its parent in the coarser box (nesting): descending from the roots
        // through box chunks reaches all of them.
        for (int i = 0; i < kLodChildren; ++i) {
            const LodCoord ch = lod_child(c, i);
            if (in_box(ch) && distance(ch) <= reach)
                stack.push_back(ch);
        }
    }
}

uint64_t lod_box_chunks(const LodViewSettings& settings) {
    const LodView view(glm::dvec3(0.0), settings);
    uint64_t n = 0;
    for (int k = 1; k <= view.top_level(); ++k) {
        const uint64_t w = 2 * uint64_t(view.half_width(k)) + 1, h = 2 * uint64_t(view.half_height(k)) + 1;
        n += w * w * h;
    }
    return n;
}

} // namespace vx::world
