#include "engine/sky_access.h"

#include <unordered_set>
#include <vector>

namespace vx::engine {

namespace {

enum class Cell : uint8_t { Opaque, Clear, Unknown };

Cell cell_at(const world::World& w, world::BlockPos p) {
    if (!world::in_world(p))
        return Cell::Unknown;
    const world::Chunk* c = w.find_chunk(world::chunk_of(p));
    if (!c)
        return Cell::Unknown;
    return w.registry().is_opaque(c->get(world::local_of(p))) ? Cell::Opaque : Cell::Clear;
}

// A cell near the eye as one integer (offsets within +-2^20 blocks: far more than any fill).
uint64_t key_of(world::BlockPos d) {
    constexpr int64_t kBias = int64_t(1) << 20;
    return (uint64_t(d.x + kBias) << 42) | (uint64_t(d.y + kBias) << 21) | uint64_t(d.z + kBias);
}

} // namespace

bool sky_access(const world::World& world, world::BlockPos eye, size_t max_cells) {
    // Up the column first: above ground this ends the search at once.
    for (int64_t dy = 1; dy <= kSkyColumnBlocks; ++dy) {
        const Cell c = cell_at(world, eye + world::BlockPos(0, dy, 0));
        if (c == Cell::Unknown)
            return true;
        if (c == Cell::Opaque)
            break;
        if (dy == kSkyColumnBlocks)
            return true;
    }
    // The eye's pocket (the eye's own block counts as clear: a camera inside a block still
    // looks out of it).
    // Depth first, up last so it is taken first: out from under a roof the walk climbs straight
    // to the unloaded chunks above instead of filling the loaded air around.
    static const world::BlockPos kSteps[6] = {{0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {0, 1, 0}};
    std::unordered_set<uint64_t> seen{key_of(world::BlockPos(0))};
    std::vector<world::BlockPos> todo{world::BlockPos(0)};
    while (!todo.empty()) {
        const world::BlockPos d = todo.back();
        todo.pop_back();
        for (const world::BlockPos& step : kSteps) {
            const world::BlockPos n = d + step;
            if (seen.count(key_of(n)))
                continue;
            const Cell c = cell_at(world, eye + n);
            if (c == Cell::Unknown)
                return true;
            if (c == Cell::Opaque)
                continue;
            if (seen.size() >= max_cells)
                return true;
            seen.insert(key_of(n));
            todo.push_back(n);
        }
    }
    return false;
}

bool SkyAccessCache::get(const world::World& world, world::BlockPos eye, uint64_t world_changes) {
    if (!m_valid || eye != m_eye || world_changes != m_changes) {
        m_open = sky_access(world, eye);
        m_eye = eye;
        m_changes = world_changes;
        m_valid = true;
        ++m_computations;
    }
    return m_open;
}

} // namespace vx::engine
