#include "render/slot_map.h"

#include <algorithm>
#include <limits>

#include "world/base/assert.h"

namespace vx::render {
namespace {

uint64_t key(const world::Quad& q) { return uint64_t(q.packed) << 32 | uint64_t(q.block) << 16 | q.reserved; }

// Corner 2: the vertex fill_slots() anchors the spares after a quad on.
glm::ivec3 corner2(const world::Quad& q) {
    glm::ivec3 c[4];
    world::quad_corners(q, c);
    return c[2];
}

void set_point(uint8_t (&p)[3], glm::ivec3 v) {
    for (int k = 0; k < 3; ++k)
        p[k] = uint8_t(v[k]);
}

int distance2(const uint8_t (&p)[3], glm::ivec3 v) {
    int d = 0;
    for (int k = 0; k < 3; ++k)
        d += (int(p[k]) - v[k]) * (int(p[k]) - v[k]);
    return d;
}

// Matching a new quad to the nearest free slot costs free x new; past this many new quads (a
// slice rewritten wholesale, where locality is lost anyway) they fill free slots in order.
constexpr size_t kNearestSearchLimit = 64;

} // namespace

void SlotMap::assign(const SlotLayout& layout, const world::ChunkMesh& mesh) {
    m_slots.assign(layout.total, Slot{});
    glm::ivec3 anchor(0);
    for (int s = 0; s < world::kSliceCount; ++s)
        if (!mesh.slice(s).empty()) {
            glm::ivec3 c[4];
            world::quad_corners(mesh.slice(s)[0], c);
            anchor = c[0];
            break;
        }
    for (int s = 0; s < world::kSliceCount; ++s) {
        const std::span<const world::Quad> quads = mesh.slice(s);
        VX_ASSERT(quads.size() <= layout.capacity[s]);
        Slot* slot = m_slots.data() + layout.start[s];
        for (uint32_t k = 0; k < layout.capacity[s]; ++k, ++slot) {
            if (k < quads.size()) {
                slot->quad = quads[k];
                slot->live = true;
                anchor = corner2(quads[k]);
            } else {
                set_point(slot->point, anchor);
            }
        }
    }
}

void SlotMap::update_slice(const SlotLayout& layout, const world::ChunkMesh& mesh, int s) {
    VX_ASSERT(m_slots.size() == layout.total && s >= 0 && s < world::kSliceCount);
    const std::span<const world::Quad> quads = mesh.slice(s);
    VX_ASSERT(quads.size() <= layout.capacity[s]);
    // The new quads by key; `placed` marks those already in a slot.
    std::vector<std::pair<uint64_t, uint32_t>> wanted(quads.size());
    for (uint32_t i = 0; i < quads.size(); ++i)
        wanted[i] = {key(quads[i]), i};
    std::sort(wanted.begin(), wanted.end());
    std::vector<bool> placed(quads.size(), false);
    Slot* const first = m_slots.data() + layout.start[s];
    std::vector<Slot*> free_slots;
    for (Slot* slot = first; slot != first + layout.capacity[s]; ++slot) {
        if (slot->live) {
            const uint64_t k = key(slot->quad);
            const auto it = std::lower_bound(wanted.begin(), wanted.end(), std::pair<uint64_t, uint32_t>{k, 0});
            if (it != wanted.end() && it->first == k && !placed[it->second]) {
                placed[it->second] = true;
                continue; // Unchanged: stays in its slot.
            }
            set_point(slot->point, corner2(slot->quad)); // Removed: a point inside its old box.
            slot->quad = world::Quad{};
            slot->live = false;
        }
        free_slots.push_back(slot);
    }
    std::vector<uint32_t> fresh;
    for (uint32_t i = 0; i < quads.size(); ++i)
        if (!placed[i])
            fresh.push_back(i);
    VX_ASSERT(fresh.size() <= free_slots.size());
    const bool nearest = fresh.size() <= kNearestSearchLimit;
    size_t next = 0;
    for (uint32_t i : fresh) {
        size_t pick = next;
        if (nearest) {
            const glm::ivec3 at = corner2(quads[i]);
            int best = std::numeric_limits<int>::max();
            for (size_t f = 0; f < free_slots.size(); ++f)
                if (free_slots[f] && distance2(free_slots[f]->point, at) < best) {
                    best = distance2(free_slots[f]->point, at);
                    pick = f;
                }
        } else {
            while (!free_slots[pick])
                ++pick;
            next = pick + 1;
        }
        free_slots[pick]->quad = quads[i];
        free_slots[pick]->live = true;
        free_slots[pick] = nullptr;
    }
}

void SlotMap::write(const Slot& slot, float* v, world::Quad* q) {
    if (slot.live) {
        glm::ivec3 c[4];
        world::quad_corners(slot.quad, c);
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k)
                v[i * 3 + k] = float(c[i][k]);
    } else {
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k)
                v[i * 3 + k] = float(slot.point[k]);
    }
    *q = slot.quad;
}

void SlotMap::write_slice(const SlotLayout& layout, int s, float* vertices, world::Quad* quads) const {
    VX_ASSERT(m_slots.size() == layout.total);
    const Slot* slot = m_slots.data() + layout.start[s];
    for (uint32_t k = 0; k < layout.capacity[s]; ++k)
        write(slot[k], vertices + size_t(k) * 12, quads + k);
}

void SlotMap::write_all(const SlotLayout& layout, float* vertices, world::Quad* quads) const {
    VX_ASSERT(m_slots.size() == layout.total);
    for (uint32_t k = 0; k < layout.total; ++k)
        write(m_slots[k], vertices + size_t(k) * 12, quads + k);
}

} // namespace vx::render
