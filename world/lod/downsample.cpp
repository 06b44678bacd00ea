#include "world/lod/downsample.h"

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include "world/base/assert.h"
#include "world/lod/cell_vote.h"
#include "world/mesh/index_unpack.h"

namespace vx::world {

namespace {

constexpr int kHalf = kChunkSize / 2; // Cells per octant edge.

// Palette entry kinds, from the registry once per child.
enum : uint8_t { kKindAir = 0, kKindOpaque = 1, kKindClear = 2 };

// Cells of one octant from the unpacked palette indices `idx` of the child.
template <class Index>
void vote_octant(const Index* idx, const uint8_t* kind, const std::vector<BlockId>& ids, LocalPos base, BlockId* out) {
    for (int z = 0; z < kHalf; ++z)
        for (int y = 0; y < kHalf; ++y) {
            BlockId* row = out + local_index(base.x, base.y + y, base.z + z);
            // The 4 rows of sub-cells under this row of cells: lower and upper, at 2z and 2z + 1.
            const Index* lo0 = idx + local_index(0, 2 * y, 2 * z);
            const Index* hi0 = lo0 + kChunkSize;
            const Index* lo1 = lo0 + kChunkSize * kChunkSize;
            const Index* hi1 = lo1 + kChunkSize;
            // The topmost non-air sub-cell of a sub-column (its lower one, air or not, when the
            // upper is air).
            auto top = [&](const Index* lo, const Index* hi, int x) {
                return uint16_t(kind[hi[x]] == kKindAir ? lo[x] : hi[x]);
            };
            for (int x = 0; x < kHalf; ++x) {
                const uint16_t t[4] = {top(lo0, hi0, 2 * x), top(lo0, hi0, 2 * x + 1), top(lo1, hi1, 2 * x),
                                       top(lo1, hi1, 2 * x + 1)};
                if (t[0] == t[1] && t[0] == t[2] && t[0] == t[3]) {
                    row[x] = ids[t[0]]; // Unanimous (air too): inside the ground, the sky, flat ground.
                    continue;
                }
                CellVote ballot;
                for (uint16_t v : t)
                    ballot.add(ids[v], kind[v] == kKindOpaque); // Air abstains.
                row[x] = ballot.winner();
            }
        }
}

} // namespace

void downsample_octant(const Chunk& child, int octant, std::span<BlockId> out, const BlockRegistry& registry) {
    VX_ASSERT(octant >= 0 && octant < kLodChildren && out.size() == size_t(kChunkVolume));
    const LocalPos base = LocalPos(octant & 1, (octant >> 1) & 1, octant >> 2) * kHalf;
    const ChunkPalette* pal = child.palette();
    if (!pal) {
        // Uniform: every sub-column votes for the one id (or the cell is all air).
        for (int z = 0; z < kHalf; ++z)
            for (int y = 0; y < kHalf; ++y)
                std::fill_n(out.begin() + local_index(base.x, base.y + y, base.z + z), kHalf, child.uniform_id());
        return;
    }
    std::vector<uint8_t> kind(pal->ids.size());
    for (size_t e = 0; e < kind.size(); ++e) {
        const BlockId id = pal->ids[e];
        kind[e] = id == kAir ? kKindAir : registry.is_opaque(id) ? kKindOpaque : kKindClear;
    }
    // Palette indices unpacked once, a byte each when they fit (most chunks hold < 256 ids).
    if (pal->indices.bits() <= 8) {
        auto idx = std::make_unique<uint8_t[]>(kChunkVolume);
        mesher_detail::unpack_rows8(pal->indices, 0, kChunkSize * kChunkSize, idx.get());
        vote_octant(idx.get(), kind.data(), pal->ids, base, out.data());
    } else {
        auto idx = std::make_unique<uint16_t[]>(kChunkVolume);
        mesher_detail::unpack_rows16(pal->indices, 0, kChunkSize * kChunkSize, idx.get());
        vote_octant(idx.get(), kind.data(), pal->ids, base, out.data());
    }
}

Chunk downsample(std::span<const Chunk* const, kLodChildren> children, const BlockRegistry& registry) {
    for (const Chunk* c : children)
        VX_ASSERT(c != nullptr);
    const bool same_uniform = std::all_of(children.begin(), children.end(), [&](const Chunk* c) {
        return c->is_uniform() && c->uniform_id() == children[0]->uniform_id();
    });
    if (same_uniform)
        return Chunk(children[0]->uniform_id());
    std::vector<BlockId> dense(kChunkVolume);
    for (int i = 0; i < kLodChildren; ++i)
        downsample_octant(*children[size_t(i)], i, dense, registry);
    return Chunk::from_dense(dense);
}

bool refresh_octant(Chunk& parent, const Chunk& child, int octant, const BlockRegistry& registry) {
    VX_ASSERT(octant >= 0 && octant < kLodChildren);
    std::vector<BlockId> before(kChunkVolume);
    parent.to_dense(before);
    std::vector<BlockId> after = before;
    downsample_octant(child, octant, after, registry);
    if (after == before)
        return false;
    parent = Chunk::from_dense(after);
    return true;
}

namespace {

// Level 0 from try_generate(); a coarser level from generate_coarse() when `direct` and the
// generator offers it, else from its 8 children built the same way, depth first.
Result<Chunk> build(const ChunkGenerator& gen, LodCoord c, bool direct, const BlockRegistry& registry) {
    VX_ASSERT(valid_lod_level(c.level));
    if (c.level == 0)
        return gen.try_generate(c.chunk);
    Chunk out;
    if (direct && gen.generate_coarse(c, out))
        return out;
    std::array<Chunk, kLodChildren> kids;
    std::array<const Chunk*, kLodChildren> ptrs;
    for (int i = 0; i < kLodChildren; ++i) {
        Result<Chunk> r = build(gen, lod_child(c, i), direct, registry);
        if (!r)
            return Error{r.error()};
        kids[size_t(i)] = std::move(*r);
        ptrs[size_t(i)] = &kids[size_t(i)];
    }
    return downsample(ptrs, registry);
}

} // namespace

Result<Chunk> downsample_generated(const ChunkGenerator& gen, LodCoord c, const BlockRegistry& registry) {
    return build(gen, c, false, registry);
}

Result<Chunk> generate_lod(const ChunkGenerator& gen, LodCoord c, const BlockRegistry& registry) {
    return build(gen, c, true, registry);
}

} // namespace vx::world
