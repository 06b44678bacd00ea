#include "world/lod/lod_raycast.h"

#include <algorithm>

namespace vx::world {

bool LodScene::add(LodCoord c, Chunk cells) {
    VX_ASSERT_RETURN(valid_lod_level(c.level), false);
    if (m_chunks.contains(c) || m_above.contains(c))
        return false;
    for (int k = c.level + 1; k <= kMaxLodLevel; ++k)
        if (m_chunks.contains(lod_ancestor(c, k)))
            return false;
    for (int k = c.level + 1; k <= kMaxLodLevel; ++k)
        m_above.insert(lod_ancestor(c, k));
    m_chunks.emplace(c, std::move(cells));
    m_max_level = std::max(m_max_level, c.level);
    return true;
}

const Chunk* LodScene::find(LodCoord c) const {
    const auto it = m_chunks.find(c);
    return it == m_chunks.end() ? nullptr : &it->second;
}

LodScene::Covering LodScene::covering(BlockPos p) const {
    for (int k = m_max_level; k >= 0; --k) {
        const LodCoord c = lod_chunk_of(p, k);
        if (const Chunk* chunk = find(c))
            return {chunk, c};
        if (!m_above.contains(c))
            return {nullptr, c}; // Nothing of the scene under c.
    }
    return {nullptr, lod_chunk_of(p, 0)}; // Not reached: a level-0 chunk is never in m_above.
}

BlockId LodScene::cell_at(BlockPos p, int* level) const {
    const Covering cov = covering(p);
    if (level)
        *level = cov.chunk ? cov.coord.level : -1;
    return cov.chunk ? cov.chunk->get(lod_local_of(p, cov.coord.level)) : kAir;
}

LodRaycastHit raycast_lod(const LodScene& scene, const Ray& ray, double max_distance) {
    // The region of the last lookup: a scene chunk's blocks, or blocks no scene chunk holds.
    LodBlockBox box{BlockPos(1), BlockPos(0)}; // Empty until the first lookup.
    LodScene::Covering cov;
    auto query = [&](BlockPos p) -> BlockId {
        if (!in_world(p)) // Beyond the edge is air (lod_chunk_of would wrap to the far side).
            return kAir;
        if (glm::any(glm::lessThan(p, box.min)) || glm::any(glm::greaterThan(p, box.max))) {
            cov = scene.covering(p);
            box = lod_block_box(cov.coord);
        }
        return cov.chunk ? cov.chunk->get(lod_local_of(p, cov.coord.level)) : kAir;
    };
    LodRaycastHit out;
    out.hit = raycast(ray, clip_to_world(ray, max_distance), query);
    if (out.hit.hit) {
        // The walk stops at the first non-air answer, so the last lookup is the hit's chunk.
        out.level = cov.coord.level;
        const int64_t mask = ~(lod_cell_size(out.level) - 1);
        out.cell = BlockPos(out.hit.block.x & mask, out.hit.block.y & mask, out.hit.block.z & mask);
    }
    return out;
}

} // namespace vx::world
