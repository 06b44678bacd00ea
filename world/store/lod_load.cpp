#include "world/store/lod_load.h"

#include <array>
#include <string>
#include <vector>

#include "world/lod/downsample.h"

namespace vx::world {

namespace {

Error failed(LodCoord c, const std::string& why) {
    return Error{"level-" + std::to_string(c.level) + " chunk (" + std::to_string(c.chunk.x) + ", " +
                 std::to_string(c.chunk.y) + ", " + std::to_string(c.chunk.z) + "): " + why};
}

Result<Chunk> level0(ChunkStore& store, const ChunkGenerator& gen, ChunkCoord c) {
    Result<ChunkLoad> r = store.load(c);
    if (!r)
        return failed({0, c}, r.error());
    if (r->state == LoadState::Present)
        return std::move(*r->chunk);
    Result<Chunk> g = gen.try_generate(c); // Absent, or corrupt and moved aside.
    if (!g)
        return failed({0, c}, g.error());
    return g;
}

} // namespace

Result<Chunk> load_or_derive_lod(ChunkStore& store, const ChunkGenerator& gen, LodCoord c,
                                 const LodDirtySet& dirty, LodDerived* derived, const LodOverlay* overlay,
                                 const BlockRegistry& registry) {
    VX_ASSERT_RETURN(valid_lod_level(c.level), failed(c, "level out of range"));
    if (c.level == 0) {
        if (overlay)
            if (auto it = overlay->find(c.chunk); it != overlay->end())
                return it->second;
        return level0(store, gen, c.chunk);
    }
    const bool stale = dirty.contains(c);
    bool corrupt = false;
    if (!stale) {
        Result<ChunkLoad> r = store.load_lod(c);
        if (!r)
            return failed(c, r.error());
        if (r->state == LoadState::Present)
            return std::move(*r->chunk);
        corrupt = r->state == LoadState::Corrupt;
        if (!corrupt) {
            Result<Chunk> g = generate_lod(gen, c, registry);
            if (!g)
                return failed(c, g.error());
            return g;
        }
    }
    // Dirty or corrupt: from the 8 children, each by the same rule.
    std::array<Chunk, kLodChildren> kids;
    std::array<const Chunk*, kLodChildren> ptrs;
    for (int i = 0; i < kLodChildren; ++i) {
        Result<Chunk> k = load_or_derive_lod(store, gen, lod_child(c, i), dirty, derived, overlay, registry);
        if (!k)
            return Error{k.error()}; // Already names the child.
        kids[size_t(i)] = std::move(*k);
        ptrs[size_t(i)] = &kids[size_t(i)];
    }
    Chunk out = downsample(ptrs, registry);
    if (derived)
        derived->emplace_back(c, out);
    return out;
}

Status save_derived(ChunkStore& store, const LodDerived& derived) {
    std::vector<LodWrite> batch;
    batch.reserve(derived.size());
    for (const auto& [c, chunk] : derived)
        batch.push_back({c, &chunk});
    return store.save_lod(batch);
}

} // namespace vx::world
