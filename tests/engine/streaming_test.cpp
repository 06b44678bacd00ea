// Chunk streaming: fills the view, meshes exactly what a full remesh would, saves edits before
// dropping chunks, and never evicts inside the view. Waits are bounded by conditions, never by
// the machine's speed: a slow machine takes longer, it does not fail.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "engine/chunk_streamer.h"
#include "stream_test_util.h"
#include "world/gen/terrain.h"
#include "world/mesh/mesher.h"
#include "world/store/sqlite_store.h"

using namespace vx;
using namespace vx::engine;
using namespace vx::world;
using Clock = std::chrono::steady_clock;
using vx::test::settle;

namespace {

struct Recorder : MeshSink {
    std::map<std::tuple<int, int, int>, ChunkMesh> meshes;
    int unloads = 0, partial_updates = 0;
    std::vector<BlockPos> edited; // on_block_edited, in order.
    void on_block_edited(BlockPos p) override { edited.push_back(p); }
    void on_mesh(ChunkCoord c, const ChunkMesh& mesh, std::span<const int> changed) override {
        meshes[{c.x, c.y, c.z}] = mesh;
        partial_updates += !changed.empty();
    }
    void on_unload(ChunkCoord c) override {
        meshes.erase({c.x, c.y, c.z});
        ++unloads;
    }
};

StreamingSettings small_settings() {
    StreamingSettings s;
    s.view_radius = 2;
    s.view_radius_vertical = 1;
    s.unload_margin = 1;
    s.unload_delay_s = 0.0;
    s.worker_count = 2;
    return s;
}

// The view's meshes equal full meshes of the same world built directly.
void expect_meshes_match(const ChunkStreamer& s, const TerrainGenerator& gen, ChunkCoord center, int r, int rv) {
    GreedyMesher mesher;
    for (int dy = -rv; dy <= rv; ++dy)
        for (int dz = -r; dz <= r; ++dz)
            for (int dx = -r; dx <= r; ++dx) {
                const ChunkCoord c = center + ChunkCoord(dx, dy, dz);
                const ChunkMesh* got = s.mesh(c);
                ASSERT_NE(got, nullptr) << "missing mesh " << c.x << "," << c.y << "," << c.z;
                Apron apron;
                for (int f = 0; f < 6; ++f) {
                    const ChunkCoord n = c + face_normal(Face(f));
                    const Chunk* live = s.world().find_chunk(n);
                    const Chunk fresh = live ? Chunk() : gen.generate(n);
                    apron.copy_face(Face(f), live ? live : &fresh, s.world().registry());
                }
                ChunkMesh expect;
                mesher.mesh({*s.world().find_chunk(c), apron, s.world().registry()}, expect);
                ASSERT_TRUE(*got == expect) << c.x << "," << c.y << "," << c.z;
            }
}

std::filesystem::path temp_store(const char* name) {
    auto p = std::filesystem::temp_directory_path() / (std::string("vx_stream_") + name);
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p / "world.db";
}

} // namespace

TEST(Streaming, FillsTheViewWithExactMeshes) {
    const TerrainGenerator gen(11);
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    const glm::dvec3 pos(40.5, double(gen.surface_height(40, 40)) + 2, 40.5);
    ASSERT_TRUE(settle(s, pos, now));
    const ChunkCoord center = chunk_of(BlockPos(40, gen.surface_height(40, 40) + 2, 40));
    expect_meshes_match(s, gen, center, 2, 1);
    const StreamingMetrics m = s.metrics();
    EXPECT_EQ(m.meshed, m.wanted_meshes);
    EXPECT_EQ(m.wanted_meshes, size_t(5 * 5 * 3));
    EXPECT_EQ(m.loaded, size_t(7 * 7 * 5)); // The view plus its neighbour ring.
}

TEST(Streaming, SameWorldWithOneWorkerOrMany) {
    const TerrainGenerator gen(5);
    auto hash_world = [&](int workers) {
        Recorder sink;
        StreamingSettings st = small_settings();
        st.worker_count = workers;
        ChunkStreamer s(gen, nullptr, sink, st);
        Clock::time_point now = Clock::now();
        EXPECT_TRUE(settle(s, glm::dvec3(-70.5, 10, 300.5), now));
        // FNV-1a over every loaded block, chunks in coordinate order.
        std::map<std::tuple<int, int, int>, const Chunk*> sorted;
        s.world().for_each_chunk([&](ChunkCoord c, const Chunk& ch) { sorted[{c.x, c.y, c.z}] = &ch; });
        uint64_t h = 1469598103934665603ull;
        for (auto& [k, ch] : sorted)
            for (int i = 0; i < kChunkVolume; ++i)
                h = (h ^ ch->get(i)) * 1099511628211ull;
        return std::make_pair(h, sorted.size());
    };
    const auto one = hash_world(1);
    const auto many = hash_world(3);
    EXPECT_EQ(one.second, many.second);
    EXPECT_EQ(one.first, many.first);
}

TEST(Streaming, EditsUpdateMeshesIncrementally) {
    const TerrainGenerator gen(3);
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    const glm::dvec3 pos(0.5, double(gen.surface_height(0, 0)) + 1, 0.5);
    ASSERT_TRUE(settle(s, pos, now));
    const ChunkCoord center = chunk_of(BlockPos(0, gen.surface_height(0, 0) + 1, 0));
    const BlockPos o = chunk_origin(center);
    // Inside, on a border between two meshed chunks, and a corner.
    const BlockPos edits[] = {o + BlockPos(5, 5, 5), o + BlockPos(0, 7, 9), o + BlockPos(31, 31, 0), o + BlockPos(-1, 3, 3)};
    for (const BlockPos& p : edits) {
        ASSERT_TRUE(s.set_block(p, 7).ok());
        EXPECT_EQ(s.get_block(p), 7);
    }
    EXPECT_GT(sink.partial_updates, 0);
    // Each change is reported once, with its block (the renderer's denoiser drops the history
    // near it); setting a block to the id it has changes nothing and reports nothing.
    EXPECT_EQ(sink.edited, std::vector<BlockPos>(std::begin(edits), std::end(edits)));
    ASSERT_TRUE(s.set_block(edits[0], 7).ok());
    EXPECT_EQ(sink.edited.size(), std::size(edits));
    ASSERT_TRUE(settle(s, pos, now));
    expect_meshes_match(s, gen, center, 2, 1);
    // A chunk that is not loaded refuses edits.
    EXPECT_FALSE(s.set_block(BlockPos(100000, 0, 0), 1).ok());
}

TEST(Streaming, DirtyChunksAreSavedBeforeTheyAreDropped) {
    const auto path = temp_store("dirty");
    const TerrainGenerator gen(8);
    const BlockPos p(3, 200, 3); // High in the sky: air before the edit.
    {
        auto store = SqliteStore::open({path.string()});
        ASSERT_TRUE(store.ok()) << store.error();
        Recorder sink;
        ChunkStreamer s(gen, store->get(), sink, small_settings());
        Clock::time_point now = Clock::now();
        ASSERT_TRUE(settle(s, glm::dvec3(3.5, 200.5, 3.5), now));
        ASSERT_TRUE(s.set_block(p, 9).ok());
        // Fly far away: the edited chunk leaves the unload radius and is dropped (saved first).
        ASSERT_TRUE(settle(s, glm::dvec3(3.5 + 32 * 20, 200.5, 3.5), now));
        for (int i = 0; i < 5; ++i)
            s.update(glm::dvec3(3.5 + 32 * 20, 200.5, 3.5), glm::dvec3(0, 0, -1), now += std::chrono::seconds(1));
        EXPECT_EQ(s.world().find_chunk(chunk_of(p)), nullptr);
        EXPECT_GT(s.metrics().unloaded, 0u);
        // Come back: the edit is loaded from the store.
        ASSERT_TRUE(settle(s, glm::dvec3(3.5, 200.5, 3.5), now));
        EXPECT_EQ(s.get_block(p), 9);
        ASSERT_TRUE(s.set_block(p + BlockPos(1, 0, 0), 10).ok());
        ASSERT_TRUE(s.flush().ok());
    }
    // A new streamer over the reopened store sees both edits.
    auto store = SqliteStore::open({path.string()});
    ASSERT_TRUE(store.ok());
    Recorder sink;
    ChunkStreamer s(gen, store->get(), sink, small_settings());
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, glm::dvec3(3.5, 200.5, 3.5), now));
    EXPECT_EQ(s.get_block(p), 9);
    EXPECT_EQ(s.get_block(p + BlockPos(1, 0, 0)), 10);
}

TEST(Streaming, MemoryCapNeverEvictsInsideTheView) {
    const TerrainGenerator gen(4);
    Recorder sink;
    StreamingSettings st = small_settings();
    st.unload_delay_s = 1e9; // Only the cap removes chunks here.
    st.memory_cap_bytes = 1;  // Absurdly small: everything evictable goes.
    ChunkStreamer s(gen, nullptr, sink, st);
    Clock::time_point now = Clock::now();
    const double y = gen.surface_height(0, 0);
    ASSERT_TRUE(settle(s, glm::dvec3(0.5, y, 0.5), now));
    ASSERT_TRUE(settle(s, glm::dvec3(32 * 6 + 0.5, y, 0.5), now));
    const StreamingMetrics m = s.metrics();
    EXPECT_GT(m.evicted, 0u);
    EXPECT_EQ(m.meshed, m.wanted_meshes); // The view is whole despite the cap.
    EXPECT_EQ(m.loaded, size_t(7 * 7 * 5));
}

// A viewer flying chunk by chunk: after each step settles, the whole view is meshed and nothing
// beyond the unload radius is kept.
TEST(Streaming, FlyThroughLeavesNoHoles) {
    const TerrainGenerator gen(21);
    Recorder sink;
    StreamingSettings st = small_settings();
    st.lookahead_s = 0; // Exact bounds below: no meshing ahead of the viewer.
    ChunkStreamer s(gen, nullptr, sink, st);
    Clock::time_point now = Clock::now();
    glm::dvec3 pos(16.5, 20.5, 16.5);
    for (int step = 0; step < 10; ++step) {
        pos += step < 6 ? glm::dvec3(32, 0, 0) : glm::dvec3(0, 0, -32);
        ASSERT_TRUE(settle(s, pos, now)) << "step " << step;
        const StreamingMetrics m = s.metrics();
        EXPECT_EQ(m.meshed, m.wanted_meshes) << "step " << step;
        const ChunkCoord center = chunk_of(BlockPos(int64_t(pos.x), int64_t(pos.y), int64_t(pos.z)));
        s.world().for_each_chunk([&](ChunkCoord c, const Chunk&) {
            const glm::ivec3 d = glm::abs(c - center);
            EXPECT_LE(std::max(d.x, d.z), 2 + 1 + 1); // View + neighbour ring + margin.
            EXPECT_LE(d.y, 1 + 1 + 1);
        });
        for (int dz = -2; dz <= 2; ++dz)
            for (int dx = -2; dx <= 2; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    EXPECT_NE(s.mesh(center + ChunkCoord(dx, dy, dz)), nullptr);
        EXPECT_EQ(sink.meshes.size() >= m.wanted_meshes, true);
    }
    EXPECT_GT(s.metrics().unloaded, 0u);
}

// Hovering across a chunk border: the margin and the delay keep edge chunks loaded.
TEST(Streaming, HysteresisStopsThrashing) {
    const TerrainGenerator gen(22);
    Recorder sink;
    StreamingSettings st = small_settings();
    st.unload_delay_s = 5.0;
    ChunkStreamer s(gen, nullptr, sink, st);
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, glm::dvec3(31.0, 20.5, 16.5), now));
    for (int i = 0; i < 200; ++i) {
        now += std::chrono::milliseconds(16);
        s.update(glm::dvec3(i % 2 ? 33.0 : 31.0, 20.5, 16.5), glm::dvec3(1, 0, 0), now);
    }
    EXPECT_EQ(s.metrics().unloaded, 0u);
    EXPECT_EQ(sink.unloads, 0);
}

namespace {

// Chunks of the box of half widths r, rv around `center` for which `s` has a mesh.
size_t count_meshes(const ChunkStreamer& s, ChunkCoord center, int r, int rv) {
    size_t n = 0;
    for (int dy = -rv; dy <= rv; ++dy)
        for (int dz = -r; dz <= r; ++dz)
            for (int dx = -r; dx <= r; ++dx)
                n += s.mesh(center + ChunkCoord(dx, dy, dz)) != nullptr;
    return n;
}

ChunkCoord chunk_at(glm::dvec3 p) {
    return chunk_of(BlockPos(int64_t(std::floor(p.x)), int64_t(std::floor(p.y)), int64_t(std::floor(p.z))));
}

} // namespace

// Edited chunks reach the store once save_delay has passed since their first edit, no earlier,
// among many clean loaded chunks; a chunk edited twice is saved once.
TEST(Streaming, DirtyChunksAreSavedWithinTheSaveDelay) {
    const auto path = temp_store("save_delay");
    const TerrainGenerator gen(9);
    auto store = SqliteStore::open({path.string()});
    ASSERT_TRUE(store.ok()) << store.error();
    Recorder sink;
    StreamingSettings st = small_settings();
    st.view_radius = 3; // 9 x 9 x 5 = 405 loaded chunks, 3 of them edited.
    st.save_delay_s = 2.0;
    st.unload_delay_s = 1e9;
    ChunkStreamer s(gen, store->get(), sink, st);
    Clock::time_point now = Clock::now();
    const glm::dvec3 pos(8.5, 100.5, 8.5);
    ASSERT_TRUE(settle(s, pos, now));
    const size_t loaded = s.metrics().loaded;
    EXPECT_EQ(loaded, size_t(9 * 9 * 5));
    // Edits are stamped with the last update's time (the caller's clock), here `now`.
    const BlockPos edits[] = {{8, 100, 8}, {9, 100, 8}, {40, 100, 8}, {8, 100, -60}}; // 3 chunks.
    for (const BlockPos& p : edits)
        ASSERT_TRUE(s.set_block(p, 5).ok());
    EXPECT_EQ(s.metrics().dirty, 3u);
    const auto delay = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(st.save_delay_s));
    s.update(pos, glm::dvec3(0, 0, -1), now + delay - std::chrono::milliseconds(1)); // Not yet due.
    EXPECT_EQ(s.metrics().saves, 0u);
    EXPECT_EQ(s.metrics().dirty, 3u);
    s.update(pos, glm::dvec3(0, 0, -1), now + delay); // All due.
    EXPECT_EQ(s.metrics().saves, 3u);
    EXPECT_EQ(s.metrics().dirty, 0u);
    EXPECT_EQ(s.metrics().loaded, loaded); // Saving dropped nothing.
    // Edited again after its save (stamped now + delay): dirty again, saved again once due.
    const Clock::time_point again = now + delay;
    ASSERT_TRUE(s.set_block(edits[0], 6).ok());
    s.update(pos, glm::dvec3(0, 0, -1), again + delay - std::chrono::milliseconds(1));
    EXPECT_EQ(s.metrics().saves, 3u);
    s.update(pos, glm::dvec3(0, 0, -1), again + delay);
    EXPECT_EQ(s.metrics().saves, 4u);
    ASSERT_TRUE(s.flush().ok());
}

// A cap far below what the view needs, while flying fast with the lookahead: no meshed chunk
// of the view ever loses its data or mesh; chunks behind are evicted.
TEST(Streaming, MemoryCapNeverEvictsInsideTheViewInFlight) {
    const TerrainGenerator gen(4);
    struct ViewGuard : Recorder {
        ChunkCoord center{0};
        int bad = 0;
        void on_unload(ChunkCoord c) override {
            const glm::ivec3 d = glm::abs(c - center);
            bad += std::max(d.x, d.z) <= 2 && d.y <= 1; // Inside the view radius.
            Recorder::on_unload(c);
        }
    } sink;
    StreamingSettings st = small_settings();
    st.unload_delay_s = 1e9; // Only the cap removes chunks here.
    st.memory_cap_bytes = 1;
    ChunkStreamer s(gen, nullptr, sink, st);
    Clock::time_point now = Clock::now();
    glm::dvec3 pos(0.5, gen.surface_height(0, 0), 0.5);
    ASSERT_TRUE(settle(s, pos, now));
    for (int frame = 0; frame < 120; ++frame) {
        pos.x += 6.0; // 375 blocks/s at 16 ms frames: the lookahead reaches the view radius.
        sink.center = chunk_at(pos);
        s.update(pos, glm::dvec3(1, 0, 0), now += std::chrono::milliseconds(16));
        const ChunkCoord center = chunk_at(pos);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -2; dz <= 2; ++dz)
                for (int dx = -2; dx <= 2; ++dx) {
                    const ChunkCoord c = center + ChunkCoord(dx, dy, dz);
                    if (s.mesh(c)) {
                        ASSERT_NE(s.world().find_chunk(c), nullptr) << "frame " << frame;
                    }
                }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(sink.bad, 0);
    ASSERT_TRUE(settle(s, pos, now));
    const StreamingMetrics m = s.metrics();
    EXPECT_GT(m.evicted, 0u);
    EXPECT_EQ(m.meshed, m.wanted_meshes);
    EXPECT_LT(m.loaded, size_t(2 * 7 * 7 * 5)); // At most the rings of the viewer and the lookahead.
}

// With a store that has nothing yet, every chunk is a load miss that generates (chained from the
// I/O lane, without the main thread): the view still fills with exact meshes.
TEST(Streaming, LoadMissesGenerateAndMesh) {
    const auto path = temp_store("miss");
    const TerrainGenerator gen(13);
    auto store = SqliteStore::open({path.string()});
    ASSERT_TRUE(store.ok()) << store.error();
    Recorder sink;
    ChunkStreamer s(gen, store->get(), sink, small_settings());
    Clock::time_point now = Clock::now();
    const glm::dvec3 pos(-20.5, double(gen.surface_height(-21, 70)) + 2, 70.5);
    ASSERT_TRUE(settle(s, pos, now));
    expect_meshes_match(s, gen, chunk_at(pos), 2, 1);
    const StreamingMetrics m = s.metrics();
    EXPECT_EQ(m.meshed, m.wanted_meshes);
    EXPECT_EQ(m.loaded, size_t(7 * 7 * 5));
    EXPECT_EQ(m.pending_data, 0u);
    EXPECT_EQ(m.regenerated_corrupt, 0u);
}

// A jump far beyond the loaded region fills the new view (a full pass, not a slab) and drops
// the old region; jumping back fills the old view again.
TEST(Streaming, TeleportFillsTheNewView) {
    const TerrainGenerator gen(17);
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    const glm::dvec3 a(16.5, double(gen.surface_height(16, 16)) + 2, 16.5);
    const glm::dvec3 b(32000.5, double(gen.surface_height(32000, -9000)) + 2, -9000.5);
    for (const glm::dvec3& p : {a, b, a}) {
        ASSERT_TRUE(settle(s, p, now));
        expect_meshes_match(s, gen, chunk_at(p), 2, 1);
        EXPECT_EQ(s.metrics().loaded, size_t(7 * 7 * 5)); // The old region is gone (delay 0).
    }
    EXPECT_GE(s.metrics().unloaded, 2u * 7 * 7 * 5);
}

// A chunk whose generation fails makes its neighbours mesh against air, and when it goes their
// meshes are asked for again (remesh_around), so has_mesh is cleared while the old meshes stay
// drawn. Dropped before the new ones came, they once stayed in the sink: ghost geometry far from
// the view (and, with levels of detail, a pointer to a freed mesh). After a teleport the sink
// holds only chunks the streamer holds.
TEST(Streaming, DroppedChunksLeaveNoMeshBehindAfterAFailedNeighbour) {
    const TerrainGenerator terrain(17);
    struct FailingOne final : ChunkGenerator {
        const TerrainGenerator& inner;
        ChunkCoord bad;
        FailingOne(const TerrainGenerator& g, ChunkCoord c) : inner(g), bad(c) {}
        Chunk generate(ChunkCoord c) const override { return inner.generate(c); }
        Result<Chunk> try_generate(ChunkCoord c) const override {
            if (c == bad)
                return Error{"injected generator failure"};
            return inner.generate(c);
        }
    };
    const glm::dvec3 a(16.5, double(terrain.surface_height(16, 16)) + 2, 16.5);
    const FailingOne gen(terrain, chunk_at(a) + ChunkCoord(1, 0, 0));
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    // The view around the failure meshes (a real-time limit only for a very slow machine).
    const auto limit = Clock::now() + std::chrono::minutes(2);
    while ((s.metrics().meshed < 50 || s.metrics().generate_failures == 0) && Clock::now() < limit) {
        now += std::chrono::milliseconds(16);
        s.update(a, glm::dvec3(0, 0, -1), now);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_GT(s.metrics().generate_failures, 0u);
    ASSERT_GE(s.metrics().meshed, 50u);
    const glm::dvec3 b(32000.5, double(terrain.surface_height(32000, -9000)) + 2, -9000.5);
    ASSERT_TRUE(settle(s, b, now));
    int ghosts = 0;
    for (const auto& [key, mesh] : sink.meshes) {
        const auto [x, y, z] = key;
        ghosts += s.world().find_chunk(ChunkCoord(x, y, z)) == nullptr;
    }
    EXPECT_EQ(ghosts, 0) << "meshes of chunks the streamer dropped";
}

// metrics() keeps its counts as states change (no scan); they match a recount through the
// public API on every frame of a flight that turns and stops.
TEST(Streaming, MetricsMatchARecountInFlight) {
    const TerrainGenerator gen(23);
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    glm::dvec3 pos(0.5, 30.5, 0.5);
    for (int frame = 0; frame < 300; ++frame) {
        if (frame < 100)
            pos.x += 3.0;
        else if (frame < 200)
            pos.z -= 4.0;
        s.update(pos, glm::dvec3(1, 0, 0), now += std::chrono::milliseconds(16));
        size_t loaded = 0;
        s.world().for_each_chunk([&](ChunkCoord, const Chunk&) { ++loaded; });
        const StreamingMetrics m = s.metrics();
        ASSERT_EQ(m.loaded, loaded) << "frame " << frame;
        ASSERT_EQ(m.meshed, count_meshes(s, chunk_at(pos), 2, 1)) << "frame " << frame;
        ASSERT_EQ(m.wanted_meshes, size_t(5 * 5 * 3));
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(settle(s, pos, now));
    EXPECT_EQ(s.metrics().meshed, s.metrics().wanted_meshes);
    EXPECT_EQ(s.metrics().pending_meshes, 0u);
}

// A game's velocity of 1e308 blocks/s is finite, but times the lookahead it is not: the lookahead
// point was once NaN (converted to a chunk coordinate: undefined behaviour, a lead chunk near the
// world's edge). It is where any speed past the view radius puts it: the view radius ahead.
TEST(Streaming, AnyFiniteVelocityLooksAheadTheViewRadius) {
    const TerrainGenerator gen(5);
    const glm::dvec3 pos(0.5, gen.surface_height(0, 0), 0.5);
    const ChunkCoord lead = chunk_at(pos + glm::dvec3(2 * 32, 0, 0)); // view_radius 2 chunks ahead.
    for (const double speed : {1e6, 1e308}) {
        Recorder sink;
        ChunkStreamer s(gen, nullptr, sink, small_settings());
        Clock::time_point now = Clock::now();
        const auto limit = std::chrono::steady_clock::now() + std::chrono::minutes(3);
        do {
            s.update(pos, glm::dvec3(1, 0, 0), glm::dvec3(speed, 0, 0), now += std::chrono::milliseconds(16));
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        } while (!s.settled() && std::chrono::steady_clock::now() < limit);
        ASSERT_TRUE(s.settled()) << speed;
        EXPECT_EQ(count_meshes(s, lead, 2, 1), size_t(5 * 5 * 3)) << speed;
        EXPECT_EQ(sink.meshes.size(), size_t(5 * 7 * 3)) << speed; // The two rings overlap.
    }
}

// A viewer at the world's last chunk (a direct user of the streamer; the facade refuses it) is
// kept 2^17 blocks inside: the box then ended on INT32_MAX chunks and its walk never returned.
TEST(Streaming, AViewerAtTheWorldsEdgeIsKeptInside) {
    const TerrainGenerator gen(5);
    Recorder sink;
    ChunkStreamer s(gen, nullptr, sink, small_settings());
    Clock::time_point now = Clock::now();
    const double edge = double(kWorldMaxBlock) - 40.0;
    ASSERT_TRUE(settle(s, glm::dvec3(edge, 60.5, 0.5), now));
    const ChunkCoord inside = chunk_of(BlockPos(kWorldMaxBlock - kEdgeMarginBlocks, 60, 0));
    EXPECT_EQ(s.metrics().loaded, size_t(7 * 7 * 5)); // The loaded ring, around `inside`.
    EXPECT_NE(s.world().find_chunk(inside + ChunkCoord(3, 0, 0)), nullptr);
    EXPECT_EQ(s.world().find_chunk(inside + ChunkCoord(4, 0, 0)), nullptr);
}
