#include "world/chunk.h"

#include <algorithm>
#include <unordered_map>

namespace vx::world {

Chunk::Chunk(const Chunk& other) : m_uniform(other.m_uniform) {
    if (other.m_palette)
        m_palette = std::make_unique<ChunkPalette>(*other.m_palette);
}

Chunk& Chunk::operator=(const Chunk& other) {
    if (this != &other)
        *this = Chunk(other);
    return *this;
}

Chunk Chunk::from_dense(std::span<const BlockId> ids) {
    VX_ASSERT(ids.size() == size_t(kChunkVolume));
    const BlockId first = ids[0];
    size_t i0 = 1;
    while (i0 < ids.size() && ids[i0] == first)
        ++i0;
    if (i0 == ids.size())
        return Chunk(first);
    auto pal = std::make_unique<ChunkPalette>();
    // Palette indices, found by a short linear search (chunks rarely hold more than a dozen ids);
    // a hash map takes over past 32 entries.
    std::vector<uint16_t> local(kChunkVolume);
    std::unordered_map<BlockId, uint16_t> big;
    BlockId last_id = first;
    uint16_t last_entry = 0;
    size_t run_start = 0;
    pal->ids.push_back(first);
    pal->counts.push_back(0);
    for (size_t i = 0; i < ids.size(); ++i) {
        const BlockId id = ids[i];
        if (id != last_id) {
            // Counts are added per run: a per-block increment is a chain of dependent
            // read-modify-writes on one counter, which cost more than the whole palette search.
            pal->counts[last_entry] += uint16_t(i - run_start);
            run_start = i;
            last_id = id;
            const size_t n = pal->ids.size();
            size_t e = 0;
            if (n <= 32) {
                while (e < n && pal->ids[e] != id)
                    ++e;
            } else {
                auto it = big.find(id);
                e = it == big.end() ? n : it->second;
            }
            if (e == n) {
                pal->ids.push_back(id);
                pal->counts.push_back(0);
                if (n == 32)
                    for (size_t k = 0; k < pal->ids.size(); ++k)
                        big.emplace(pal->ids[k], uint16_t(k));
                else if (n > 32)
                    big.emplace(id, uint16_t(e));
            }
            last_entry = uint16_t(e);
        }
        local[i] = last_entry;
    }
    pal->counts[last_entry] += uint16_t(ids.size() - run_start);
    pal->indices = PackedArray(kChunkVolume, bits_for_count(uint32_t(pal->ids.size())));
    pal->indices.set_all(local.data());
    Chunk c;
    c.m_palette = std::move(pal);
    return c;
}

Chunk Chunk::from_palette(ChunkPalette palette) {
    VX_ASSERT(palette.ids.size() >= 2 && palette.ids.size() == palette.counts.size());
    VX_ASSERT(palette.indices.size() == uint32_t(kChunkVolume));
    VX_ASSERT(size_t(1) << palette.indices.bits() >= palette.ids.size());
    Chunk c;
    c.m_palette = std::make_unique<ChunkPalette>(std::move(palette));
    return c;
}

void Chunk::to_dense(std::span<BlockId> out) const {
    VX_ASSERT(out.size() == size_t(kChunkVolume));
    if (!m_palette) {
        std::fill(out.begin(), out.end(), m_uniform);
        return;
    }
    for (int i = 0; i < kChunkVolume; ++i)
        out[i] = m_palette->ids[m_palette->indices.get(uint32_t(i))];
}

uint32_t Chunk::find_or_add_entry(BlockId id) {
    ChunkPalette& p = *m_palette;
    uint32_t free_entry = UINT32_MAX;
    for (uint32_t e = 0; e < p.ids.size(); ++e) {
        if (p.ids[e] == id)
            return e; // Reuse the entry even if it fell to 0 uses: no duplicate ids.
        if (p.counts[e] == 0 && free_entry == UINT32_MAX)
            free_entry = e;
    }
    if (free_entry != UINT32_MAX) {
        p.ids[free_entry] = id;
        return free_entry;
    }
    const uint32_t e = uint32_t(p.ids.size());
    p.ids.push_back(id);
    p.counts.push_back(0);
    if (p.ids.size() > (size_t(1) << p.indices.bits()))
        p.indices = p.indices.resized(p.indices.bits() + 1);
    return e;
}

BlockId Chunk::set(int index, BlockId id) {
    VX_DEBUG_ASSERT(index >= 0 && index < kChunkVolume);
    if (!m_palette) {
        if (id == m_uniform)
            return id;
        auto pal = std::make_unique<ChunkPalette>();
        pal->ids = {m_uniform, id};
        pal->counts = {uint16_t(kChunkVolume - 1), 1};
        pal->indices = PackedArray(kChunkVolume, 1);
        pal->indices.set(uint32_t(index), 1);
        const BlockId old = m_uniform;
        m_palette = std::move(pal);
        return old;
    }
    ChunkPalette& p = *m_palette;
    const uint32_t old_entry = p.indices.get(uint32_t(index));
    const BlockId old = p.ids[old_entry];
    if (old == id)
        return old;
    --p.counts[old_entry];
    const uint32_t e = find_or_add_entry(id);
    ChunkPalette& q = *m_palette; // find_or_add_entry may have widened the indices.
    q.indices.set(uint32_t(index), e);
    if (++q.counts[e] == kChunkVolume) {
        m_palette.reset();
        m_uniform = id;
    }
    return old;
}

void Chunk::fill(BlockId id) {
    m_palette.reset();
    m_uniform = id;
}

void Chunk::compact() {
    if (!m_palette)
        return;
    ChunkPalette& p = *m_palette;
    std::vector<uint32_t> remap(p.ids.size(), UINT32_MAX);
    ChunkPalette out;
    for (uint32_t e = 0; e < p.ids.size(); ++e) {
        if (p.counts[e] == 0)
            continue;
        remap[e] = uint32_t(out.ids.size());
        out.ids.push_back(p.ids[e]);
        out.counts.push_back(p.counts[e]);
    }
    if (out.ids.size() == 1) {
        fill(out.ids[0]);
        return;
    }
    const uint32_t bits = bits_for_count(uint32_t(out.ids.size()));
    if (out.ids.size() == p.ids.size() && bits == p.indices.bits())
        return;
    out.indices = PackedArray(kChunkVolume, bits);
    for (uint32_t i = 0; i < uint32_t(kChunkVolume); ++i)
        out.indices.set(i, remap[p.indices.get(i)]);
    *m_palette = std::move(out);
}

uint32_t Chunk::distinct_ids() const {
    if (!m_palette)
        return 1;
    uint32_t n = 0;
    for (uint16_t c : m_palette->counts)
        n += c > 0;
    return n;
}

size_t Chunk::memory_bytes() const {
    size_t bytes = sizeof(Chunk);
    if (m_palette) {
        const ChunkPalette& p = *m_palette;
        bytes += sizeof(ChunkPalette) + p.ids.capacity() * sizeof(BlockId) +
                 p.counts.capacity() * sizeof(uint16_t) + p.indices.memory_bytes();
    }
    return bytes;
}

bool operator==(const Chunk& a, const Chunk& b) {
    if (a.is_uniform() && b.is_uniform())
        return a.m_uniform == b.m_uniform;
    for (int i = 0; i < kChunkVolume; ++i)
        if (a.get(i) != b.get(i))
            return false;
    return true;
}

} // namespace vx::world
