// PgStore's concurrent writers of one world: both edits kept, stale copies merged, no deadlocks.
#include <algorithm>
#include <atomic>
#include <barrier>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "pg_store_test_util.h"
#include "pg_test_util.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"

using namespace vx::world;
using vx::world::test::open_pg;
using vx::world::test::versioned_chunk;

// A write if absent (pregeneration's) commits where nothing or a tombstone is stored, and is
// dropped where another process stored a chunk after this one looked (theirs kept); a plain write
// of the same coordinate queued after it is unconditional.
TEST(PgStore, AWriteIfAbsentKeepsAnotherProcesssChunk) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    auto mine = open_pg(uri);
    auto other = open_pg(uri);
    // x = 0: the other stores it after our check; 1: the other erased it (a tombstone); 2: never
    // stored; 3: the other stores it, and our plain write follows our write if absent.
    ASSERT_TRUE(other->save({1, 0, 0}, Chunk(4)).ok());
    ASSERT_TRUE(other->flush().ok());
    ASSERT_TRUE(other->erase({1, 0, 0}).ok());
    ASSERT_TRUE(other->flush().ok());
    for (int x = 0; x < 4; ++x)
        EXPECT_FALSE(*mine->contains({x, 0, 0}));
    ASSERT_TRUE(other->save({0, 0, 0}, Chunk(9)).ok());
    ASSERT_TRUE(other->save({3, 0, 0}, Chunk(9)).ok());
    ASSERT_TRUE(other->flush().ok());
    const Chunk terrain(5);
    for (int x = 0; x < 4; ++x) {
        ChunkWrite w{{x, 0, 0}, &terrain};
        w.if_absent = true;
        ASSERT_TRUE(mine->save(std::span<const ChunkWrite>(&w, 1)).ok());
    }
    ASSERT_TRUE(mine->save({3, 0, 0}, Chunk(6)).ok());
    vx::Status s = mine->flush();
    ASSERT_TRUE(s.ok()) << s.error();
    EXPECT_EQ(mine->pending_edits(), 0u);
    auto check = open_pg(uri);
    const BlockId want[4] = {9, 5, 5, 6};
    for (int x = 0; x < 4; ++x)
        EXPECT_TRUE(*check->load({x, 0, 0})->chunk == Chunk(want[x])) << "x = " << x;
}

TEST(PgStore, TwoWritersOfOneChunkBothKeepTheirEdits) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const ChunkCoord c{4, -1, 7};
    {
        auto seed = open_pg(uri);
        ASSERT_TRUE(seed->save(c, versioned_chunk(c, 1)).ok());
        ASSERT_TRUE(seed->flush().ok());
    }
    auto a = open_pg(uri), b = open_pg(uri);
    Chunk ca = *a->load(c)->chunk, cb = *b->load(c)->chunk;
    EXPECT_EQ(a->known_version(c), 1u);
    // Different blocks of the same chunk, edited by each writer from the same version.
    const BlockEdit ea[] = {{{3, 20, 3}, 9}, {{4, 20, 3}, 9}};
    const BlockEdit eb[] = {{{10, 25, 30}, 11}};
    for (const BlockEdit& e : ea)
        ca.set(e.pos, e.id);
    for (const BlockEdit& e : eb)
        cb.set(e.pos, e.id);
    const ChunkWrite wa{c, &ca, ea}, wb{c, &cb, eb};
    ASSERT_TRUE(a->save(std::span(&wa, 1)).ok());
    ASSERT_TRUE(b->save(std::span(&wb, 1)).ok());
    ASSERT_TRUE(a->flush().ok());
    ASSERT_TRUE(b->flush().ok()); // Finds version 2 (a's), re-applies its edit on top.
    EXPECT_EQ(b->health().conflicts, 1u);
    EXPECT_EQ(a->health().conflicts, 0u);
    std::vector<ChunkCoord> merged;
    b->poll_changes(merged); // b's in-memory copy lacks a's edits: it is told to reload.
    EXPECT_NE(std::find(merged.begin(), merged.end(), c), merged.end());

    auto check = open_pg(uri);
    const Chunk stored = *check->load(c)->chunk;
    EXPECT_EQ(check->known_version(c), 3u);
    EXPECT_EQ(stored.get(LocalPos(3, 20, 3)), 9);
    EXPECT_EQ(stored.get(LocalPos(4, 20, 3)), 9);
    EXPECT_EQ(stored.get(LocalPos(10, 25, 30)), 11);
    Chunk want = versioned_chunk(c, 1);
    want.set(LocalPos(3, 20, 3), 9);
    want.set(LocalPos(4, 20, 3), 9);
    want.set(LocalPos(10, 25, 30), 11);
    EXPECT_TRUE(stored == want); // Nothing else changed.
}

// A load whose result the caller does not apply (an engine's reload still on its way to the main
// thread while a save of the older copy is queued) must not make that older copy current: the save
// names the version its copy was loaded as (ChunkWrite::base_version), so it merges with b's edit
// instead of writing over it. The store once took the version of its last load, and b's edit was
// gone (found in review). A copy saved twice, never told the version its first save made, is this
// process's own lineage: no conflict.
TEST(PgStore, AStaleCopyMergesEvenAfterALoadOfANewerVersion) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    const ChunkCoord c{-3, 2, 5};
    {
        auto seed = open_pg(uri);
        ASSERT_TRUE(seed->save(c, versioned_chunk(c, 1)).ok());
        ASSERT_TRUE(seed->flush().ok());
    }
    auto a = open_pg(uri), b = open_pg(uri);
    vx::Result<ChunkLoad> la = a->load(c), lb = b->load(c);
    ASSERT_TRUE(la && lb);
    ASSERT_EQ(la->version, 1u);
    Chunk ca = *la->chunk, cb = *lb->chunk;
    const BlockEdit eb[] = {{{10, 25, 30}, 11}};
    cb.set(eb[0].pos, eb[0].id);
    ChunkWrite wb{c, &cb, eb};
    wb.base_version = lb->version;
    ASSERT_TRUE(b->save(std::span(&wb, 1)).ok());
    ASSERT_TRUE(b->flush().ok()); // Version 2: b's edit.
    vx::Result<ChunkLoad> unapplied = a->load(c); // Read, never applied to `ca`.
    ASSERT_TRUE(unapplied);
    EXPECT_EQ(unapplied->version, 2u);
    const BlockEdit ea[] = {{{3, 20, 3}, 9}};
    ca.set(ea[0].pos, ea[0].id);
    ChunkWrite wa{c, &ca, ea};
    wa.base_version = la->version; // 1: what `ca` is.
    ASSERT_TRUE(a->save(std::span(&wa, 1)).ok());
    ASSERT_TRUE(a->flush().ok());
    EXPECT_EQ(a->health().conflicts, 1u);
    auto check = open_pg(uri);
    Chunk want = versioned_chunk(c, 1);
    want.set(eb[0].pos, eb[0].id);
    want.set(ea[0].pos, ea[0].id);
    EXPECT_TRUE(*check->load(c)->chunk == want) << "both edits";

    // b saves its copy (version 2 plus its edit) twice more, never learning what its saves made.
    const BlockEdit eb2[] = {{{11, 25, 30}, 12}};
    cb = *check->load(c)->chunk; // Version 3 (a's merge); b applies it, as an engine's reload does.
    const uint64_t v3 = check->load(c)->version;
    cb.set(eb2[0].pos, eb2[0].id);
    ChunkWrite wb2{c, &cb, eb2};
    wb2.base_version = v3;
    ASSERT_TRUE(b->save(std::span(&wb2, 1)).ok());
    ASSERT_TRUE(b->flush().ok());
    const BlockEdit eb3[] = {{{12, 25, 30}, 13}};
    cb.set(eb3[0].pos, eb3[0].id);
    ChunkWrite wb3{c, &cb, eb3};
    wb3.base_version = v3; // Still what b loaded: its lineage maps it to its own last write.
    ASSERT_TRUE(b->save(std::span(&wb3, 1)).ok());
    ASSERT_TRUE(b->flush().ok());
    EXPECT_EQ(b->health().conflicts, 0u);
    want.set(eb2[0].pos, eb2[0].id);
    want.set(eb3[0].pos, eb3[0].id);
    auto last = open_pg(uri);
    EXPECT_TRUE(*last->load(c)->chunk == want) << "every edit of both";
}

TEST(PgStore, ForgottenVersionsCostAConflictButLoseNothing) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    PgStoreCreateInfo info;
    info.uri = uri;
    info.max_known_versions = 4; // Forget down to 2 once 5 are known.
    auto opened = PgStore::open(info);
    ASSERT_TRUE(opened.ok()) << opened.error();
    PgStore& store = **opened;
    std::vector<ChunkCoord> coords;
    for (int i = 0; i < 12; ++i)
        coords.push_back({i, 0, -i});
    for (ChunkCoord c : coords)
        ASSERT_TRUE(store.save(c, versioned_chunk(c, 1)).ok());
    ASSERT_TRUE(store.flush().ok());
    size_t known = 0;
    for (ChunkCoord c : coords)
        known += store.known_version(c) != 0;
    EXPECT_LE(known, 4u); // Bounded, not one entry per chunk ever seen.

    // Edit every chunk from a fresh load; some versions get forgotten again on the way.
    for (ChunkCoord c : coords) {
        Chunk chunk = *store.load(c)->chunk;
        const BlockEdit e{{1, 2, 3}, 7};
        chunk.set(e.pos, e.id);
        const ChunkWrite w{c, &chunk, std::span(&e, 1)};
        ASSERT_TRUE(store.save(std::span(&w, 1)).ok());
    }
    ASSERT_TRUE(store.flush().ok());
    auto check = open_pg(uri);
    for (ChunkCoord c : coords) {
        Chunk want = versioned_chunk(c, 1);
        want.set(LocalPos(1, 2, 3), 7);
        EXPECT_TRUE(*check->load(c)->chunk == want) << c.x;
    }
}

// Two writers commit overlapping batches at the same time, each in its own order: writer A's
// queue has grown large before (so its hash table iterates in another order than B's), and they
// insert the shared chunks in opposite orders. Upserts sent in coordinate order lock rows in the
// same order in both transactions, so neither waits for a row the other holds while holding one
// it wants: no deadlock (which the server would break by aborting one: a failed flush here).
TEST(PgStore, OverlappingWritersNeverDeadlock) {
    VX_NEED_PG();
    const std::string uri = cluster->new_database();
    constexpr int kShared = 64, kRounds = 12;
    std::unique_ptr<PgStore> w[2] = {open_pg(uri), open_pg(uri)};
    std::vector<ChunkWrite> warm; // 4,096 uniform chunks: A's table grows (and keeps) its buckets.
    const Chunk stone(3);
    for (int i = 0; i < 4096; ++i)
        warm.push_back({ChunkCoord(i, -50, 0), &stone});
    ASSERT_TRUE(w[0]->save(warm).ok());
    ASSERT_TRUE(w[0]->flush().ok());
    std::vector<ChunkCoord> shared;
    for (int i = 0; i < kShared; ++i)
        shared.push_back({i % 8, 0, i / 8});
    std::barrier sync(2);
    std::atomic<int> failures{0};
    auto write = [&](int who) {
        for (int round = 0; round < kRounds; ++round) {
            // Each round edits what the store reads now, as the engine's copy would be after
            // reloading the chunks another process changed (a stale copy would overwrite them).
            std::vector<Chunk> copies;
            for (ChunkCoord c : shared) {
                auto got = w[who]->load(c);
                copies.push_back(got && got->chunk ? *got->chunk : Chunk(kAir));
            }
            std::vector<BlockEdit> edits(kShared);
            std::vector<ChunkWrite> batch;
            for (int k = 0; k < kShared; ++k) {
                const int i = who == 0 ? k : kShared - 1 - k; // Opposite orders.
                edits[size_t(i)] = {LocalPos(who, round, 0), BlockId(10 + round)};
                copies[size_t(i)].set(edits[size_t(i)].pos, edits[size_t(i)].id);
                batch.push_back({shared[size_t(i)], &copies[size_t(i)], std::span(&edits[size_t(i)], 1)});
            }
            sync.arrive_and_wait(); // Both commit at once.
            if (!w[who]->save(batch) || !w[who]->flush())
                failures.fetch_add(1);
        }
    };
    std::thread a(write, 0), b(write, 1);
    a.join();
    b.join();
    EXPECT_EQ(failures.load(), 0);
    // Every edit of both writers is stored (the conflicts merged them).
    auto check = open_pg(uri);
    for (ChunkCoord c : shared) {
        const Chunk got = *check->load(c)->chunk;
        for (int round = 0; round < kRounds; ++round)
            for (int who = 0; who < 2; ++who)
                ASSERT_EQ(got.get(LocalPos(who, round, 0)), BlockId(10 + round)) << c.x << "," << c.z;
    }
}
