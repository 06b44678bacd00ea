#include "render/edit_marks.h"

#include <limits>

namespace vx::render {

namespace {

EditMarks::Box united(const EditMarks::Box& a, const EditMarks::Box& b) {
    return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)};
}

// Blocks in the box (as a double: world boxes may be far apart).
double volume(const EditMarks::Box& b) {
    return (double(b.hi.x - b.lo.x) + 1.0) * (double(b.hi.y - b.lo.y) + 1.0) * (double(b.hi.z - b.lo.z) + 1.0);
}

bool contains(const EditMarks::Box& outer, const EditMarks::Box& inner) {
    return glm::all(glm::lessThanEqual(outer.lo, inner.lo)) && glm::all(glm::lessThanEqual(inner.hi, outer.hi));
}

} // namespace

void EditMarks::add(world::BlockPos lo, world::BlockPos hi) {
    const Box box{lo, hi};
    for (const Box& b : m_boxes)
        if (contains(b, box))
            return; // A block edited twice, or inside a merged region.
    m_boxes.push_back(box);
    if (m_boxes.size() <= gpu::kMaxEditBoxes)
        return;
    // Merge the pair whose union adds the fewest blocks.
    size_t best_i = 0, best_j = 1;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < m_boxes.size(); ++i)
        for (size_t j = i + 1; j < m_boxes.size(); ++j) {
            const double grow = volume(united(m_boxes[i], m_boxes[j])) - volume(m_boxes[i]) - volume(m_boxes[j]);
            if (grow < best) {
                best = grow;
                best_i = i;
                best_j = j;
            }
        }
    m_boxes[best_i] = united(m_boxes[best_i], m_boxes[best_j]);
    m_boxes.erase(m_boxes.begin() + std::ptrdiff_t(best_j));
}

void EditMarks::write(gpu::FrameParams& p, world::BlockPos origin) const {
    p.edits = glm::uvec4(uint32_t(m_boxes.size()), 0u, 0u, 0u);
    for (size_t i = 0; i < m_boxes.size(); ++i) {
        // 64-bit differences, then float: the box's faces (hi + 1: a block's far side).
        const world::BlockPos lo = m_boxes[i].lo - origin, hi = m_boxes[i].hi - origin;
        const float reach = float(kEditReach);
        p.edit_boxes[2 * i] = glm::vec4(float(lo.x) - reach, float(lo.y) - reach, float(lo.z) - reach, 0.f);
        p.edit_boxes[2 * i + 1] =
            glm::vec4(float(hi.x + 1) + reach, float(hi.y + 1) + reach, float(hi.z + 1) + reach, 0.f);
    }
}

} // namespace vx::render
