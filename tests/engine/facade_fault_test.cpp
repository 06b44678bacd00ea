// The facade <vx/vx.h> under a game's faults, without a GPU: a Generator that throws for some
// chunks (std and non-std exceptions), a game clock behind or ahead of the steady clock, and the
// log hook (engine messages reach it; a handler that throws takes nothing down), and an OS that
// refuses the engine's threads. Game time is a
// synthetic clock the test advances; waits are bounded by conditions, never by the machine.
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_test_util.h"
#include "thread_refusal.h"
#include "world/store/store_open.h"

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

std::string fault_world(const char* name) { return vx::test::temp_world_path("vx_facade_fault_test", name); }

// The game's clock: starts at steady now + `offset`, moves only when the test says.
struct GameClock {
    Clock::time_point t;
    explicit GameClock(Clock::duration offset) : t(Clock::now() + offset) {}
};

// Updates with game time advancing `step` a frame until the view is settled (true), or a very
// slow machine's limit passes (false).
bool settle_at(vx::Engine& e, GameClock& clock, Clock::duration step = 10ms) {
    const auto end = Clock::now() + std::chrono::minutes(3);
    while (Clock::now() < end) {
        clock.t += step;
        e.update(clock.t);
        if (e.settled())
            return true;
        std::this_thread::sleep_for(1ms);
    }
    return false;
}

// Collects the log while alive; restores stderr logging when it goes.
struct LogCapture {
    struct Line {
        vx::LogLevel level;
        std::string text;
    };
    std::mutex mutex;
    std::vector<Line> lines;
    LogCapture() {
        vx::set_log_handler([this](vx::LogLevel level, std::string_view text) {
            std::lock_guard lock(mutex);
            lines.push_back({level, std::string(text)});
        });
    }
    ~LogCapture() { vx::set_log_handler(nullptr); }
    // Error lines holding every one of `parts`.
    size_t count(std::initializer_list<std::string_view> parts) {
        std::lock_guard lock(mutex);
        size_t n = 0;
        for (const Line& l : lines) {
            bool all = l.level == vx::LogLevel::Error;
            for (std::string_view p : parts)
                all = all && l.text.find(p) != std::string::npos;
            n += all;
        }
        return n;
    }
};

constexpr vx::BlockId kRock = 1, kPost = 2;

// Rock below y = 0, a post every 8 blocks on y = 0..3. While `fail` is set it throws a
// std::runtime_error for chunk (1, 0, 0) and an int (not a std::exception) for (-1, 0, 0).
class FaultyGenerator final : public vx::Generator {
public:
    void generate(vx::ChunkCoord c, std::span<vx::BlockId> blocks) const override {
        const vx::BlockPos o = vx::chunk_origin(c);
        for (int z = 0; z < 32; ++z)
            for (int x = 0; x < 32; ++x) {
                if (((o.x + x) & 7) == 0 && ((o.z + z) & 7) == 0)
                    for (int y = 0; y < 4; ++y)
                        blocks[vx::chunk_index(x, y, z)] = kPost;
                // Half the chunk is filled when it throws: none of it may be used.
                if (fail.load() && c == vx::ChunkCoord(1, 0, 0) && z == 16)
                    throw std::runtime_error("no data for this chunk");
            }
        if (fail.load() && c == vx::ChunkCoord(-1, 0, 0))
            throw 42;
    }
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        if (c.y != 0)
            return c.y < 0 ? kRock : vx::kAir;
        return std::nullopt;
    }
    std::atomic<bool> fail{true};
};

vx::EngineCreateInfo small_info(vx::WorldSource source) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.blocks = {{"rock", {0.5f, 0.5f, 0.5f}}, {"post", {0.1f, 0.1f, 0.9f}}};
    info.streaming.view_radius = 2;
    info.streaming.view_radius_vertical = 1;
    info.streaming.unload_margin = 0;
    info.streaming.worker_threads = 2;
    return info;
}

vx::Viewer viewer_at(vx::BlockPos block) {
    vx::Viewer v;
    v.block = block;
    v.forward = {1, -0.2, 0};
    return v;
}

// The blocks the generator makes at p when it does not fail.
std::optional<vx::BlockId> expected(vx::BlockPos p) {
    if (p.y < 0)
        return kRock;
    return p.y < 4 && (p.x & 7) == 0 && (p.z & 7) == 0 ? kPost : vx::kAir;
}

// An engine on `gen` (failing; nothing stored) with its view around chunk (0, 0, 0) settled on
// `clock`, although two of its chunks cannot be generated; null if that went wrong.
std::unique_ptr<vx::Engine> settled_engine(std::shared_ptr<FaultyGenerator> gen, GameClock& clock) {
    auto engine = vx::Engine::create(small_info(vx::WorldSource::custom(std::move(gen))));
    if (!engine) {
        ADD_FAILURE() << engine.error();
        return nullptr;
    }
    EXPECT_TRUE((*engine)->set_viewer(viewer_at({4, 2, 4})));
    if (!settle_at(**engine, clock)) {
        ADD_FAILURE() << "the view did not settle";
        return nullptr;
    }
    EXPECT_EQ((*engine)->stats().chunks_generate_failed, 2u);
    return std::move(*engine);
}

// A settled engine on a failing generator, its log captured.
class FailingGenerator : public testing::Test {
protected:
    void SetUp() override {
        engine = settled_engine(gen, clock);
        ASSERT_TRUE(engine);
    }
    LogCapture log;
    std::shared_ptr<FaultyGenerator> gen = std::make_shared<FaultyGenerator>();
    GameClock clock{0s};
    std::unique_ptr<vx::Engine> engine;
};

TEST_F(FailingGenerator, OnlyItsChunksFail) {
    vx::Engine& e = *engine;
    vx::Stats st = e.stats();
    EXPECT_GE(st.generate_failures, 2u);
    // Every other chunk of the view is meshed, the failed ones' neighbours included (as if air).
    EXPECT_EQ(st.chunks_meshed + 2, st.chunks_in_view);
    EXPECT_EQ(st.chunks_queued, 0u);
    EXPECT_GE(log.count({"chunk 1,0,0", "no data for this chunk"}), 1u);
    EXPECT_GE(log.count({"chunk -1,0,0", "not a std::exception"}), 1u);

    // The failed chunks hold nothing (not the half the generator filled); the rest is right.
    EXPECT_EQ(e.get_block({32 + 8, 0, 8}), std::nullopt);
    EXPECT_EQ(e.get_block({-32 + 8, 0, 8}), std::nullopt);
    EXPECT_FALSE(e.set_block({32 + 8, 5, 8}, kRock));
    auto ray = e.raycast({0, 10, 8}, {0.5, 0.5, 0.5}, {1, 0, 0}, 100.0);
    ASSERT_TRUE(ray) << ray.error();
    EXPECT_EQ(ray->kind, vx::RayHit::Kind::Unloaded);
    EXPECT_EQ(ray->block, vx::BlockPos(32, 10, 8));
    for (vx::BlockPos p : {vx::BlockPos{8, 0, 8}, vx::BlockPos{9, 0, 8}, vx::BlockPos{64 + 16, 3, 16},
                           vx::BlockPos{8, -1, 40}, vx::BlockPos{32 + 8, 0, 32 + 8}, vx::BlockPos{-8, 40, 8}})
        EXPECT_EQ(e.get_block(p), expected(p)) << p.x << "," << p.y << "," << p.z;
    // Edits beside a failed chunk still work.
    ASSERT_TRUE(e.set_block({31, 5, 8}, kRock));
    EXPECT_EQ(e.get_block({31, 5, 8}), std::optional<vx::BlockId>(kRock));

    // The generator recovers: after the back-off (at most 60 s of game time) both chunks arrive
    // and the view is complete.
    gen->fail = false;
    const auto end = Clock::now() + std::chrono::minutes(3);
    clock.t += 61s;
    while (Clock::now() < end && !(e.settled() && e.stats().chunks_generate_failed == 0)) {
        clock.t += 10ms;
        e.update(clock.t);
        std::this_thread::sleep_for(1ms);
    }
    st = e.stats();
    EXPECT_EQ(st.chunks_generate_failed, 0u);
    EXPECT_EQ(st.chunks_meshed, st.chunks_in_view);
    for (vx::BlockPos p : {vx::BlockPos{32 + 8, 0, 8}, vx::BlockPos{32 + 8, 3, 24}, vx::BlockPos{32 + 9, 0, 8},
                           vx::BlockPos{-32 + 8, 1, 16}, vx::BlockPos{-32 + 8, 4, 16}})
        EXPECT_EQ(e.get_block(p), expected(p)) << p.x << "," << p.y << "," << p.z;
    EXPECT_EQ(e.get_block({31, 5, 8}), std::optional<vx::BlockId>(kRock)); // The edit stayed.
    EXPECT_TRUE(e.shutdown());
}

// A failed chunk the viewer leaves is dropped like any other (no longer counted); when the viewer
// comes back it is generated afresh, and its neighbours, meshed against air meanwhile, are meshed
// again with it.
TEST_F(FailingGenerator, FailedChunkIsDroppedWithTheViewAndGeneratedWhenBack) {
    vx::Engine& e = *engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4 + 32 * 20, 2, 4})));
    ASSERT_TRUE(settle_at(e, clock));
    clock.t += 4s; // Past the unload delay (3 s): the chunks left behind go.
    ASSERT_TRUE(settle_at(e, clock));
    EXPECT_EQ(e.stats().chunks_generate_failed, 0u);
    EXPECT_EQ(e.get_block({31, 0, 8}), std::nullopt);
    gen->fail = false;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 2, 4})));
    ASSERT_TRUE(settle_at(e, clock));
    const vx::Stats st = e.stats();
    EXPECT_EQ(st.chunks_generate_failed, 0u);
    EXPECT_EQ(st.chunks_meshed, st.chunks_in_view);
    EXPECT_EQ(e.get_block({32 + 8, 2, 8}), std::optional<vx::BlockId>(kPost));
    EXPECT_EQ(e.get_block({-32 + 8, 2, 8}), std::optional<vx::BlockId>(kPost));
    EXPECT_TRUE(e.shutdown());
}

// With levels of detail the coarse chunks over a failing chunk fail too (their blocks come from
// the same generator); roots among them stay holes until a retry works. settled() does not wait
// for them, as it does not for failed chunks without levels: it never became true, so the loading
// screen embedding.md shows looped forever.
TEST(FacadeFaults, LevelsOfDetailSettleAroundAFailingGenerator) {
    auto gen = std::make_shared<FaultyGenerator>();
    vx::EngineCreateInfo info = small_info(vx::WorldSource::custom(gen));
    info.streaming.view_distance = 400;
    info.streaming.lod_ring = 2;
    auto engine = vx::Engine::create(std::move(info));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    GameClock clock{0s};
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 2, 4})));
    ASSERT_TRUE(settle_at(e, clock));
    vx::Stats st = e.stats();
    EXPECT_EQ(st.chunks_generate_failed, 2u);
    EXPECT_GT(st.lod_top_level, 0);
    EXPECT_GT(st.holes, 0u); // Still reported: the game can show them.
    gen->fail = false; // Recovered: after the back-off (at most 60 s of game time) nothing is missing.
    clock.t += 61s;
    const auto end = Clock::now() + std::chrono::minutes(3);
    do {
        ASSERT_TRUE(settle_at(e, clock));
        st = e.stats();
    } while ((st.holes != 0 || st.chunks_generate_failed != 0) && Clock::now() < end);
    EXPECT_EQ(st.holes, 0u);
    EXPECT_EQ(st.chunks_generate_failed, 0u);
    EXPECT_TRUE(e.shutdown());
}

TEST(FacadeFaults, ThrowingLogHandlerTakesNothingDown) {
    struct Reset {
        ~Reset() { vx::set_log_handler(nullptr); }
    } reset; // Also when an assertion below returns early.
    vx::set_log_handler([](vx::LogLevel, std::string_view) { throw std::runtime_error("handler failed"); });
    GameClock clock(0s);
    testing::internal::CaptureStderr();
    std::unique_ptr<vx::Engine> engine = settled_engine(std::make_shared<FaultyGenerator>(), clock);
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_TRUE(engine);
    // The lines the handler threw for went to stderr instead.
    EXPECT_NE(err.find("vx error: chunk 1,0,0"), std::string::npos) << err;
    EXPECT_TRUE(engine->shutdown());
}

// The block at `p` as a second, read-only connection to the SQLite world sees it; nullopt while
// the chunk is not stored.
std::optional<vx::BlockId> stored_block(const std::string& path, vx::BlockPos p) {
    auto store = vx::world::open_store({.name = path, .read_only = true, .create = false, .listen = false});
    if (!store)
        return std::nullopt;
    auto load = (*store)->load(vx::chunk_of(p));
    if (!load || !load->chunk)
        return std::nullopt;
    return load->chunk->get(vx::world::local_of(p));
}

// A game clock `offset` from the steady clock: an edit is handed to the store save_delay_s of
// game time after it, not before, and reaches the database without save() or shutdown.
void check_save_delay_on_game_clock(Clock::duration offset) {
    const std::string path = fault_world(offset < 0s ? "behind" : "ahead");
    auto gen = std::make_shared<FaultyGenerator>();
    gen->fail = false;
    vx::EngineCreateInfo info = small_info(vx::WorldSource::sqlite(path, gen));
    info.streaming.save_delay_s = 1.0;
    auto engine = vx::Engine::create(info);
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 2, 4})));
    GameClock clock(offset);
    ASSERT_TRUE(settle_at(e, clock));
    const vx::BlockPos p{5, 6, 5};
    ASSERT_TRUE(e.set_block(p, kPost));
    const Clock::time_point edited = clock.t;
    EXPECT_EQ(e.stats().dirty_chunks, 1u);
    e.update(edited + 500ms); // Half the delay: not yet.
    EXPECT_EQ(e.stats().dirty_chunks, 1u);
    e.update(edited + 3s);
    EXPECT_EQ(e.stats().dirty_chunks, 0u);
    // The store commits what it was handed within its own bound (about a second of real time),
    // on ticks that update() queues every half second of game time.
    clock.t = edited + 3s;
    const auto end = Clock::now() + std::chrono::minutes(1);
    std::optional<vx::BlockId> stored;
    while (Clock::now() < end && (stored = stored_block(path, p)) != std::optional<vx::BlockId>(kPost)) {
        clock.t += 100ms;
        e.update(clock.t);
        std::this_thread::sleep_for(20ms);
    }
    EXPECT_EQ(stored, std::optional<vx::BlockId>(kPost));
    EXPECT_TRUE(e.shutdown());
}

// A stored world: a chunk missing from the store goes to the generator from the I/O thread; its
// failure is reported the same way, and nothing of it is ever written to the store.
TEST(FacadeFaults, ThrowingGeneratorInAStoredWorldStoresNothingOfItsChunk) {
    const std::string path = fault_world("throwing");
    auto engine = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, std::make_shared<FaultyGenerator>())));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 2, 4})));
    GameClock clock(0s);
    ASSERT_TRUE(settle_at(e, clock));
    EXPECT_EQ(e.stats().chunks_generate_failed, 2u);
    ASSERT_TRUE(e.set_block({31, 5, 8}, kPost)); // Beside a failed chunk.
    auto ticket = e.save();
    ASSERT_TRUE(ticket) << ticket.error();
    ASSERT_TRUE(e.wait(*ticket));
    EXPECT_TRUE(e.shutdown());
    EXPECT_EQ(stored_block(path, {31, 5, 8}), std::optional<vx::BlockId>(kPost));
    EXPECT_EQ(stored_block(path, {32 + 8, 0, 8}), std::nullopt);
    EXPECT_EQ(stored_block(path, {-32 + 8, 0, 8}), std::nullopt);
}

// A game's generator whose name() (or version()) throws: the exception once escaped
// Engine::create and terminated the program; now create reports it.
TEST(FacadeFaults, AGeneratorWhoseNameThrowsIsAnErrorFromCreate) {
    class Nameless final : public vx::Generator {
    public:
        explicit Nameless(bool version) : m_version(version) {}
        void generate(vx::ChunkCoord, std::span<vx::BlockId>) const override {}
        std::string_view name() const override {
            if (!m_version)
                throw std::runtime_error("no name today");
            return "nameless";
        }
        uint32_t version() const override {
            if (m_version)
                throw 7;
            return 1;
        }

    private:
        bool m_version;
    };
    for (const bool version : {false, true}) {
        const std::string path = fault_world(version ? "throwing_version" : "throwing_name");
        auto engine = vx::Engine::create(small_info(vx::WorldSource::sqlite(path, std::make_shared<Nameless>(version))));
        ASSERT_FALSE(engine);
        EXPECT_NE(engine.error().find("the game's generator name() or version() threw"), std::string::npos)
            << engine.error();
        if (!version) {
            EXPECT_NE(engine.error().find("no name today"), std::string::npos) << engine.error();
        }
    }
}

TEST(FacadeFaults, GameClockBehindSavesEdits) { check_save_delay_on_game_clock(-1h); }

TEST(FacadeFaults, GameClockAheadWaitsForSaveDelay) { check_save_delay_on_game_clock(1h); }

} // namespace

// The OS refuses the engine's threads (tests/engine/thread_refusal.h): create() says so and
// returns, with nothing to wait for; once threads start again, so does an engine. A stored
// world's file is left as it was (nothing was loaded or saved).
TEST(FacadeFaults, NoThreadsIsAnErrorFromCreate) {
    const std::string path = fault_world("no_threads");
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::sqlite(path, 5);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    info.streaming.worker_threads = 2;
    {
        vx::engine::test::RefuseThreads refuse;
        ASSERT_TRUE(refuse.ok()) << "could not set the default thread attributes";
        auto engine = vx::Engine::create(info);
        ASSERT_FALSE(engine);
        EXPECT_NE(engine.error().find("cannot start its worker threads"), std::string::npos) << engine.error();
        EXPECT_NE(engine.error().find("Resource temporarily unavailable"), std::string::npos) << engine.error();
    }
    auto engine = vx::Engine::create(info);
    ASSERT_TRUE(engine) << engine.error();
    vx::Viewer v;
    v.block = {0, vx::terrain_height(5, 0, 0) + 4, 0};
    ASSERT_TRUE((*engine)->set_viewer(v));
    ASSERT_TRUE(vx::test::settle(**engine));
    EXPECT_GT((*engine)->stats().chunks_meshed, 0u);
}
