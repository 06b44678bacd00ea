#include "world/world.h"

#include <algorithm>

namespace vx::world {

BlockId World::get_block(BlockPos p) const {
    if (!in_world(p)) // Beyond the edge is air (chunk_of would wrap to the far side).
        return kAir;
    const Chunk* c = find_chunk(chunk_of(p));
    return c ? c->get(local_of(p)) : kAir;
}

BlockId World::set_block(BlockPos p, BlockId id) {
    VX_ASSERT(in_world(p));
    const ChunkCoord cc = chunk_of(p);
    if (id == kAir) {
        Chunk* c = find_chunk(cc);
        return c ? c->set(local_of(p), id) : kAir;
    }
    return chunk(cc).set(local_of(p), id);
}

const Chunk* World::find_chunk(ChunkCoord c) const {
    auto it = m_chunks.find(c);
    return it == m_chunks.end() ? nullptr : &it->second;
}

Chunk* World::find_chunk(ChunkCoord c) {
    auto it = m_chunks.find(c);
    return it == m_chunks.end() ? nullptr : &it->second;
}

Chunk& World::chunk(ChunkCoord c) { return m_chunks[c]; }

void World::put_chunk(ChunkCoord c, Chunk chunk) { m_chunks[c] = std::move(chunk); }

bool World::remove_chunk(ChunkCoord c) { return m_chunks.erase(c) > 0; }

bool World::chunk_bounds(ChunkCoord& lo, ChunkCoord& hi) const {
    if (m_chunks.empty())
        return false;
    lo = ChunkCoord(INT32_MAX);
    hi = ChunkCoord(INT32_MIN);
    for (const auto& [c, chunk] : m_chunks) {
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    return true;
}

} // namespace vx::world
