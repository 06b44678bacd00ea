// Coarse levels of detail in the stores (ChunkStore::load_lod / save_lod / dirty marks): the
// backend-independent tests join the StoreSuite (instantiated in store_suite_test.cpp); the
// SQLite-specific ones (worlds made before coarse levels, a locked database) follow.
#include <random>
#include <thread>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "store_backend.h"
#include "test_util.h"
#include "world/store/store_open.h"

using namespace vx::world;
using vx::world::test::StoreOptions;
using vx::world::test::StoreSuite;
using vx::world::test::TempDir;
using vx::world::test::versioned_chunk;

namespace {

void expect_lod(ChunkStore& store, LodCoord c, const Chunk& want) {
    vx::Result<ChunkLoad> r = store.load_lod(c);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->state, LoadState::Present) << "level " << c.level << ": " << r->problem;
    EXPECT_TRUE(*r->chunk == want) << "level " << c.level;
}

LoadState lod_state(ChunkStore& store, LodCoord c) {
    vx::Result<ChunkLoad> r = store.load_lod(c);
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? r->state : LoadState::Corrupt;
}

bool sorted_equal(std::vector<LodCoord> a, std::vector<LodCoord> b) {
    auto key = [](const LodCoord& c) { return std::tuple(c.level, c.chunk.x, c.chunk.y, c.chunk.z); };
    auto less = [&](const LodCoord& x, const LodCoord& y) { return key(x) < key(y); };
    std::sort(a.begin(), a.end(), less);
    std::sort(b.begin(), b.end(), less);
    return a == b;
}

std::vector<LodCoord> dirty(ChunkStore& store) {
    vx::Result<std::vector<LodCoord>> r = store.list_lod_dirty();
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? *r : std::vector<LodCoord>{};
}

#define SKIP_WITHOUT_LOD(store)                                                                                       \
    if (!(store)->supports_lod())                                                                                     \
    GTEST_SKIP() << GetParam() << " keeps no coarse levels"

} // namespace

TEST_P(StoreSuite, CoarseLevelsRoundTripAndSurviveReopen) {
    const std::string world = backend().new_world();
    std::mt19937 rng(7);
    // The same chunk coordinates at several levels hold different chunks; negative and extreme
    // coordinates; level 10 is the highest.
    std::vector<std::pair<LodCoord, Chunk>> lods;
    for (int level : {1, 2, 3, 10})
        for (ChunkCoord c : {ChunkCoord(0, 0, 0), ChunkCoord(-1, -3, 5), ChunkCoord(7, -2, -9)})
            lods.emplace_back(LodCoord{level, c}, test::random_chunk(rng, 0.4, 2 + level));
    lods.emplace_back(LodCoord{4, ChunkCoord(INT32_MIN, INT32_MAX, -1)}, Chunk(9));
    const Chunk level0 = versioned_chunk({0, 0, 0}, 1);
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        SKIP_WITHOUT_LOD(store);
        std::vector<LodWrite> batch;
        for (auto& [c, chunk] : lods)
            batch.push_back({c, &chunk});
        ASSERT_TRUE(store->save_lod(batch).ok());
        ASSERT_TRUE(store->save({0, 0, 0}, level0).ok());
        EXPECT_EQ(store->pending_edits(), lods.size() * 2 + 1); // Each save also clears a dirty mark.
        for (auto& [c, chunk] : lods) // Queued coarse chunks read back before any commit.
            expect_lod(*store, c, chunk);
        ASSERT_TRUE(store->flush().ok());
        EXPECT_EQ(store->pending_edits(), 0u);
        // Level 0 is not a coarse level; 11 is past the highest: refused, nothing queued.
        const Chunk one(1);
        EXPECT_FALSE(store->save_lod({0, {0, 0, 0}}, one).ok());
        EXPECT_FALSE(store->save_lod({kMaxLodLevel + 1, {0, 0, 0}}, one).ok());
        EXPECT_FALSE(store->load_lod({0, {0, 0, 0}}).ok());
        EXPECT_EQ(store->pending_edits(), 0u);
    }
    auto store = backend().open(world);
    ASSERT_TRUE(store);
    for (auto& [c, chunk] : lods)
        expect_lod(*store, c, chunk);
    EXPECT_EQ(lod_state(*store, {5, {0, 0, 0}}), LoadState::Absent);
    EXPECT_EQ(lod_state(*store, {1, {0, 0, 1}}), LoadState::Absent);
    // Level 0 is untouched by the coarse levels and the other way round.
    EXPECT_EQ(*store->count(), 1u);
    vx::Result<ChunkLoad> l0 = store->load({0, 0, 0});
    ASSERT_TRUE(l0.ok());
    EXPECT_TRUE(l0->state == LoadState::Present && *l0->chunk == level0);
    vx::Result<StoreCheck> check = check_world(world);
    ASSERT_TRUE(check.ok()) << check.error();
    EXPECT_EQ(check->records, lods.size() + 1);
    EXPECT_EQ(check->corrupt, 0u);

    // Erase one coarse chunk; overwrite another: the last write wins, after reopening too.
    const Chunk other(11);
    const LodWrite writes[] = {{lods[0].first, nullptr}, {lods[1].first, &other}};
    ASSERT_TRUE(store->save_lod(writes).ok());
    EXPECT_EQ(lod_state(*store, lods[0].first), LoadState::Absent);
    ASSERT_TRUE(store->flush().ok());
    store.reset(); // One writer per file: the first closes before the second opens.
    store = backend().open(world);
    EXPECT_EQ(lod_state(*store, lods[0].first), LoadState::Absent);
    expect_lod(*store, lods[1].first, other);
    expect_lod(*store, lods[2].first, lods[2].second);
}

TEST_P(StoreSuite, CoarseRecordOfAnotherLevelIsQuarantined) {
    const std::string world = backend().new_world();
    const ChunkCoord c(1, -2, 3);
    const Chunk a = versioned_chunk(c, 2), b = versioned_chunk(c, 3), d = versioned_chunk({4, 4, 4}, 4);
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        SKIP_WITHOUT_LOD(store);
        ASSERT_TRUE(store->save_lod({2, c}, a).ok());
        ASSERT_TRUE(store->save_lod({3, c}, b).ok());
        ASSERT_TRUE(store->save_lod({1, {4, 4, 4}}, d).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    // The level-2 record filed under level 3 (same coordinates: only the level's checksum seed
    // tells them apart); one payload bit flipped in the level-1 record.
    backend().write_raw_lod(world, {3, c}, [&] {
        std::vector<uint8_t> r;
        RecordCodec().encode_lod({2, c}, a, r);
        return r;
    }());
    std::vector<uint8_t> flipped;
    RecordCodec().encode_lod({1, {4, 4, 4}}, d, flipped);
    flipped[flipped.size() / 2] ^= 0x04;
    backend().write_raw_lod(world, {1, {4, 4, 4}}, flipped);

    vx::Result<StoreCheck> before = check_world(world);
    ASSERT_TRUE(before.ok()) << before.error();
    EXPECT_EQ(before->records, 3u);
    EXPECT_EQ(before->corrupt, 2u);
    {
        auto store = backend().open(world);
        vx::Result<ChunkLoad> r = store->load_lod({3, c});
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(r->state, LoadState::Corrupt);
        EXPECT_NE(r->problem.find("another level"), std::string::npos) << r->problem;
        EXPECT_EQ(lod_state(*store, {1, {4, 4, 4}}), LoadState::Corrupt);
        expect_lod(*store, {2, c}, a);
        // Moved aside: absent now, so it can be derived again and saved.
        EXPECT_EQ(lod_state(*store, {3, c}), LoadState::Absent);
        ASSERT_TRUE(store->save_lod({3, c}, b).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    vx::Result<StoreCheck> after = check_world(world);
    ASSERT_TRUE(after.ok());
    EXPECT_EQ(after->records, 2u); // Level 2 kept, level 3 saved again; level 1 waits to be derived.
    EXPECT_EQ(after->corrupt, 0u);
    EXPECT_EQ(backend().quarantine_count(world), 2u);
}

TEST_P(StoreSuite, ReadOnlyStoreReportsCorruptCoarseRecordWithoutMovingIt) {
    const std::string world = backend().new_world();
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        SKIP_WITHOUT_LOD(store);
        ASSERT_TRUE(store->save_lod({2, {0, 1, 0}}, Chunk(3)).ok());
    }
    backend().write_raw_lod(world, {2, {0, 1, 0}}, {0x01, 0x02});
    StoreOptions o;
    o.read_only = true;
    auto store = backend().open(world, o);
    ASSERT_TRUE(store);
    EXPECT_EQ(lod_state(*store, {2, {0, 1, 0}}), LoadState::Corrupt);
    EXPECT_EQ(lod_state(*store, {2, {0, 1, 0}}), LoadState::Corrupt);
    EXPECT_FALSE(store->save_lod({2, {0, 1, 0}}, Chunk(3)).ok());
    const LodCoord mark{1, {0, 0, 0}};
    EXPECT_FALSE(store->mark_lod_dirty(std::span(&mark, 1)).ok());
    EXPECT_EQ(backend().quarantine_count(world), 0u);
}

TEST_P(StoreSuite, DirtyMarksSurviveReopenAndAreClearedBySaving) {
    const std::string world = backend().new_world();
    const LodCoord p1{1, {0, 0, -1}}, p2{2, {0, 0, -1}}, p3{3, {-1, 0, -1}};
    {
        auto store = backend().open(world);
        ASSERT_TRUE(store);
        SKIP_WITHOUT_LOD(store);
        EXPECT_TRUE(dirty(*store).empty());
        // A level-0 edit and the marks on its ancestors, committed together.
        ASSERT_TRUE(store->save({0, 0, -1}, versioned_chunk({0, 0, -1}, 1)).ok());
        const LodCoord marks[] = {p1, p2, p3};
        ASSERT_TRUE(store->mark_lod_dirty(marks).ok());
        EXPECT_TRUE(sorted_equal(dirty(*store), {p1, p2, p3})); // Queued marks count.
        ASSERT_TRUE(store->flush().ok());
    }
    {
        auto store = backend().open(world);
        EXPECT_TRUE(sorted_equal(dirty(*store), {p1, p2, p3}));
        // Saving a marked coarse chunk clears its mark; marking a saved one sets it again.
        ASSERT_TRUE(store->save_lod(p1, Chunk(1)).ok());
        ASSERT_TRUE(store->save_lod(p3, Chunk(1)).ok());
        ASSERT_TRUE(store->mark_lod_dirty(std::span(&p3, 1)).ok());
        ASSERT_TRUE(store->save_lod(p2, Chunk(1)).ok());
        EXPECT_TRUE(sorted_equal(dirty(*store), {p3}));
    } // Closed without flush: the destructor commits.
    StoreOptions o;
    o.read_only = true;
    auto store = backend().open(world, o);
    EXPECT_TRUE(sorted_equal(dirty(*store), {p3}));
}

// ---- SQLite-specific ----

namespace {

std::unique_ptr<SqliteStore> open_sqlite(const std::string& path, bool read_only = false) {
    SqliteStoreCreateInfo info;
    info.path = path;
    info.read_only = read_only;
    vx::Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
    EXPECT_TRUE(s.ok()) << s.error();
    return s.ok() ? std::move(*s) : nullptr;
}

// Tables named lod_* in the file.
int lod_tables(const std::string& path) {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, "SELECT count(*) FROM sqlite_schema WHERE name LIKE 'lod\\_%' ESCAPE '\\'", -1,
                                 &st, nullptr),
              SQLITE_OK);
    EXPECT_EQ(sqlite3_step(st), SQLITE_ROW);
    const int n = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(db);
    return n;
}

void raw_exec(const std::string& path, const char* sql) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* msg = nullptr;
    EXPECT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, &msg), SQLITE_OK) << (msg ? msg : "");
    sqlite3_free(msg);
    sqlite3_close(db);
}

} // namespace

TEST(SqliteStoreLod, WorldWithoutCoarseTablesOpensReadOnlyAndReadWrite) {
    TempDir dir;
    const std::string path = dir.file("old.db");
    const Chunk c0 = versioned_chunk({1, 2, 3}, 5);
    {
        auto store = open_sqlite(path);
        ASSERT_TRUE(store->save({1, 2, 3}, c0).ok());
        ASSERT_TRUE(store->save_lod({1, {0, 1, 1}}, Chunk(2)).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    EXPECT_EQ(lod_tables(path), 3);
    // A world of a build before coarse levels: the same file without the lod_* tables.
    raw_exec(path, "DROP TABLE lod_chunks; DROP TABLE lod_dirty; DROP TABLE lod_quarantine;");
    {
        auto store = open_sqlite(path, /*read_only=*/true);
        ASSERT_TRUE(store);
        EXPECT_EQ(lod_state(*store, {1, {0, 1, 1}}), LoadState::Absent);
        EXPECT_TRUE(dirty(*store).empty());
        EXPECT_EQ(*store->quarantine_count(), 0u);
        EXPECT_TRUE(store->list_lod_coords()->empty());
        vx::Result<ChunkLoad> r = store->load({1, 2, 3});
        ASSERT_TRUE(r.ok() && r->state == LoadState::Present);
        EXPECT_TRUE(*r->chunk == c0);
    }
    vx::Result<StoreCheck> check = check_store(path);
    ASSERT_TRUE(check.ok()) << check.error();
    EXPECT_EQ(check->records, 1u);
    {
        auto store = open_sqlite(path);
        ASSERT_TRUE(store);
        EXPECT_EQ(lod_state(*store, {1, {0, 1, 1}}), LoadState::Absent);
        ASSERT_TRUE(store->save({1, 2, 4}, c0).ok()); // Level-0 commits leave the schema alone.
        ASSERT_TRUE(store->flush().ok());
        EXPECT_EQ(lod_tables(path), 0);
        ASSERT_TRUE(store->save_lod({2, {0, 0, 0}}, Chunk(4)).ok()); // The first coarse commit adds them.
        ASSERT_TRUE(store->flush().ok());
        EXPECT_EQ(lod_tables(path), 3);
    }
    auto store = open_sqlite(path, /*read_only=*/true);
    expect_lod(*store, {2, {0, 0, 0}}, Chunk(4));
    EXPECT_EQ(*store->count(), 2u);
}

TEST(SqliteStoreLod, FailedCommitOfCoarseChunksKeepsTheQueue) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    ASSERT_TRUE(store->save({0, 0, 0}, Chunk(1)).ok());
    ASSERT_TRUE(store->flush().ok());
    const LodCoord c{1, {0, 0, 0}}, mark{2, {0, 0, 0}};
    ASSERT_TRUE(store->save_lod(c, Chunk(6)).ok());
    ASSERT_TRUE(store->mark_lod_dirty(std::span(&mark, 1)).ok());
    // Another connection holds the write lock: the first flush fails creating the coarse tables,
    // the second (tables made, another coarse chunk queued) beginning its transaction, each after
    // the busy timeout (2 s). Nothing queued is lost.
    const LodCoord c2{3, {0, 0, 0}};
    for (int round = 0; round < 2; ++round) {
        if (round == 1) {
            ASSERT_TRUE(store->flush().ok());
            ASSERT_TRUE(store->save_lod(c2, Chunk(7)).ok());
        }
        sqlite3* other = nullptr;
        ASSERT_EQ(sqlite3_open(path.c_str(), &other), SQLITE_OK);
        ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
        vx::Status s = store->flush();
        ASSERT_FALSE(s.ok());
        EXPECT_NE(s.error().find("locked"), std::string::npos) << s.error();
        EXPECT_EQ(store->pending_edits(), round == 0 ? 3u : 2u); // Coarse chunk, its cleared mark (and a mark).
        expect_lod(*store, round == 0 ? c : c2, Chunk(round == 0 ? 6 : 7)); // Read back from the queue.
        sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
        sqlite3_close(other);
    }
    ASSERT_TRUE(store->flush().ok());
    store = open_sqlite(path, /*read_only=*/true);
    expect_lod(*store, c, Chunk(6));
    expect_lod(*store, c2, Chunk(7));
    EXPECT_TRUE(sorted_equal(dirty(*store), {mark}));
}
