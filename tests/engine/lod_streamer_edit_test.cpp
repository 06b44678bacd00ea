// LodStreamer's edits: they climb the coarse levels, in memory and in the store, and survive reopening.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <span>
#include <thread>

#include "engine/chunk_streamer.h"
#include "engine/lod_streamer.h"
#include "lod_streamer_test_util.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/store/sqlite_store.h"

namespace vx::engine {
namespace {

using namespace vx::world;
using Clock = std::chrono::steady_clock;
using test::Rig;
using test::settle;
using test::small_view;
using test::streaming_for;

// The edit tests' view: a few levels over a small box, to 300 blocks.
LodViewSettings edit_view() {
    LodViewSettings s = small_view();
    s.view_distance = 300;
    return s;
}

// `name` in the temporary folder, removed if a run before left it.
std::filesystem::path fresh_file(const char* name) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove(path);
    return path;
}

// A SQLite store at `path`, a test's own file (null, with a test failure, when it cannot open).
std::unique_ptr<SqliteStore> open_sqlite(const std::filesystem::path& path) {
    SqliteStoreCreateInfo info;
    info.path = path.string();
    auto store = SqliteStore::open(info);
    EXPECT_TRUE(store) << store.error();
    return store ? std::move(*store) : nullptr;
}

// Reopens the store at `path` and expects its coarse chunks over block `p`, levels 1..top, to hold
// a block there (an edit reached every stored level).
void expect_stored_levels_hold(const std::filesystem::path& path, BlockPos p, int top) {
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    for (int k = 1; k <= top; ++k) {
        auto loaded = store->load_lod(lod_chunk_of(p, k));
        ASSERT_TRUE(loaded) << loaded.error();
        ASSERT_EQ(loaded->state, LoadState::Present) << "level " << k;
        EXPECT_NE(loaded->chunk->get(local_index(lod_local_of(p, k))), kAir) << "level " << k;
    }
}

// Moves the viewer to `to` (a minute later on the synthetic clock: past every unload delay) and
// updates level 0 until chunk `c` is dropped; false if it never is (a minute of real time).
bool move_until_dropped(ChunkStreamer& streamer, const glm::dvec3& to, ChunkCoord c, Clock::time_point& now) {
    now += std::chrono::minutes(1);
    const auto limit = Clock::now() + std::chrono::minutes(1);
    do {
        now += std::chrono::milliseconds(16);
        streamer.update(to, glm::dvec3(1, 0, 0), now);
    } while (streamer.world().find_chunk(c) && Clock::now() < limit);
    return streamer.world().find_chunk(c) == nullptr;
}

// The flush tests' world: a store at `path`, the streamers over it, settled around `eye` and
// flushed (settled() says whether that worked), and the clock they ran on.
struct FlushedWorld {
    FlushedWorld(const TerrainGenerator& terrain, const std::filesystem::path& path, const glm::dvec3& eye)
        : store(open_sqlite(path)), rig(terrain, store.get(), edit_view()) {
        ok = store && settle(rig.streamer, rig.lod, eye, now) && rig.streamer.flush().ok();
    }
    std::unique_ptr<SqliteStore> store;
    Rig rig;
    Clock::time_point now{};
    bool ok = false;
};

TEST(LodStreamer, EditsReachTheCoarseLevelsAndSurviveReopening) {
    const TerrainGenerator terrain(5);
    const LodViewSettings s = edit_view();
    const std::filesystem::path path = fresh_file("vx_lod_streamer_edits.sqlite");
    const glm::dvec3 eye(16.5, 20.0, 16.5);
    // A column of stone high in the air above the viewer: it changes every level's cells.
    std::vector<BlockPos> column;
    for (int y = 40; y < 50; ++y)
        column.push_back(BlockPos(20, y, 20));
    {
        auto store = open_sqlite(path);
        ASSERT_TRUE(store);
        Rig rig(terrain, store.get(), s);
        auto& [rec, lod, streamer] = rig;
        Clock::time_point now{};
        ASSERT_TRUE(settle(streamer, lod, eye, now));
        for (BlockPos p : column) {
            ASSERT_TRUE(streamer.set_block(p, 1));
            lod.note_edit(chunk_of(p));
        }
        // One frame later the coarse levels hold the edit (their meshes follow on the pool).
        now += std::chrono::milliseconds(16);
        streamer.update(eye, glm::dvec3(1, 0, 0), now);
        lod.update(eye, now, Clock::now() + std::chrono::milliseconds(2));
        EXPECT_GE(lod.metrics().edits_applied, uint64_t(lod.top_level()));
        for (int k = 1; k <= lod.top_level(); ++k) {
            const LodCoord c = lod_chunk_of(column.front(), k);
            const Chunk* coarse = lod.coarse_chunk(c);
            ASSERT_NE(coarse, nullptr) << "level " << k;
            EXPECT_NE(coarse->get(local_index(lod_local_of(column.front(), k))), kAir) << "level " << k;
            if (k == 1) { // The octant over the edited chunk is its downsampling, cell for cell.
                std::vector<BlockId> want(kChunkVolume), got(kChunkVolume);
                const LodCoord fine{0, chunk_of(column.front())};
                downsample_octant(*streamer.world().find_chunk(fine.chunk), lod_octant(fine), want);
                for (int i = 0; i < kChunkVolume; ++i)
                    got[size_t(i)] = coarse->get(i);
                int differ = 0;
                const ChunkCoord base = ChunkCoord(lod_octant(fine) & 1, (lod_octant(fine) >> 1) & 1, lod_octant(fine) >> 2) * 16;
                for (int x = 0; x < 16; ++x)
                    for (int y = 0; y < 16; ++y)
                        for (int z = 0; z < 16; ++z) {
                            const int i = local_index(base.x + x, base.y + y, base.z + z);
                            differ += int(want[size_t(i)] != got[size_t(i)]);
                        }
                EXPECT_EQ(differ, 0);
            }
        }
        ASSERT_TRUE(settle(streamer, lod, eye, now));
        ASSERT_TRUE(streamer.flush());
    }
    expect_stored_levels_hold(path, column.front(), LodView(eye, s).top_level());
    std::filesystem::remove(path);
}

// Edits followed at once by a flush, with no frame between (Engine::save or shutdown right after
// set_block): flush_edits() puts the coarse levels' saves ahead of the flush, so the stored
// coarse chunks hold the edit. Before, the flush saved the blocks only, and the coarse records
// stayed as they were, not even marked stale.
TEST(LodStreamer, AFlushRightAfterAnEditCarriesTheCoarseLevels) {
    const TerrainGenerator terrain(5);
    const std::filesystem::path path = fresh_file("vx_lod_streamer_flush.sqlite");
    const BlockPos p(20, 45, 20); // High in the air: every level's cell over it changes.
    int top = 0;
    {
        FlushedWorld w(terrain, path, glm::dvec3(16.5, 20.0, 16.5));
        ASSERT_TRUE(w.ok);
        auto& [rec, lod, streamer] = w.rig;
        top = lod.top_level();
        ASSERT_GE(top, 1);
        ASSERT_TRUE(streamer.set_block(p, 1));
        lod.note_edit(chunk_of(p));
        lod.flush_edits();
        ASSERT_TRUE(streamer.flush());
    }
    expect_stored_levels_hold(path, p, top);
    std::filesystem::remove(path);
}

// An edit to a chunk that the next frame drops (the viewer moved on): applied before the
// ChunkStreamer's update (apply_edits, as Engine::update does), its coarse levels are
// refreshed and saved; one whose chunk is already gone has every ancestor marked stale, to be
// derived from the saved blocks (those still kept are derived at once, and saved). Before, apply_edits found no chunk and forgot the edit: the
// coarse levels never showed it, in this session or the next.
TEST(LodStreamer, EditsOfChunksDroppedInTheNextFrameStillReachTheCoarseLevels) {
    const TerrainGenerator terrain(5);
    const std::filesystem::path path = fresh_file("vx_lod_streamer_dropped.sqlite");
    const BlockPos applied(20, 45, 20), late(84, 45, 20); // Level-0 chunks 0 and 2: other parents.
    int top = 0;
    {
        FlushedWorld w(terrain, path, glm::dvec3(16.5, 20.0, 16.5));
        ASSERT_TRUE(w.ok);
        auto& [rec, lod, streamer] = w.rig;
        Clock::time_point& now = w.now;
        top = lod.top_level();
        ASSERT_GE(top, 1);
        const glm::dvec3 far(32000.5, 20.0, -9000.5);
        streamer.update(far, glm::dvec3(1, 0, 0), now); // The old view's chunks are now outside.
        ASSERT_TRUE(streamer.set_block(applied, 1));
        lod.note_edit(chunk_of(applied));
        lod.apply_edits();
        ASSERT_TRUE(streamer.set_block(late, 1));
        lod.note_edit(chunk_of(late)); // Not applied before its chunk goes.
        now += std::chrono::minutes(1); // Past any unload delay: the next updates drop them.
        const auto limit = Clock::now() + std::chrono::minutes(1);
        do {
            now += std::chrono::milliseconds(16);
            streamer.update(far, glm::dvec3(1, 0, 0), now); // Drops are spread over frames.
        } while (streamer.world().find_chunk(chunk_of(late)) && Clock::now() < limit);
        ASSERT_EQ(streamer.world().find_chunk(chunk_of(late)), nullptr) << "the edited chunk was dropped";
        lod.update(far, now, Clock::now() + std::chrono::milliseconds(2));
        ASSERT_TRUE(streamer.flush());
    }
    expect_stored_levels_hold(path, applied, top);
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    auto dirty = store->list_lod_dirty();
    ASSERT_TRUE(dirty) << dirty.error();
    for (int k = 1; k <= kMaxLodLevel; ++k) { // Marked stale, or derived again (those kept) and saved.
        const LodCoord c = lod_ancestor({0, chunk_of(late)}, k);
        if (std::find(dirty->begin(), dirty->end(), c) != dirty->end())
            continue;
        auto loaded = store->load_lod(c);
        ASSERT_TRUE(loaded) << loaded.error();
        ASSERT_EQ(loaded->state, LoadState::Present) << "level " << k << " is neither stale nor saved";
        EXPECT_NE(loaded->chunk->get(local_index(lod_local_of(late, k))), kAir) << "level " << k;
    }
    std::filesystem::remove(path);
}

// The same with the coarse levels still kept in memory (the viewer moved only far enough to drop
// the edited chunk, not its coarse ancestors): those are derived again from the saved blocks. They
// once kept their old cells, so the far view lacked the edit for the rest of the session.
TEST(LodStreamer, KeptCoarseChunksOverADroppedEditedChunkShowTheEdit) {
    const TerrainGenerator terrain(5);
    const std::filesystem::path path = fresh_file("vx_lod_streamer_dropped_kept.sqlite");
    const BlockPos late(84, 45, 20); // Level-0 chunk 2, high in the air: every level's cell changes.
    {
        FlushedWorld w(terrain, path, glm::dvec3(16.5, 20.0, 16.5));
        ASSERT_TRUE(w.ok);
        auto& [rec, lod, streamer] = w.rig;
        Clock::time_point& now = w.now;
        const int top = lod.top_level();
        ASSERT_GE(top, 1);
        const glm::dvec3 moved(-100.5, 20.0, 16.5); // Level-0 chunk -4: chunk 2 leaves the view.
        ASSERT_TRUE(streamer.set_block(late, 1));
        lod.note_edit(chunk_of(late)); // Not applied before its chunk goes.
        ASSERT_TRUE(move_until_dropped(streamer, moved, chunk_of(late), now)) << "the edited chunk was dropped";
        ASSERT_TRUE(settle(streamer, lod, moved, now));
        int kept = 0;
        for (int k = 1; k <= top; ++k) {
            if (const Chunk* coarse = lod.coarse_chunk(lod_chunk_of(late, k))) {
                ++kept;
                EXPECT_NE(coarse->get(local_index(lod_local_of(late, k))), kAir) << "level " << k;
            }
        }
        EXPECT_GE(kept, 2) << "of " << top << " levels over the edit, kept in memory";
        ASSERT_TRUE(streamer.flush());
    }
    std::filesystem::remove(path);
}

// Terrain whose coarse chunk `held` is not made until release() (a slow load).
class HeldCoarseTerrain final : public ChunkGenerator {
public:
    HeldCoarseTerrain(const TerrainGenerator& inner, LodCoord held) : m_inner(inner), m_held(held) {}
    Chunk generate(ChunkCoord c) const override { return m_inner.generate(c); }
    bool generate_coarse(LodCoord c, Chunk& out) const override {
        while (c == m_held && !m_released.load())
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return m_inner.generate_coarse(c, out);
    }
    int coarse_levels() const override { return m_inner.coarse_levels(); }
    void release() const { m_released.store(true); }

private:
    const TerrainGenerator& m_inner;
    LodCoord m_held;
    mutable std::atomic<bool> m_released{false};
};

// An edit reaches level 1 while level 2 over it is still loading: it waits, and on arrival climbs
// every level (level 1, already refreshed, unchanged, stopped the climb, and the edit was dropped:
// levels 2 and up never showed it, in memory or in the store). A save while it waits marks those
// levels stale, so a session that ended then would derive them.
TEST(LodStreamer, AnEditWaitingForALevelToLoadReachesItAndThoseAbove) {
    const TerrainGenerator terrain(5);
    const BlockPos p(20, 45, 20); // High in the air: every level's cell changes.
    const HeldCoarseTerrain gen(terrain, lod_chunk_of(p, 2));
    const std::filesystem::path path = fresh_file("vx_lod_streamer_waiting.sqlite");
    const glm::dvec3 eye(16.5, 20.0, 16.5);
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    int top = 0;
    {
        Rig rig(gen, store.get(), edit_view());
        auto& [rec, lod, streamer] = rig;
        Clock::time_point now{};
        const auto limit = Clock::now() + std::chrono::minutes(1);
        while (!(streamer.world().find_chunk(chunk_of(p)) && lod.coarse_chunk(lod_chunk_of(p, 1))) &&
               Clock::now() < limit) {
            now += std::chrono::milliseconds(16);
            streamer.update(eye, glm::dvec3(1, 0, 0), now);
            lod.update(eye, now, Clock::now() + std::chrono::milliseconds(2));
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        ASSERT_NE(lod.coarse_chunk(lod_chunk_of(p, 1)), nullptr);
        ASSERT_EQ(lod.coarse_chunk(lod_chunk_of(p, 2)), nullptr) << "level 2 is held";
        top = lod.top_level();
        ASSERT_GE(top, 3);
        ASSERT_TRUE(streamer.set_block(p, 1));
        lod.note_edit(chunk_of(p));
        lod.flush_edits(); // Engine::save(): level 1 refreshed, level 2 waited for.
        ASSERT_TRUE(streamer.flush());
        auto dirty = store->list_lod_dirty();
        ASSERT_TRUE(dirty);
        for (int k = 2; k <= top; ++k)
            EXPECT_NE(std::find(dirty->begin(), dirty->end(), lod_chunk_of(p, k)), dirty->end()) << "level " << k;
        gen.release();
        ASSERT_TRUE(settle(streamer, lod, eye, now));
        for (int k = 1; k <= top; ++k) {
            const Chunk* coarse = lod.coarse_chunk(lod_chunk_of(p, k));
            ASSERT_NE(coarse, nullptr) << "level " << k;
            EXPECT_NE(coarse->get(local_index(lod_local_of(p, k))), kAir) << "level " << k;
        }
        ASSERT_TRUE(streamer.flush());
    }
    store.reset();
    std::filesystem::remove(path);
}

// A damaged coarse record over an edit is derived from the levels below (and saved), never
// generated: generated terrain hid the edit at that level, and for good, since the record the
// store moved aside read as a miss from then on.
TEST(LodStreamer, ADamagedCoarseRecordIsDerivedNotGenerated) {
    const TerrainGenerator terrain(5);
    const std::filesystem::path path = fresh_file("vx_lod_streamer_damaged.sqlite");
    const BlockPos p(20, 45, 20); // High in the air: every level's cell changes.
    const glm::dvec3 eye(16.5, 20.0, 16.5);
    int top = 0;
    {
        FlushedWorld w(terrain, path, eye);
        ASSERT_TRUE(w.ok);
        auto& [rec, lod, streamer] = w.rig;
        top = lod.top_level();
        ASSERT_GE(top, 2);
        ASSERT_TRUE(streamer.set_block(p, 1));
        lod.note_edit(chunk_of(p));
        ASSERT_TRUE(settle(streamer, lod, eye, w.now));
        ASSERT_TRUE(streamer.flush());
    }
    {
        auto store = open_sqlite(path);
        ASSERT_TRUE(store);
        const uint8_t junk[4] = {0xDE, 0xAD, 0xBE, 0xEF};
        const Chunk unused; // The record is written as given.
        const LodWrite damaged{lod_chunk_of(p, 2), &unused, junk};
        ASSERT_TRUE(store->save_lod(std::span<const LodWrite>(&damaged, 1)));
        ASSERT_TRUE(store->flush());
    }
    for (int session = 2; session <= 3; ++session) { // The third reads the derived record saved.
        FlushedWorld w(terrain, path, eye);
        ASSERT_TRUE(w.ok);
        for (int k = 1; k <= top; ++k) {
            const Chunk* coarse = w.rig.lod.coarse_chunk(lod_chunk_of(p, k));
            ASSERT_NE(coarse, nullptr) << "session " << session << ", level " << k;
            EXPECT_NE(coarse->get(local_index(lod_local_of(p, k))), kAir) << "session " << session << ", level " << k;
        }
    }
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    auto saved = store->load_lod(lod_chunk_of(p, 2));
    ASSERT_TRUE(saved);
    EXPECT_EQ(saved->state, LoadState::Present);
    store.reset();
    std::filesystem::remove(path);
}

// An edit to a level-0 chunk in memory but under a drawn coarse chunk (its level-1 parent is not
// kept) cannot climb the levels: the kept ones over it are derived again (mark_stale). The store
// lacks the edit until it is saved, so the derivation reads the chunk in memory (LodOverlay), or the
// edit would be missing from those coarse chunks until they were next loaded. A dropped chunk's
// edit, saved, is derived beside it.
TEST(LodStreamer, CoarseChunksDerivedOverAnUnsavedEditShowIt) {
    const TerrainGenerator terrain(5);
    const std::filesystem::path path = fresh_file("vx_lod_streamer_rederived.sqlite");
    const BlockPos dropped(84, 45, 20); // Level-0 chunk x 2; high in the air: every level's cell changes.
    const BlockPos unsaved(100, 45, 20); // Chunk x 3: one level-1 chunk over both.
    ASSERT_EQ(lod_parent({0, chunk_of(dropped)}), lod_parent({0, chunk_of(unsaved)}));
    auto store = open_sqlite(path);
    ASSERT_TRUE(store);
    StreamingSettings ss = streaming_for(edit_view());
    ss.save_delay_s = 1e6; // The second edit stays unsaved until the flush at the end.
    {
        Rig rig(terrain, store.get(), edit_view(), ss);
        auto& [rec, lod, streamer] = rig;
        Clock::time_point now{};
        const glm::dvec3 start(112.5, 20.0, 16.5); // Chunk x 3.
        const glm::dvec3 moved(272.5, 20.0, 16.5); // Chunk x 8: chunk 2 leaves (6 > 5), chunk 3 stays.
        ASSERT_TRUE(settle(streamer, lod, start, now));
        ASSERT_TRUE(streamer.set_block(dropped, 1)); // Saved when its chunk is dropped.
        ASSERT_TRUE(move_until_dropped(streamer, moved, chunk_of(dropped), now)) << "the edited chunk was dropped";
        ASSERT_TRUE(settle(streamer, lod, moved, now));
        ASSERT_NE(streamer.world().find_chunk(chunk_of(unsaved)), nullptr) << "its neighbour stayed";
        ASSERT_EQ(lod.coarse_chunk(lod_parent({0, chunk_of(unsaved)})), nullptr) << "its level-1 parent is kept";
        ASSERT_TRUE(streamer.set_block(unsaved, 2));
        lod.note_edit(chunk_of(unsaved));
        now += std::chrono::milliseconds(16);
        streamer.update(moved, glm::dvec3(1, 0, 0), now);
        lod.update(moved, now, Clock::now() + std::chrono::milliseconds(2));
        EXPECT_EQ(streamer.metrics().dirty, 1u);
        lod.note_edit(chunk_of(dropped));
        ASSERT_TRUE(settle(streamer, lod, moved, now));
        EXPECT_EQ(streamer.metrics().dirty, 1u) << "the neighbour's edit was saved: the test did not test the overlay";
        int kept = 0;
        for (int k = 1; k <= lod.top_level(); ++k) {
            if (const Chunk* coarse = lod.coarse_chunk(lod_chunk_of(unsaved, k))) {
                ++kept;
                EXPECT_NE(coarse->get(local_index(lod_local_of(unsaved, k))), kAir) << "level " << k;
                EXPECT_NE(coarse->get(local_index(lod_local_of(dropped, k))), kAir) << "level " << k;
            }
        }
        EXPECT_GE(kept, 2) << "of " << lod.top_level() << " levels over the edits, kept in memory";
        ASSERT_TRUE(streamer.flush());
    }
    store.reset();
    std::filesystem::remove(path);
}

TEST(LodStreamer, StaleStoredCoarseChunksAreDerivedFromTheEditedBlocks) {
    const TerrainGenerator terrain(9);
    const LodViewSettings s = small_view();
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "vx_lod_streamer_stale.sqlite";
    std::filesystem::remove(path);
    const glm::dvec3 eye(16.5, 20.0, 16.5);
    const BlockPos edit(21, 60, 21); // In the air: every level's cell there was air.
    const LodCoord l1 = lod_chunk_of(edit, 1);
    SqliteStoreCreateInfo info;
    info.path = path.string();
    {
        auto store = SqliteStore::open(info);
        ASSERT_TRUE(store) << store.error();
        Chunk c = terrain.generate(chunk_of(edit));
        c.set(local_of(edit), 1);
        ASSERT_TRUE((*store)->save(chunk_of(edit), c));
        // The level-1 chunk stored before the edit, then marked stale with it (as the engine does).
        auto coarse = generate_lod(terrain, l1);
        ASSERT_TRUE(coarse);
        ASSERT_EQ(coarse->get(local_index(lod_local_of(edit, 1))), kAir);
        ASSERT_TRUE((*store)->save_lod(l1, *coarse));
        const LodCoord mark[] = {l1};
        ASSERT_TRUE((*store)->mark_lod_dirty(mark));
        ASSERT_TRUE((*store)->flush());
    }
    auto store = SqliteStore::open(info);
    ASSERT_TRUE(store) << store.error();
    Rig rig(terrain, store->get(), s);
    auto& [rec, lod, streamer] = rig;
    Clock::time_point now{};
    ASSERT_TRUE(settle(streamer, lod, eye, now));
    const Chunk* derived = lod.coarse_chunk(l1);
    ASSERT_NE(derived, nullptr);
    EXPECT_NE(derived->get(local_index(lod_local_of(edit, 1))), kAir) << "the stale stored chunk was used";
    std::filesystem::remove(path);
}

} // namespace
} // namespace vx::engine
