// Coarse chunks made stale by edits, re-derived on load (world/store/lod_load.h): the backend tests
// join the StoreSuite (SQLite and PostgreSQL, instantiated in store_suite_test.cpp); failure
// injection wraps a SQLite store.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "store_backend.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/store/lod_load.h"

using namespace vx::world;
using vx::world::test::StoreSuite;
using vx::world::test::TempDir;

namespace {

constexpr uint64_t kSeed = 11;

auto key(const LodCoord& c) { return std::tuple(c.level, c.chunk.x, c.chunk.y, c.chunk.z); }
struct LodLess {
    bool operator()(const LodCoord& a, const LodCoord& b) const { return key(a) < key(b); }
};

// The reference: coarse chunks as downsample() of level-0 blocks, generated except where edited,
// level by level (each chunk built once).
class Pyramid {
public:
    Pyramid(const TerrainGenerator& gen, const std::map<LodCoord, Chunk, LodLess>& edits)
        : m_gen(gen), m_edits(edits) {}
    const Chunk& chunk(LodCoord c) {
        if (auto it = m_chunks.find(c); it != m_chunks.end())
            return it->second;
        if (c.level == 0) {
            auto e = m_edits.find(c);
            return m_chunks.emplace(c, e != m_edits.end() ? e->second : m_gen.generate(c.chunk)).first->second;
        }
        std::array<const Chunk*, kLodChildren> kids;
        for (int i = 0; i < kLodChildren; ++i)
            kids[size_t(i)] = &chunk(lod_child(c, i));
        return m_chunks.emplace(c, downsample(kids)).first->second;
    }

private:
    const TerrainGenerator& m_gen;
    const std::map<LodCoord, Chunk, LodLess>& m_edits;
    std::map<LodCoord, Chunk, LodLess> m_chunks;
};

// Two edits at the surface near the origin: the surface chunk dug out to air, and a glass cube
// (16³, cell-aligned at every level to 3) set into the chunk above it. Both change cells at
// levels 1..3.
std::map<LodCoord, Chunk, LodLess> make_edits(const TerrainGenerator& gen) {
    const int64_t h = std::max<int64_t>(gen.surface_height(40, 40), gen.params().sea_level);
    const ChunkCoord dug = chunk_of(BlockPos(40, h, 40));
    Chunk above = gen.generate(dug + ChunkCoord(0, 1, 0));
    for (int z = 0; z < 16; ++z)
        for (int y = 16; y < 32; ++y)
            for (int x = 0; x < 16; ++x)
                above.set(x, y, z, gen.ids().glass);
    std::map<LodCoord, Chunk, LodLess> edits;
    edits.emplace(LodCoord{0, dug}, Chunk(kAir));
    edits.emplace(LodCoord{0, dug + ChunkCoord(0, 1, 0)}, std::move(above));
    return edits;
}

LodDirtySet dirty_of(ChunkStore& store) {
    vx::Result<std::vector<LodCoord>> r = store.list_lod_dirty();
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? LodDirtySet(r->begin(), r->end()) : LodDirtySet{};
}

} // namespace

// A world whose coarse levels 1..3 were stored (from its generated blocks), then edited at level 0
// with dirty marks on the edits' ancestors, reopened: the re-derived chunks are the downsampling of
// the edited blocks; saving them clears the marks, and they survive reopening.
TEST_P(StoreSuite, EditedBlocksReachCoarseLevelsOnLoad) {
    const std::string world = backend().new_world();
    const TerrainGenerator gen(kSeed);
    const auto edits = make_edits(gen);
    const std::map<LodCoord, Chunk, LodLess> none;
    Pyramid before(gen, none), after(gen, edits);
    std::set<LodCoord, LodLess> ancestors; // Of the edits, levels 1..3.
    std::set<LodCoord, LodLess> stored;    // Those and their siblings, as before the edits.
    for (const auto& [c, chunk] : edits)
        for (int k = 1; k <= 3; ++k) {
            const LodCoord a = lod_ancestor(c, k);
            ancestors.insert(a);
            stored.insert(a);
            if (k < 3)
                for (int i = 0; i < kLodChildren; ++i)
                    stored.insert(lod_child(lod_parent(a), i));
        }
    // A stored chunk nothing marks, unlike its terrain: returned as stored.
    const LodCoord elsewhere{2, ChunkCoord(-5, 0, 7)};
    const Chunk sentinel(7);
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        if (!store->supports_lod())
            GTEST_SKIP() << GetParam() << " keeps no coarse levels";
        std::vector<LodWrite> batch;
        for (const LodCoord& c : stored)
            batch.push_back({c, &before.chunk(c)});
        batch.push_back({elsewhere, &sentinel});
        ASSERT_TRUE(store->save_lod(batch).ok());
        ASSERT_TRUE(store->flush().ok());
        // The edits and the marks on their ancestors, committed together.
        for (const auto& [c, chunk] : edits)
            ASSERT_TRUE(store->save(c.chunk, chunk).ok());
        const std::vector<LodCoord> marks(ancestors.begin(), ancestors.end());
        ASSERT_TRUE(store->mark_lod_dirty(marks).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    auto store = backend().open(world);
    ASSERT_TRUE(store);
    const LodDirtySet dirty = dirty_of(*store);
    ASSERT_EQ(dirty.size(), ancestors.size());
    LodDerived derived;
    for (const LodCoord& a : ancestors) {
        ASSERT_FALSE(before.chunk(a) == after.chunk(a)) << "the edits must change level " << a.level;
        vx::Result<Chunk> r = load_or_derive_lod(*store, gen, a, dirty, &derived);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_TRUE(*r == after.chunk(a)) << "level " << a.level;
    }
    // Every marked chunk was rebuilt (the level-3 one again with the finer ones under it), children
    // before parents.
    std::set<LodCoord, LodLess> rebuilt;
    for (const auto& [c, chunk] : derived) {
        EXPECT_TRUE(ancestors.contains(c));
        EXPECT_TRUE(chunk == after.chunk(c));
        if (c.level > 1)
            for (const LodCoord& a : ancestors)
                if (a.level == c.level - 1 && lod_parent(a) == c) {
                    EXPECT_TRUE(rebuilt.contains(a)) << "a child before its parent";
                }
        rebuilt.insert(c);
    }
    EXPECT_EQ(rebuilt, ancestors);
    // A level-0 chunk in the caller's overlay (edited in memory, not saved yet) is read in place of
    // the store's.
    const LodCoord edited = edits.begin()->first;
    LodOverlay overlay;
    overlay.emplace(edited.chunk, Chunk(7));
    vx::Result<Chunk> o = load_or_derive_lod(*store, gen, lod_parent(edited), dirty, nullptr, &overlay);
    ASSERT_TRUE(o.ok()) << o.error();
    Chunk expected = after.chunk(lod_parent(edited));
    ASSERT_TRUE(refresh_octant(expected, overlay.at(edited.chunk), lod_octant(edited)));
    EXPECT_TRUE(*o == expected);
    vx::Result<Chunk> s = load_or_derive_lod(*store, gen, elsewhere, dirty);
    ASSERT_TRUE(s.ok()) << s.error();
    EXPECT_TRUE(*s == sentinel);
    // Neither stored nor marked: the generator's coarse chunk.
    const LodCoord absent{1, ChunkCoord(9, 0, 9)};
    vx::Result<Chunk> g = load_or_derive_lod(*store, gen, absent, dirty);
    ASSERT_TRUE(g.ok() && generate_lod(gen, absent).ok());
    EXPECT_TRUE(*g == *generate_lod(gen, absent));

    // The engine saves what was rebuilt: the marks clear, and a reopened world loads them stored.
    ASSERT_TRUE(save_derived(*store, derived).ok());
    ASSERT_TRUE(store->flush().ok());
    store.reset(); // One writer per file: the first closes before the second opens.
    store = backend().open(world);
    EXPECT_TRUE(dirty_of(*store).empty());
    for (const LodCoord& a : ancestors) {
        vx::Result<ChunkLoad> l = store->load_lod(a);
        ASSERT_TRUE(l.ok() && l->state == LoadState::Present) << "level " << a.level;
        EXPECT_TRUE(*l->chunk == after.chunk(a));
        LodDerived again;
        vx::Result<Chunk> r = load_or_derive_lod(*store, gen, a, {}, &again);
        ASSERT_TRUE(r.ok());
        EXPECT_TRUE(*r == after.chunk(a));
        EXPECT_TRUE(again.empty()) << "current chunks are not rebuilt";
    }
}

// A corrupt coarse record over an edit (no marks: the chunk was saved after the edit) is
// re-derived from the blocks under it, edit included, not regenerated.
TEST_P(StoreSuite, CorruptCoarseRecordIsDerivedFromTheBlocksUnderIt) {
    const std::string world = backend().new_world();
    const TerrainGenerator gen(kSeed);
    const auto edits = make_edits(gen);
    Pyramid after(gen, edits);
    const LodCoord dug = edits.begin()->first;
    const LodCoord a1 = lod_ancestor(dug, 1), a2 = lod_ancestor(dug, 2);
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        if (!store->supports_lod())
            GTEST_SKIP() << GetParam() << " keeps no coarse levels";
        for (const auto& [c, chunk] : edits)
            ASSERT_TRUE(store->save(c.chunk, chunk).ok());
        ASSERT_TRUE(store->save_lod(a1, after.chunk(a1)).ok());
        ASSERT_TRUE(store->save_lod(a2, after.chunk(a2)).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    backend().write_raw_lod(world, a1, {0x56, 0x58, 0x00, 0x01});
    backend().write_raw_lod(world, a2, {0x00});
    // a2's other children are neither stored nor marked: the generator's coarse chunks.
    std::array<Chunk, kLodChildren> kids;
    std::array<const Chunk*, kLodChildren> ptrs;
    for (int i = 0; i < kLodChildren; ++i) {
        const LodCoord k = lod_child(a2, i);
        kids[size_t(i)] = k == a1 ? after.chunk(a1) : *generate_lod(gen, k);
        ptrs[size_t(i)] = &kids[size_t(i)];
    }
    const Chunk want = downsample(ptrs);
    auto store = backend().open(world);
    LodDerived derived;
    vx::Result<Chunk> r = load_or_derive_lod(*store, gen, a2, {}, &derived);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(*r == want);
    ASSERT_EQ(derived.size(), 2u); // Both corrupt records, the finer first.
    EXPECT_TRUE(derived[0].first == a1 && derived[0].second == after.chunk(a1));
    EXPECT_TRUE(derived[1].first == a2 && derived[1].second == want);
    EXPECT_FALSE(want == *generate_lod(gen, a2)) << "regenerating would lose the edit";
    EXPECT_EQ(backend().quarantine_count(world), 2u);
}

// ---- Failures (a SQLite store behind a wrapper that fails on demand) ----

namespace {

// Passes every call to `inner`, except loads of the chosen level-0 or coarse chunk, which fail as
// a server that went away would.
class FailingLoads final : public ChunkStore {
public:
    explicit FailingLoads(std::unique_ptr<ChunkStore> inner) : m_inner(std::move(inner)) {}
    using ChunkStore::save;
    using ChunkStore::save_lod;
    std::optional<ChunkCoord> fail_load;
    std::optional<LodCoord> fail_load_lod;

    vx::Result<ChunkLoad> load(ChunkCoord c) override {
        if (fail_load && *fail_load == c)
            return vx::Error{"server closed the connection (injected)"};
        return m_inner->load(c);
    }
    vx::Result<ChunkLoad> load_lod(LodCoord c) override {
        if (fail_load_lod && *fail_load_lod == c)
            return vx::Error{"server closed the connection (injected)"};
        return m_inner->load_lod(c);
    }
    vx::Status save(std::span<const ChunkWrite> batch) override { return m_inner->save(batch); }
    vx::Status tick(Clock::time_point now) override { return m_inner->tick(now); }
    vx::Status flush() override { return m_inner->flush(); }
    vx::Result<bool> contains(ChunkCoord c) override { return m_inner->contains(c); }
    vx::Result<uint64_t> count() override { return m_inner->count(); }
    vx::Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override {
        return m_inner->for_each_coord(fn);
    }
    vx::Result<std::optional<std::string>> get_meta(std::string_view k) override { return m_inner->get_meta(k); }
    vx::Status set_meta(std::string_view k, std::string_view v) override { return m_inner->set_meta(k, v); }
    bool supports_lod() const override { return true; }
    vx::Status save_lod(std::span<const LodWrite> batch) override { return m_inner->save_lod(batch); }
    vx::Status mark_lod_dirty(std::span<const LodCoord> c) override { return m_inner->mark_lod_dirty(c); }
    vx::Result<std::vector<LodCoord>> list_lod_dirty() override { return m_inner->list_lod_dirty(); }
    bool read_only() const override { return false; }

private:
    std::unique_ptr<ChunkStore> m_inner;
};

class FailingGenerator final : public ChunkGenerator {
public:
    FailingGenerator(const TerrainGenerator& inner, ChunkCoord bad) : m_inner(inner), m_bad(bad) {}
    Chunk generate(ChunkCoord c) const override { return m_inner.generate(c); }
    vx::Result<Chunk> try_generate(ChunkCoord c) const override {
        if (c == m_bad)
            return vx::Error{"generator threw for this chunk"};
        return m_inner.generate(c);
    }
    bool generate_coarse(LodCoord c, Chunk& out) const override { return m_inner.generate_coarse(c, out); }

private:
    const TerrainGenerator& m_inner;
    ChunkCoord m_bad;
};

} // namespace

TEST(LodLoad, StoreAndGeneratorFailuresReturnErrorsNotTerrain) {
    TempDir dir;
    SqliteStoreCreateInfo info;
    info.path = dir.file("w.db");
    auto opened = SqliteStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    FailingLoads store(std::move(*opened));
    const TerrainGenerator gen(kSeed);
    const auto edits = make_edits(gen);
    const LodCoord dug = edits.begin()->first;
    const LodCoord a1 = lod_ancestor(dug, 1), a2 = lod_ancestor(dug, 2);
    ASSERT_TRUE(store.save(dug.chunk, edits.begin()->second).ok());
    ASSERT_TRUE(store.save_lod(a2, Chunk(3)).ok());
    const LodCoord marks[] = {a1, a2};
    ASSERT_TRUE(store.mark_lod_dirty(marks).ok());
    ASSERT_TRUE(store.flush().ok());
    const LodDirtySet dirty = dirty_of(store);
    ASSERT_EQ(dirty.size(), 2u);

    // A level-0 load under a dirty chunk fails: the error names that chunk, nothing is derived.
    store.fail_load = dug.chunk;
    LodDerived derived;
    vx::Result<Chunk> r = load_or_derive_lod(store, gen, a2, dirty, &derived);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("injected"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("level-0 chunk"), std::string::npos) << r.error();
    EXPECT_TRUE(derived.empty());
    store.fail_load.reset();

    // A coarse load fails: for a stored chunk, and for one that is not stored (it must not be
    // generated over: the store could not say whether it holds edits).
    const LodCoord sibling = lod_child(a2, lod_octant(a1) ^ 1);
    for (const LodCoord c : {a2, sibling}) {
        store.fail_load_lod = c;
        vx::Result<Chunk> f = load_or_derive_lod(store, gen, c, {});
        ASSERT_FALSE(f.ok()) << "level " << c.level;
        EXPECT_NE(f.error().find("injected"), std::string::npos) << f.error();
    }
    // Under a dirty parent the failing sibling fails the parent.
    store.fail_load_lod = sibling;
    EXPECT_FALSE(load_or_derive_lod(store, gen, a2, dirty).ok());
    store.fail_load_lod.reset();

    // The generator fails for a level-0 chunk under a dirty chunk.
    const ChunkCoord bad = lod_child(a1, lod_octant(dug) ^ 1).chunk;
    const FailingGenerator failing(gen, bad);
    vx::Result<Chunk> g = load_or_derive_lod(store, failing, a1, dirty);
    ASSERT_FALSE(g.ok());
    EXPECT_NE(g.error().find("generator threw"), std::string::npos) << g.error();

    // All back: the same calls succeed.
    vx::Result<Chunk> ok = load_or_derive_lod(store, gen, a2, dirty, &derived);
    ASSERT_TRUE(ok.ok()) << ok.error();
    EXPECT_EQ(derived.size(), 2u);
}
