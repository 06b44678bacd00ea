// The facade <vx/vx.h> end to end without a GPU (RenderTarget::none): streaming, get_block (air
// vs not loaded), edits, raycasts (hit, miss, leaving loaded space), events, a game's own
// generator and blocks, saving with tickets, shutdown, and reopening a SQLite world. Waits are
// bounded by conditions (a generous limit), never by the machine's speed.
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <thread>

#include <unistd.h>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_test_util.h"

#include "world/gen/terrain.h"
#include "world/lod/lod_coords.h"
#include "world/store/sqlite_store.h"
#if VX_WITH_OPENVDB
#include "world/vdb/vdb_world.h"
#endif

using Clock = std::chrono::steady_clock;

namespace {

using vx::test::settle;

constexpr uint64_t kSeed = 7;

vx::EngineCreateInfo small_info(vx::WorldSource source) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.streaming.view_radius = 2;
    info.streaming.view_radius_vertical = 1;
    info.streaming.unload_margin = 0;
    info.streaming.unload_delay_s = 0.0;
    info.streaming.worker_threads = 2;
    info.chunk_events = true;
    return info;
}

// A column of the seed's terrain above the sea, so the sky over it is air.
int64_t dry_column_x(int64_t z) {
    for (int64_t x = 0;; ++x)
        if (vx::terrain_height(kSeed, x, z) > 4)
            return x;
}

std::string temp_path(const char* name) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_facade_test";
    std::filesystem::create_directories(dir);
    const auto p = dir / (std::string(name) + "_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(p);
    std::filesystem::remove(p.string() + "-wal");
    std::filesystem::remove(p.string() + "-shm");
    return p.string();
}

vx::Viewer viewer_at(vx::BlockPos block) {
    vx::Viewer v;
    v.block = block;
    v.forward = {1, -0.2, 0};
    return v;
}

TEST(Facade, StreamsAndAnswersBlocks) {
    auto engine = vx::Engine::create(small_info(vx::WorldSource::terrain(kSeed)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const int64_t x = dry_column_x(16), h = vx::terrain_height(kSeed, x, 16);
    ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
    ASSERT_TRUE(settle(e));

    // Every block of the viewer's chunk equals the generator's; far away is unknown, not air.
    const vx::ChunkCoord c = vx::chunk_of({x, h + 2, 16});
    const vx::world::Chunk expect = vx::world::TerrainGenerator(kSeed).generate(c);
    for (int i = 0; i < vx::kChunkVolume; i += 97) {
        const vx::BlockPos p = vx::chunk_origin(c) + vx::BlockPos(i & 31, (i >> 5) & 31, i >> 10);
        ASSERT_EQ(e.get_block(p), std::optional<vx::BlockId>(expect.get(i))) << i;
    }
    EXPECT_EQ(e.get_block({x, h + 1, 16}), std::optional<vx::BlockId>(vx::kAir)); // Loaded air.
    EXPECT_EQ(e.get_block({x + 100000, 0, 16}), std::nullopt);                    // Not loaded.

    // 5 × 5 × 3 chunks in view, all meshed; 7 × 7 × 5 loaded (the ring for neighbours).
    const vx::Stats s = e.stats();
    EXPECT_EQ(s.chunks_in_view, 75u);
    EXPECT_EQ(s.chunks_meshed, 75u);
    EXPECT_EQ(s.chunks_loaded, 245u);
    EXPECT_GT(s.block_memory_bytes, 0u);
    EXPECT_EQ(s.gpu_memory_bytes, 0u); // No GPU.
    EXPECT_EQ(s.blas_builds, 0u);
    // Not a persistent world: saving says so.
    auto ticket = e.save();
    ASSERT_FALSE(ticket);
    EXPECT_NE(ticket.error().find("does not persist"), std::string::npos) << ticket.error();
}

TEST(Facade, EditsAndRaycasts) {
    auto engine = vx::Engine::create(small_info(vx::WorldSource::terrain(kSeed)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const int64_t x = dry_column_x(16), h = vx::terrain_height(kSeed, x, 16);
    ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
    ASSERT_TRUE(settle(e));
    const vx::BlockId stone = *e.find_block("stone"), glass = *e.find_block("glass");

    // Up from the eye, before any edit: air until the top of the loaded space (viewer chunk + 2).
    const vx::BlockPos eye{x, h + 2, 16};
    const int64_t top = (int64_t(vx::chunk_of(eye).y) + 3) * vx::kChunkSize;
    auto up = e.raycast(eye, {0.5, 0.5, 0.5}, {0, 1, 0}, 1000.0);
    ASSERT_TRUE(up) << up.error();
    EXPECT_EQ(up->kind, vx::RayHit::Kind::Unloaded);
    EXPECT_EQ(up->block, vx::BlockPos(x, top, 16));
    EXPECT_EQ(up->distance, double(top) - (double(h + 2) + 0.5));
    auto short_up = e.raycast(eye, {0.5, 0.5, 0.5}, {0, 1, 0}, 2.0);
    ASSERT_TRUE(short_up);
    EXPECT_EQ(short_up->kind, vx::RayHit::Kind::Miss);
    const vx::BlockPos p{x, h + 5, 16};
    ASSERT_TRUE(e.set_block(p, stone));
    EXPECT_EQ(e.get_block(p), std::optional<vx::BlockId>(stone));

    // Straight down from 5.5 blocks above the block's top face (y = h + 6): distance 5.5, exact.
    auto down = e.raycast({x, h + 11, 16}, {0.5, 0.5, 0.5}, {0, -1, 0}, 20.0);
    ASSERT_TRUE(down) << down.error();
    EXPECT_EQ(down->kind, vx::RayHit::Kind::Hit);
    EXPECT_EQ(down->block, p);
    EXPECT_EQ(down->id, stone);
    EXPECT_EQ(down->face, vx::Face::PosY);
    EXPECT_EQ(down->distance, 5.5);
    EXPECT_EQ(down->previous, p + vx::BlockPos(0, 1, 0));

    EXPECT_FALSE(e.raycast(eye, {0.5, 0.5, 0.5}, {0, 0, 0}, 10.0)); // No direction: an error.
    // Any finite length is a direction (1e-200 hit the stone below at distance 0, past the limit).
    for (const double scale : {1e-200, 1e200}) {
        auto scaled = e.raycast({x, h + 11, 16}, {0.5, 0.5, 0.5}, {0, -scale, 0}, 20.0);
        ASSERT_TRUE(scaled) << scaled.error();
        EXPECT_EQ(scaled->kind, down->kind) << scale;
        EXPECT_NEAR(scaled->distance, down->distance, 1e-12) << scale;
        EXPECT_FALSE(e.raycast({x, h + 11, 16}, {0.5, 0.5, 0.5}, {0, -scale, 0}, 2.0)->kind == vx::RayHit::Kind::Hit);
    }
    // An offset past 2^40 or an origin outside the world is an error, not a wrapped block.
    EXPECT_FALSE(e.raycast(eye, {1e300, 0.5, 0.5}, {0, 1, 0}, 2.0));
    EXPECT_FALSE(e.raycast({int64_t(1) << 40, 0, 0}, {0.5, 0.5, 0.5}, {0, 1, 0}, 2.0));

    // Refusals change nothing: an unknown id, a chunk not loaded, and a batch holding either.
    vx::Status bad_id = e.set_block(p, vx::BlockId(999));
    ASSERT_FALSE(bad_id);
    EXPECT_NE(bad_id.error().find("not a registered block"), std::string::npos) << bad_id.error();
    vx::Status far = e.set_block({x + 100000, 0, 0}, stone);
    ASSERT_FALSE(far);
    EXPECT_NE(far.error().find("not loaded"), std::string::npos) << far.error();
    const vx::BlockEdit batch[] = {{p, glass}, {p + vx::BlockPos(1, 0, 0), glass}, {{x + 100000, 0, 0}, glass}};
    const std::optional<vx::BlockId> beside = e.get_block(p + vx::BlockPos(1, 0, 0));
    ASSERT_TRUE(beside.has_value());
    ASSERT_NE(*beside, glass);
    EXPECT_FALSE(e.set_blocks(batch));
    EXPECT_EQ(e.get_block(p), std::optional<vx::BlockId>(stone));
    EXPECT_EQ(e.get_block(p + vx::BlockPos(1, 0, 0)), beside);
    EXPECT_TRUE(e.set_blocks(std::span(batch, 2)));
    EXPECT_EQ(e.get_block(p + vx::BlockPos(1, 0, 0)), std::optional<vx::BlockId>(glass));

    ASSERT_TRUE(e.shutdown());
    EXPECT_FALSE(e.set_block(p, stone));
    EXPECT_EQ(e.get_block(p), std::nullopt);
    EXPECT_TRUE(e.shutdown()); // Idempotent.
}

TEST(Facade, ChunkEvents) {
    auto engine = vx::Engine::create(small_info(vx::WorldSource::terrain(kSeed)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const int64_t h = vx::terrain_height(kSeed, 16, 16);
    ASSERT_TRUE(e.set_viewer(viewer_at({16, h, 16})));
    ASSERT_TRUE(settle(e));
    const vx::ChunkCoord home = vx::chunk_of({16, h, 16});
    std::set<std::tuple<int, int, int, int>> seen;
    auto drain = [&] {
        for (const vx::ChunkEvent& ev : e.poll_events())
            seen.insert({int(ev.kind), ev.chunk.x, ev.chunk.y, ev.chunk.z});
    };
    auto has = [&](vx::ChunkEvent::Kind k, vx::ChunkCoord c) { return seen.count({int(k), c.x, c.y, c.z}) == 1; };
    drain();
    EXPECT_TRUE(has(vx::ChunkEvent::Kind::Loaded, home));
    EXPECT_TRUE(has(vx::ChunkEvent::Kind::Meshed, home));
    EXPECT_TRUE(e.poll_events().empty()); // Drained.

    // 20 chunks away: everything around home unloads (margin 0, no delay).
    ASSERT_TRUE(e.set_viewer(viewer_at({16 + 20 * 32, h, 16})));
    ASSERT_TRUE(settle(e));
    drain();
    EXPECT_TRUE(has(vx::ChunkEvent::Kind::Unloaded, home));
    EXPECT_EQ(e.get_block({16, h, 16}), std::nullopt);
}

// A game's generator: a floor of stone below y = 0 and a post of "post" blocks every 8 blocks.
class PostGenerator final : public vx::Generator {
public:
    explicit PostGenerator(vx::BlockId stone, vx::BlockId post) : m_stone(stone), m_post(post) {}
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        ++m_calls;
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int z = 0; z < 32; ++z)
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const vx::BlockPos p = o + vx::BlockPos(x, y, z);
                    if (p.y < 0)
                        blocks[vx::chunk_index(x, y, z)] = m_stone;
                    else if (p.y < 4 && (p.x & 7) == 0 && (p.z & 7) == 0)
                        blocks[vx::chunk_index(x, y, z)] = m_post;
                }
    }
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        if (c.y < 0)
            return m_stone;
        if (c.y > 0)
            return vx::kAir;
        return std::nullopt;
    }
    mutable std::atomic<int> m_calls{0};

private:
    vx::BlockId m_stone, m_post;
};

TEST(Facade, GameBlocksAndGenerator) {
    std::vector<vx::BlockType> blocks = {{"rock", {0.5f, 0.5f, 0.5f}}, {"post", {0.1f, 0.1f, 0.9f}}};
    auto gen = std::make_shared<PostGenerator>(1, 2);
    vx::EngineCreateInfo info = small_info(vx::WorldSource::custom(gen));
    info.blocks = blocks;
    auto engine = vx::Engine::create(info);
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    EXPECT_EQ(e.find_block("rock"), std::optional<vx::BlockId>(1));
    EXPECT_EQ(e.find_block("post"), std::optional<vx::BlockId>(2));
    EXPECT_EQ(e.find_block("stone"), std::nullopt); // The built-in palette is not there.
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 2, 4})));
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.get_block({8, 3, 16}), std::optional<vx::BlockId>(2));
    EXPECT_EQ(e.get_block({8, 4, 16}), std::optional<vx::BlockId>(vx::kAir));
    EXPECT_EQ(e.get_block({9, 3, 16}), std::optional<vx::BlockId>(vx::kAir));
    EXPECT_EQ(e.get_block({9, -40, 16}), std::optional<vx::BlockId>(1));
    // Only the chunk layer y = 0 needed generate(): 7 × 7 columns of the loaded box.
    EXPECT_EQ(gen->m_calls.load(), 49);
    EXPECT_FALSE(e.set_block({9, 5, 16}, 3)); // Id 3 is not one of the game's blocks.

    // Bad descriptions fail with a message.
    info.blocks.push_back({"post"});
    auto dup = vx::Engine::create(info);
    ASSERT_FALSE(dup);
    EXPECT_NE(dup.error().find("post"), std::string::npos) << dup.error();
    vx::EngineCreateInfo null_gen = small_info(vx::WorldSource::custom(nullptr));
    EXPECT_FALSE(vx::Engine::create(null_gen));
    // A stored world given a null generator is refused before the file is made: it was created with
    // the terrain of seed 1 and remembered it, so the game's generator was refused from then on.
    const std::string path = temp_path("null_generator");
    auto stored = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, nullptr)));
    ASSERT_FALSE(stored);
    EXPECT_NE(stored.error().find("null generator"), std::string::npos) << stored.error();
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Facade, SaveTicketsAndReopen) {
    const std::string path = temp_path("save");
    const int64_t x = dry_column_x(16), h = vx::terrain_height(kSeed, x, 16);
    const vx::BlockPos a{x, h + 3, 16}, b{x, h + 4, 16};
    {
        auto engine = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, kSeed)));
        ASSERT_TRUE(engine) << engine.error();
        vx::Engine& e = **engine;
        ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
        ASSERT_TRUE(settle(e));
        const vx::BlockId lamp = *e.find_block("lamp");
        ASSERT_TRUE(e.set_block(a, lamp));
        EXPECT_EQ(e.stats().dirty_chunks, 1u);
        auto ticket = e.save();
        ASSERT_TRUE(ticket) << ticket.error();
        EXPECT_EQ(e.stats().dirty_chunks, 0u); // Handed to the I/O thread at once.
        ASSERT_TRUE(e.wait(*ticket));
        EXPECT_EQ(e.save_state(*ticket), vx::SaveState::Durable);
        EXPECT_EQ(e.save_state(vx::SaveTicket{ticket->sequence + 1}), vx::SaveState::Unknown); // Never issued.
        // A second edit is saved by shutdown alone.
        ASSERT_TRUE(e.set_block(b, lamp));
        ASSERT_TRUE(e.shutdown());
        EXPECT_EQ(e.save_state(*ticket), vx::SaveState::Durable); // Still answers after shutdown.
    }
    auto engine = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, kSeed)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.get_block(a), e.find_block("lamp"));
    EXPECT_EQ(e.get_block(b), e.find_block("lamp"));
    ASSERT_TRUE(e.shutdown());

    // The file remembers its seed and blocks: another seed, or blocks renumbered, are refused;
    // blocks appended are fine.
    auto other_seed = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, kSeed + 1)));
    ASSERT_FALSE(other_seed);
    EXPECT_NE(other_seed.error().find("seed 7"), std::string::npos) << other_seed.error();
    vx::EngineCreateInfo renumbered = small_info(vx::WorldSource::sqlite(path, kSeed));
    renumbered.blocks = vx::default_blocks();
    std::swap(renumbered.blocks[0], renumbered.blocks[1]);
    auto swapped = vx::Engine::create(renumbered);
    ASSERT_FALSE(swapped);
    EXPECT_NE(swapped.error().find("other blocks"), std::string::npos) << swapped.error();
    vx::EngineCreateInfo appended = small_info(vx::WorldSource::sqlite(path, kSeed));
    appended.blocks = vx::default_blocks();
    appended.blocks.push_back({"marble", {0.9f, 0.9f, 0.85f}});
    EXPECT_TRUE(vx::Engine::create(appended));
}

TEST(Facade, DescriptionErrors) {
    vx::EngineCreateInfo window = small_info(vx::WorldSource::terrain(1));
    window.render.target = vx::RenderTarget::glfw_window(nullptr);
    auto w = vx::Engine::create(window);
    ASSERT_FALSE(w);
    EXPECT_NE(w.error().find("needs a GLFWwindow*"), std::string::npos) << w.error();

    vx::EngineCreateInfo sized = small_info(vx::WorldSource::terrain(1));
    sized.render.target = vx::RenderTarget::headless(0, 10);
    EXPECT_FALSE(vx::Engine::create(sized));

    auto vdb = vx::Engine::create(small_info(vx::WorldSource::vdb("/nonexistent/world.vdb")));
    ASSERT_FALSE(vdb);
    EXPECT_NE(vdb.error().find(VX_WITH_OPENVDB ? "world.vdb" : "COMPONENTS vdb"), std::string::npos) << vdb.error();

    auto db = vx::Engine::create(small_info(vx::WorldSource::sqlite("/nonexistent/dir/w.db", 1)));
    ASSERT_FALSE(db);
    EXPECT_NE(db.error().find("w.db"), std::string::npos) << db.error();

    // Bad viewers are refused and the previous one stays.
    auto engine = vx::Engine::create(small_info(vx::WorldSource::terrain(1)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Viewer v;
    v.offset.x = std::nan("");
    EXPECT_FALSE((*engine)->set_viewer(v));
    v.offset = glm::dvec3(0.5);
    v.block.x = int64_t(1) << 40;
    EXPECT_FALSE((*engine)->set_viewer(v));
    v.block.x = 0;
    EXPECT_TRUE((*engine)->set_viewer(v));
}

#if VX_WITH_OPENVDB
// A VDB world opened read_only: its blocks stream in, space outside it is air, edits stay in
// memory, save refuses, no overlay is created. (The overlay: tests/vdb/vdb_overlay_test.cpp.)
TEST(Facade, VdbWorldIsReadOnly) {
    vx::world::World src;
    for (int64_t x = -3; x < 40; ++x)
        for (int64_t z = -3; z < 40; ++z)
            src.set_block({x, -1, z}, 1);
    src.set_block({5, 0, 5}, 8);
    const std::string path = temp_path("vdb_world") + ".vdb";
    ASSERT_TRUE(vx::vdb::export_vdb(src, path));
    vx::WorldSource source = vx::WorldSource::vdb(path);
    source.read_only = true;
    auto engine = vx::Engine::create(small_info(source));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 4, 4})));
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.get_block({5, 0, 5}), std::optional<vx::BlockId>(8));
    EXPECT_EQ(e.get_block({20, -1, 20}), std::optional<vx::BlockId>(1));
    EXPECT_EQ(e.get_block({50, -1, 50}), std::optional<vx::BlockId>(vx::kAir)); // Outside the file.
    ASSERT_TRUE(e.set_block({6, 0, 6}, 2));
    EXPECT_EQ(e.get_block({6, 0, 6}), std::optional<vx::BlockId>(2));
    EXPECT_EQ(e.stats().dirty_chunks, 0u); // Nothing to save to.
    auto ticket = e.save();
    ASSERT_FALSE(ticket);
    EXPECT_NE(ticket.error().find("read-only"), std::string::npos) << ticket.error();
    EXPECT_TRUE(e.shutdown());
    EXPECT_FALSE(std::filesystem::exists(path + ".edits.sqlite"));
}
#endif

} // namespace

namespace {

vx::EngineCreateInfo lod_info(vx::WorldSource source) {
    vx::EngineCreateInfo info = small_info(std::move(source));
    info.streaming.view_distance = 420;
    info.streaming.lod_ring = 2;
    info.streaming.lod_vertical_reach = 64;
    info.chunk_events = false;
    return info;
}

} // namespace

// Levels of detail through the facade: the view fills to the view distance with coarse levels,
// no hole once settled, edits reach the coarse levels, and the settings are checked.
TEST(Facade, LevelsOfDetailFillTheViewDistance) {
    auto engine = vx::Engine::create(lod_info(vx::WorldSource::terrain(kSeed)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    const int64_t x = dry_column_x(16), h = vx::terrain_height(kSeed, x, 16);
    ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
    ASSERT_TRUE(settle(e));
    vx::Stats s = e.stats();
    EXPECT_GE(s.lod_top_level, 2);
    EXPECT_EQ(s.holes, 0u);
    for (int k = 0; k <= s.lod_top_level; ++k) {
        EXPECT_GT(s.level_chunks_drawn[size_t(k)], 0u) << "level " << k;
        EXPECT_GT(s.level_chunks_kept[size_t(k)], 0u) << "level " << k;
    }
    EXPECT_GT(s.lod_swaps, 0u);
    // Level 0 near the viewer is full detail: edits work as without LOD, and the swaps go on.
    ASSERT_TRUE(e.set_block({x, h + 1, 16}, 1));
    e.update();
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.stats().holes, 0u);
    EXPECT_EQ(e.get_block({x, h + 1, 16}), std::optional<vx::BlockId>(1));
}

TEST(Facade, LevelOfDetailSettingsAreChecked) {
    using Edit = void (*)(vx::StreamingDesc&);
    for (Edit bad : std::initializer_list<Edit>{[](vx::StreamingDesc& d) { d.view_distance = -1; },
                     [](vx::StreamingDesc& d) { d.view_distance = 1 << 20; },
                     [](vx::StreamingDesc& d) { d.lod_ring = 0; },
                     [](vx::StreamingDesc& d) { d.lod_vertical_reach = -5; }}) {
        vx::EngineCreateInfo info = lod_info(vx::WorldSource::terrain(1));
        bad(info.streaming);
        auto e = vx::Engine::create(info);
        ASSERT_FALSE(e);
        EXPECT_FALSE(e.error().empty());
    }
    // A view distance within the full-detail radius is full detail only.
    vx::EngineCreateInfo info = lod_info(vx::WorldSource::terrain(1));
    info.streaming.view_distance = 64;
    auto e = vx::Engine::create(info);
    ASSERT_TRUE(e) << e.error();
    ASSERT_TRUE((*e)->set_viewer(viewer_at({0, 40, 0})));
    ASSERT_TRUE(settle(**e));
    EXPECT_EQ((*e)->stats().lod_top_level, 0);
    EXPECT_EQ((*e)->stats().holes, 0u);
}

namespace {

// Flat ground (stone below y = 0) with coarse chunks offered, or not, or thrown from.
class FlatGenerator final : public vx::Generator {
public:
    enum class Coarse { Offered, None, Throws };
    explicit FlatGenerator(Coarse coarse) : m_coarse(coarse) {}
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int y = 0; y < 32; ++y)
            if (o.y + y < 0)
                for (int z = 0; z < 32; ++z)
                    for (int x = 0; x < 32; ++x)
                        blocks[vx::chunk_index(x, y, z)] = 1;
    }
    bool generate_coarse(int level, vx::ChunkCoord c, std::span<vx::BlockId> cells) const override {
        ++coarse_calls;
        if (m_coarse == Coarse::Throws)
            throw std::runtime_error("coarse generator failed");
        if (m_coarse == Coarse::None)
            return false;
        const int64_t y0 = int64_t(c.y) * (int64_t(32) << level);
        for (int y = 0; y < 32; ++y)
            if (y0 + (int64_t(y) << level) < 0) // The cell holds a block below 0: solid.
                for (int z = 0; z < 32; ++z)
                    for (int x = 0; x < 32; ++x)
                        cells[vx::chunk_index(x, y, z)] = 1;
        return true;
    }
    int coarse_levels() const override { return m_coarse == Coarse::None ? 0 : 6; }
    mutable std::atomic<int> coarse_calls{0};

private:
    Coarse m_coarse;
};

} // namespace

// A game's generator: its coarse chunks reach the view distance; without them the levels stop at
// 2 (chunks built from blocks); one that throws is logged and built from blocks: no hole stays.
TEST(Facade, GameGeneratorCoarseChunksOfferedAbsentOrThrowing) {
    for (auto mode : {FlatGenerator::Coarse::Offered, FlatGenerator::Coarse::None, FlatGenerator::Coarse::Throws}) {
        auto gen = std::make_shared<FlatGenerator>(mode);
        vx::EngineCreateInfo info = lod_info(vx::WorldSource::custom(gen));
        info.streaming.view_distance = 420;
        auto engine = vx::Engine::create(info);
        ASSERT_TRUE(engine) << engine.error();
        vx::Engine& e = **engine;
        ASSERT_TRUE(e.set_viewer(viewer_at({5, 3, 5})));
        ASSERT_TRUE(settle(e));
        const vx::Stats s = e.stats();
        EXPECT_EQ(s.holes, 0u);
        if (mode == FlatGenerator::Coarse::None) {
            EXPECT_EQ(s.lod_top_level, 2) << "without coarse chunks the levels stop at 2";
        } else {
            EXPECT_GE(s.lod_top_level, 3);
            EXPECT_GT(gen->coarse_calls.load(), 0);
        }
        for (int k = 1; k <= s.lod_top_level; ++k)
            EXPECT_GT(s.level_chunks_drawn[size_t(k)], 0u) << "level " << k;
    }
}

// An edit followed at once by save() or shutdown(), with no frame between, reaches the coarse
// levels' records too: the flush carries their saves (LodStreamer::flush_edits). Before, only the
// block's own chunk was saved, and the next session's far view showed the world without it.
TEST(Facade, ShutdownRightAfterAnEditSavesTheCoarseLevels) {
    const std::string path = temp_path("lod_shutdown");
    const int64_t x = dry_column_x(16), h = vx::terrain_height(kSeed, x, 16);
    const vx::BlockPos high{x, h + 40, 16}; // In the air above the viewer: every level changes.
    int top = 0;
    {
        auto engine = vx::Engine::create(lod_info(vx::WorldSource::sqlite(path, kSeed)));
        ASSERT_TRUE(engine) << engine.error();
        vx::Engine& e = **engine;
        ASSERT_TRUE(e.set_viewer(viewer_at({x, h + 2, 16})));
        ASSERT_TRUE(settle(e));
        top = e.stats().lod_top_level;
        ASSERT_GE(top, 1);
        ASSERT_TRUE(e.set_block(high, 1));
        ASSERT_TRUE(e.shutdown());
    }
    vx::world::SqliteStoreCreateInfo info;
    info.path = path;
    auto store = vx::world::SqliteStore::open(info);
    ASSERT_TRUE(store) << store.error();
    const vx::world::BlockPos p(high.x, high.y, high.z);
    for (int k = 1; k <= top; ++k) {
        auto loaded = (*store)->load_lod(vx::world::lod_chunk_of(p, k));
        ASSERT_TRUE(loaded) << loaded.error();
        ASSERT_EQ(loaded->state, vx::world::LoadState::Present) << "level " << k;
        EXPECT_NE(loaded->chunk->get(vx::world::local_index(vx::world::lod_local_of(p, k))), vx::world::kAir)
            << "level " << k;
    }
}
