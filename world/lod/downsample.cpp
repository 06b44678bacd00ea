#include "world/lod/downsample.h"

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include "world/base/assert.h"
#include "world/mesh/index_unpack.h"

namespace vx::world {

namespace {

constexpr int kHalf = kChunkSize / 2; // Cells per octant edge.
constexpr uint16_t kNoVote = 0xFFFF;

// Palette indices of a non-uniform chunk, one per block in local-index order.
void unpack_indices(const ChunkPalette& pal, uint16_t* out) {
    if (pal.indices.bits() <= 8) {
        auto bytes = std::make_unique<uint8_t[]>(kChunkVolume);
        mesher_detail::unpack_rows8(pal.indices, 0, kChunkSize * kChunkSize, bytes.get());
        std::copy_n(bytes.get(), kChunkVolume, out);
    } else {
        mesher_detail::unpack_rows16(pal.indices, 0, kChunkSize * kChunkSize, out);
    }
}

// The winner among up to 4 votes (palette entries): most votes, ties to the smaller block id.
uint16_t elect(const uint16_t* votes, int n, const std::vector<BlockId>& ids) {
    uint16_t best = kNoVote;
    int best_count = 0;
    for (int i = 0; i < n; ++i) {
        int count = 0;
        for (int j = 0; j < n; ++j)
            count += votes[j] == votes[i];
        if (count > best_count || (count == best_count && ids[votes[i]] < ids[best])) {
            best = votes[i];
            best_count = count;
        }
    }
    return best;
}

} // namespace

void downsample_octant(const Chunk& child, int octant, std::span<BlockId> out) {
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
    auto idx = std::make_unique<uint16_t[]>(kChunkVolume);
    unpack_indices(*pal, idx.get());
    std::vector<uint8_t> air(pal->ids.size());
    for (size_t e = 0; e < air.size(); ++e)
        air[e] = pal->ids[e] == kAir;
    for (int z = 0; z < kHalf; ++z)
        for (int y = 0; y < kHalf; ++y) {
            BlockId* row = out.data() + local_index(base.x, base.y + y, base.z + z);
            for (int x = 0; x < kHalf; ++x) {
                uint16_t votes[4];
                int n = 0;
                for (int dz = 0; dz < 2; ++dz)
                    for (int dx = 0; dx < 2; ++dx) {
                        const uint16_t lo = idx[local_index(2 * x + dx, 2 * y, 2 * z + dz)];
                        const uint16_t hi = idx[local_index(2 * x + dx, 2 * y + 1, 2 * z + dz)];
                        // The topmost non-air sub-cell of this sub-column, if any.
                        if (!air[hi])
                            votes[n++] = hi;
                        else if (!air[lo])
                            votes[n++] = lo;
                    }
                row[x] = n == 0 ? kAir : pal->ids[elect(votes, n, pal->ids)];
            }
        }
}

Chunk downsample(std::span<const Chunk* const, kLodChildren> children) {
    for (const Chunk* c : children)
        VX_ASSERT(c != nullptr);
    const bool same_uniform = std::all_of(children.begin(), children.end(), [&](const Chunk* c) {
        return c->is_uniform() && c->uniform_id() == children[0]->uniform_id();
    });
    if (same_uniform)
        return Chunk(children[0]->uniform_id());
    std::vector<BlockId> dense(kChunkVolume);
    for (int i = 0; i < kLodChildren; ++i)
        downsample_octant(*children[size_t(i)], i, dense);
    return Chunk::from_dense(dense);
}

namespace {

// Level 0 from try_generate(); a coarser level from generate_coarse() when `direct` and the
// generator offers it, else from its 8 children built the same way, depth first.
Result<Chunk> build(const ChunkGenerator& gen, LodCoord c, bool direct) {
    VX_ASSERT(valid_lod_level(c.level));
    if (c.level == 0)
        return gen.try_generate(c.chunk);
    Chunk out;
    if (direct && gen.generate_coarse(c, out))
        return out;
    std::array<Chunk, kLodChildren> kids;
    std::array<const Chunk*, kLodChildren> ptrs;
    for (int i = 0; i < kLodChildren; ++i) {
        Result<Chunk> r = build(gen, lod_child(c, i), direct);
        if (!r)
            return Error{r.error()};
        kids[size_t(i)] = std::move(*r);
        ptrs[size_t(i)] = &kids[size_t(i)];
    }
    return downsample(ptrs);
}

} // namespace

Result<Chunk> downsample_generated(const ChunkGenerator& gen, LodCoord c) { return build(gen, c, false); }

Result<Chunk> generate_lod(const ChunkGenerator& gen, LodCoord c) { return build(gen, c, true); }

} // namespace vx::world
