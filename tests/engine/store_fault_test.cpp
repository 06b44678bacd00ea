// A store that fails and comes back (a disk that is away, a full volume): the streamer keeps the
// game running, a save made while it is away reports Failed, a chunk whose load fails is neither
// generated over nor lost, and once the store is back every edit is saved; nothing acknowledged as
// saved is lost. The failure is injected by a ChunkStore wrapper around a real SqliteStore.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <vx/log.h>

#include "engine/chunk_streamer.h"
#include "job_test_util.h"
#include "stream_test_util.h"
#include "thread_refusal.h"
#include "world/gen/terrain.h"
#include "world/store/sqlite_store.h"

using namespace vx;
using namespace vx::engine;
using namespace vx::world;
using Clock = std::chrono::steady_clock;
using vx::test::settle;

namespace {

// Passes every call to `inner` unless `away` is set: then commits (tick, flush) and loads fail as
// an unreachable disk would, and queued edits stay queued in `inner`. Called on the I/O lane;
// `away` is flipped by the test thread.
class FlakyStore final : public ChunkStore {
public:
    explicit FlakyStore(std::unique_ptr<ChunkStore> inner) : m_inner(std::move(inner)) {}
    std::atomic<bool> away{false};
    std::atomic<int> failed_calls{0};
    std::atomic<int> load_delay_ms{0}; // A slow disk: each load keeps the I/O lane this long.

    Result<ChunkLoad> load(ChunkCoord c) override {
        std::this_thread::sleep_for(std::chrono::milliseconds(load_delay_ms.load()));
        {
            std::lock_guard lock(m_loaded_mutex);
            m_loaded.push_back(c);
        }
        if (fail())
            return Error{"the disk is away (injected)"};
        return m_inner->load(c);
    }
    Status save(std::span<const ChunkWrite> batch) override { return m_inner->save(batch); }
    Status tick(Clock::time_point now) override { return fail() ? Status(Error{"the disk is away (injected)"}) : m_inner->tick(now); }
    Status flush() override { return fail() ? Status(Error{"the disk is away (injected)"}) : m_inner->flush(); }
    Result<bool> contains(ChunkCoord c) override { return m_inner->contains(c); }
    Result<uint64_t> count() override { return m_inner->count(); }
    Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override { return m_inner->for_each_coord(fn); }
    Result<std::optional<std::string>> get_meta(std::string_view key) override { return m_inner->get_meta(key); }
    Status set_meta(std::string_view key, std::string_view value) override { return m_inner->set_meta(key, value); }
    bool read_only() const override { return false; }
    size_t pending_edits() const override { return m_inner->pending_edits(); }
    // Thread-safe. How many loads asked for chunks within `r` (Chebyshev) of `c`.
    int loads_near(ChunkCoord c, int r) {
        std::lock_guard lock(m_loaded_mutex);
        int n = 0;
        for (ChunkCoord l : m_loaded) {
            const glm::ivec3 d = glm::abs(l - c);
            n += std::max({d.x, d.y, d.z}) <= r;
        }
        return n;
    }

private:
    std::mutex m_loaded_mutex;
    std::vector<ChunkCoord> m_loaded;
    bool fail() {
        if (!away.load())
            return false;
        failed_calls.fetch_add(1);
        return true;
    }
    std::unique_ptr<ChunkStore> m_inner;
};

// Collects the log's lines while alive (the handler runs on engine threads: under a lock).
struct LogLines {
    std::mutex mutex;
    std::vector<std::string> lines;
    LogLines() {
        vx::set_log_handler([this](vx::LogLevel, std::string_view line) {
            std::lock_guard lock(mutex);
            lines.emplace_back(line);
        });
    }
    ~LogLines() { vx::set_log_handler(nullptr); }
    size_t count(std::string_view part) {
        std::lock_guard lock(mutex);
        size_t n = 0;
        for (const std::string& l : lines)
            n += l.find(part) != std::string::npos;
        return n;
    }
};

struct NullSink : MeshSink {
    void on_mesh(ChunkCoord, const ChunkMesh&, std::span<const int>) override {}
    void on_unload(ChunkCoord) override {}
};

StreamingSettings settings() {
    StreamingSettings s;
    s.view_radius = 1;
    s.view_radius_vertical = 1;
    s.unload_margin = 0;
    s.unload_delay_s = 0.0;
    s.save_delay_s = 0.5;
    s.worker_count = 1;
    return s;
}

std::string temp_world(const char* name) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_store_fault_test";
    std::filesystem::create_directories(dir);
    const auto p = dir / (std::string(name) + ".db");
    for (const char* suffix : {"", "-wal", "-shm"})
        std::filesystem::remove(p.string() + suffix);
    return p.string();
}

} // namespace

TEST(StoreFaults, SavesWhileTheStoreIsAwayFailAndNothingIsLostWhenItComesBack) {
    const std::string path = temp_world("commit");
    const TerrainGenerator gen(5);
    auto opened = SqliteStore::open({path});
    ASSERT_TRUE(opened.ok()) << opened.error();
    FlakyStore store(std::move(*opened));
    NullSink sink;
    LogLines log;
    const glm::dvec3 pos(8.5, 60.5, 8.5);
    const BlockPos a{8, 60, 8}, b{9, 61, 8}, c{-20, 60, 8}; // Two chunks.
    {
        ChunkStreamer s(gen, &store, sink, settings());
        Clock::time_point now = Clock::now();
        ASSERT_TRUE(settle(s, pos, now));
        ASSERT_TRUE(s.set_block(a, 7).ok());
        const uint64_t durable = s.request_save();
        ASSERT_TRUE(s.wait_saved(durable).ok()); // Acknowledged: must survive everything below.

        store.away = true;
        ASSERT_TRUE(s.set_block(b, 7).ok());
        ASSERT_TRUE(s.set_block(c, 9).ok());
        const uint64_t failing = s.request_save();
        const Status failed = s.wait_saved(failing);
        ASSERT_FALSE(failed.ok());
        EXPECT_NE(failed.error().find("away"), std::string::npos) << failed.error();
        EXPECT_EQ(s.save_state(failing), SaveState::Failed);
        // The game goes on: updates keep running, background commits fail quietly, edits work.
        const auto limit = Clock::now() + std::chrono::minutes(3);
        while (store.failed_calls.load() < 4 && Clock::now() < limit) { // Ticks on the I/O lane.
            now += std::chrono::milliseconds(50);
            s.update(pos, glm::dvec3(0, 0, -1), now);
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        now += std::chrono::milliseconds(50);
        s.update(pos, glm::dvec3(0, 0, -1), now); // The last failure's report reaches the main thread.
        EXPECT_EQ(s.get_block(b), BlockId(7));
        EXPECT_GE(store.failed_calls.load(), 4);
        // One line for the outage, however many commits failed in it.
        EXPECT_EQ(log.count("store commit failed"), 1u);

        store.away = false;
        const uint64_t back = s.request_save();
        ASSERT_TRUE(s.wait_saved(back).ok());
        EXPECT_EQ(s.save_state(back), SaveState::Durable);
        const auto until = Clock::now() + std::chrono::minutes(3);
        while (log.count("store commits work again") == 0 && Clock::now() < until) {
            now += std::chrono::milliseconds(50); // The flush's success reaches the main thread.
            s.update(pos, glm::dvec3(0, 0, -1), now);
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        EXPECT_EQ(log.count("store commits work again"), 1u);
    }
    // Reopened from the file alone (for reading: the flaky store's writer is still open): every
    // edit, acknowledged before or saved after the outage.
    auto reopened = SqliteStore::open({.path = path, .read_only = true});
    ASSERT_TRUE(reopened.ok()) << reopened.error();
    for (const auto& [p, id] : {std::pair{a, BlockId(7)}, {b, BlockId(7)}, {c, BlockId(9)}}) {
        auto load = (*reopened)->load(chunk_of(p));
        ASSERT_TRUE(load.ok()) << load.error();
        ASSERT_EQ(load->state, LoadState::Present);
        EXPECT_EQ(load->chunk->get(local_of(p)), id);
    }
}

TEST(StoreFaults, AChunkWhoseLoadFailsIsNotGeneratedOverAndLoadsWhenTheStoreIsBack) {
    const std::string path = temp_world("load");
    const TerrainGenerator gen(5);
    const BlockPos far{8 + 32 * 6, 60, 8}; // In the view only after the move below.
    {
        // A stored edit in a chunk the viewer will reach later.
        auto opened = SqliteStore::open({path});
        ASSERT_TRUE(opened.ok()) << opened.error();
        Chunk chunk = gen.generate(chunk_of(far));
        chunk.set(local_of(far), 11);
        ASSERT_TRUE((*opened)->save(chunk_of(far), chunk).ok());
        ASSERT_TRUE((*opened)->flush().ok());
    }
    auto opened = SqliteStore::open({path});
    ASSERT_TRUE(opened.ok()) << opened.error();
    FlakyStore store(std::move(*opened));
    NullSink sink;
    ChunkStreamer s(gen, &store, sink, settings());
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, glm::dvec3(8.5, 60.5, 8.5), now));

    store.away = true;
    const glm::dvec3 there(far.x + 0.5, 60.5, 8.5);
    for (int i = 0; i < 100; ++i) { // The new view's loads all fail.
        now += std::chrono::milliseconds(50);
        s.update(there, glm::dvec3(0, 0, -1), now);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_FALSE(s.settled());
    // Not generated in place of the stored chunk: unknown until the store answers.
    EXPECT_EQ(s.world().find_chunk(chunk_of(far)), nullptr);

    store.away = false;
    ASSERT_TRUE(settle(s, there, now));
    EXPECT_EQ(s.get_block(far), BlockId(11)); // The stored edit, not the generator's block.
    ASSERT_TRUE(s.flush().ok());
}

namespace {

// A shared store in miniature: chunk `c` is stored (version `current`), everything else absent.
// A load of `c` reads the version current when it starts, opens `loading`, then waits for
// `released` (a load in flight); poll_changes hands out what `announce` queued. I/O lane and test
// thread: the version and the news under a lock.
class SharedFake final : public ChunkStore {
public:
    SharedFake(ChunkCoord c, Chunk first) : m_c(c), m_current(std::move(first)) {}
    engine::test::Gate loading, released;
    Result<ChunkLoad> load(ChunkCoord c) override {
        ChunkLoad out;
        if (c != m_c)
            return out;
        out.state = LoadState::Present;
        {
            std::lock_guard lock(m_mutex);
            out.chunk = m_current;
        }
        loading.open();
        released.wait();
        return out;
    }
    // Test thread: another process's commit of `c`, and its notification.
    void announce(Chunk next) {
        std::lock_guard lock(m_mutex);
        m_current = std::move(next);
        m_changed.push_back(m_c);
    }
    // Test thread: another process's commit of `c` that the store could not name (its pending
    // changes overflowed, or it missed notifications): it asks for a resync.
    void announce_resync(Chunk next) {
        std::lock_guard lock(m_mutex);
        m_current = std::move(next);
        m_resync = true;
    }
    bool poll_changes(std::vector<ChunkCoord>& out) override {
        std::lock_guard lock(m_mutex);
        out.insert(out.end(), m_changed.begin(), m_changed.end());
        m_changed.clear();
        return std::exchange(m_resync, false);
    }
    Status save(std::span<const ChunkWrite>) override { return {}; }
    Status tick(Clock::time_point) override { return {}; }
    Status flush() override { return {}; }
    Result<bool> contains(ChunkCoord c) override { return c == m_c; }
    Result<uint64_t> count() override { return uint64_t(1); }
    Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override {
        fn(m_c);
        return {};
    }
    Result<std::optional<std::string>> get_meta(std::string_view) override { return std::optional<std::string>{}; }
    Status set_meta(std::string_view, std::string_view) override { return {}; }
    bool read_only() const override { return false; }

private:
    const ChunkCoord m_c;
    std::mutex m_mutex;
    Chunk m_current;
    std::vector<ChunkCoord> m_changed;
    bool m_resync = false;
};

// Updates `s` around `eye` until block `p` is `id` (true), or a minute of real time passes.
bool update_until_block(ChunkStreamer& s, const glm::dvec3& eye, Clock::time_point& now, BlockPos p, BlockId id) {
    const auto limit = Clock::now() + std::chrono::minutes(1);
    while (s.get_block(p) != id && Clock::now() < limit) {
        now += std::chrono::milliseconds(16);
        s.update(eye, glm::dvec3(0, 0, -1), now);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return s.get_block(p) == id;
}

} // namespace

// Another process changes a chunk while this one's load of it is in flight: the load read the
// older version, and the notification came while the chunk was not yet present. It is read again
// once present, so the newer version shows. Before, the news was dropped (only present chunks
// were reloaded) and the chunk showed the older version until something else touched it.
TEST(StoreFaults, AChangeDuringALoadIsReadOnceTheChunkIsPresent) {
    const TerrainGenerator gen(5);
    const glm::dvec3 eye(8.5, 60.5, 8.5);
    const ChunkCoord c = chunk_of(BlockPos(8, 60, 8));
    SharedFake store(c, Chunk(1));
    NullSink sink;
    ChunkStreamer s(gen, &store, sink, settings());
    Clock::time_point now = Clock::now();
    s.update(eye, glm::dvec3(0, 0, -1), now);
    store.loading.wait(); // In flight: it has read version 1.
    store.announce(Chunk(2));
    for (int i = 0; i < 5; ++i) { // The news arrives while the chunk is still requested.
        now += std::chrono::milliseconds(16);
        s.update(eye, glm::dvec3(0, 0, -1), now);
    }
    ASSERT_EQ(s.world().find_chunk(c), nullptr);
    store.released.open();
    ASSERT_TRUE(settle(s, eye, now));
    EXPECT_TRUE(update_until_block(s, eye, now, BlockPos(8, 60, 8), 2)) << "the version committed during the load";
}

// A chunk outside the view, still drawn while its unload delay runs, whose neighbour another
// process changed: the neighbour's reload asks it for a new mesh (its border may show). It was not
// queued, wanting no mesh out there, so its old mesh stayed drawn and an edit of it never reached
// the sink (the edit path found no current mesh). Now it is kept current while drawn.
TEST(StoreFaults, AChunkStillDrawnOutsideTheViewIsKeptCurrent) {
    struct Counts : MeshSink {
        std::map<std::tuple<int, int, int>, int> meshes;
        void on_mesh(ChunkCoord c, const ChunkMesh&, std::span<const int>) override { ++meshes[{c.x, c.y, c.z}]; }
        void on_unload(ChunkCoord) override {}
        int of(ChunkCoord c) { return meshes[{c.x, c.y, c.z}]; }
    };
    const TerrainGenerator gen(5);
    const ChunkCoord c = chunk_of(BlockPos(8, 60, 8)), x = c + ChunkCoord(-1, 0, 0);
    SharedFake store(c, Chunk(1));
    store.released.open(); // Loads do not wait.
    Counts sink;
    StreamingSettings st = settings();
    st.unload_delay_s = 600.0; // x stays loaded and drawn after the viewer leaves.
    ChunkStreamer s(gen, &store, sink, st);
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, glm::dvec3(8.5, 60.5, 8.5), now));
    ASSERT_NE(s.mesh(x), nullptr);
    const glm::dvec3 away(8.5 + 64, 60.5, 8.5); // The view is chunks 1..3 in x: x (-1) is outside.
    ASSERT_TRUE(settle(s, away, now));
    ASSERT_NE(s.world().find_chunk(x), nullptr);
    const int before = sink.of(x);
    store.announce(Chunk(2));
    ASSERT_TRUE(update_until_block(s, away, now, BlockPos(8, 60, 8), 2));
    ASSERT_TRUE(settle(s, away, now));
    EXPECT_GT(sink.of(x), before) << "remeshed after its neighbour's reload";
    ASSERT_NE(s.mesh(x), nullptr);
    const BlockPos p = chunk_origin(x) + BlockPos(16, 16, 16);
    const int edited_before = sink.of(x);
    ASSERT_TRUE(s.set_block(p, s.get_block(p) == kAir ? BlockId(1) : kAir).ok());
    EXPECT_GT(sink.of(x), edited_before) << "the edit reached the sink";
}

// The store cannot name what changed (its pending changes overflowed, or it missed notifications
// and forgot versions): poll_changes() asks for a resync, and every chunk held is read again, so
// the other process's commit shows although no coordinate was reported.
TEST(StoreFaults, AResyncReadsEveryHeldChunkAgain) {
    const TerrainGenerator gen(5);
    const glm::dvec3 eye(8.5, 60.5, 8.5);
    const ChunkCoord c = chunk_of(BlockPos(8, 60, 8));
    SharedFake store(c, Chunk(1));
    store.released.open();
    NullSink sink;
    ChunkStreamer s(gen, &store, sink, settings());
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, eye, now));
    ASSERT_EQ(s.get_block(BlockPos(8, 60, 8)), BlockId(1));
    store.announce_resync(Chunk(2));
    EXPECT_TRUE(update_until_block(s, eye, now, BlockPos(8, 60, 8), 2)) << "reloaded on the resync";
}

// A save requested but not waited for, then the streamer destroyed while the I/O lane is still
// busy with loads: the queued saves and their flush run before the jobs stop. They were dropped
// unrun (the ticket Failed "flush cancelled", the edit gone from the store) because the
// destructor took "handed to the I/O lane" for "handed to the store".
TEST(StoreFaults, DestroyingTheStreamerRunsASaveStillQueued) {
    const std::string path = temp_world("queued_save");
    const TerrainGenerator gen(5);
    auto opened = SqliteStore::open({path});
    ASSERT_TRUE(opened.ok()) << opened.error();
    FlakyStore store(std::move(*opened));
    NullSink sink;
    const BlockPos edit{8, 60, 8};
    uint64_t ticket = 0;
    std::shared_ptr<const SaveTracker> tracker;
    {
        ChunkStreamer s(gen, &store, sink, settings());
        Clock::time_point now = Clock::now();
        ASSERT_TRUE(settle(s, glm::dvec3(8.5, 60.5, 8.5), now));
        ASSERT_TRUE(s.set_block(edit, 7).ok());
        // A teleport queues 125 loads (the loaded ring, 5³) of 5 ms each ahead of the save.
        store.load_delay_ms = 5;
        s.update(glm::dvec3(8.5 + 32 * 100, 60.5, 8.5), glm::dvec3(0, 0, -1), now + std::chrono::milliseconds(16));
        ticket = s.request_save();
        tracker = s.save_tracker();
    }
    EXPECT_EQ(tracker->state(ticket), SaveState::Durable) << tracker->last_error();
    auto reopened = SqliteStore::open({.path = path, .read_only = true});
    ASSERT_TRUE(reopened.ok()) << reopened.error();
    auto load = (*reopened)->load(chunk_of(edit));
    ASSERT_TRUE(load.ok()) << load.error();
    ASSERT_EQ(load->state, LoadState::Present);
    EXPECT_EQ(load->chunk->get(local_of(edit)), BlockId(7));
}

// Teleports through places not loaded yet: their queued loads are cancelled once the viewer is
// gone, not read in the FIFO I/O lane ahead of the loads of where it stays. With the unload
// delay they stayed: every one of the 125 loads of the place passed through was read.
TEST(StoreFaults, TeleportingAwayCancelsLoadsNotStarted) {
    const std::string path = temp_world("teleport");
    const TerrainGenerator gen(5);
    auto opened = SqliteStore::open({path});
    ASSERT_TRUE(opened.ok()) << opened.error();
    FlakyStore store(std::move(*opened));
    NullSink sink;
    StreamingSettings st = settings();
    st.unload_delay_s = 30.0; // Far longer than the test: a drop is never the delay's doing.
    ChunkStreamer s(gen, &store, sink, st);
    Clock::time_point now = Clock::now();
    ASSERT_TRUE(settle(s, glm::dvec3(8.5, 60.5, 8.5), now));
    store.load_delay_ms = 5;
    const glm::dvec3 passed(8.5 + 32 * 100, 60.5, 8.5), stay(8.5 - 32 * 100, 60.5, 8.5);
    s.update(passed, glm::dvec3(0, 0, -1), now += std::chrono::milliseconds(16)); // 5³ loads queued.
    s.update(stay, glm::dvec3(0, 0, -1), now += std::chrono::milliseconds(16));
    store.load_delay_ms = 0;
    ASSERT_TRUE(settle(s, stay, now));
    // The loads already running when the viewer left (one, or a few on a slow machine) are read.
    EXPECT_LT(store.loads_near(ChunkCoord(100, 1, 0), 2), 60); // The chunk of `passed`, and its ring.
    EXPECT_EQ(s.metrics().pending_data, 0u);
}

// The OS refuses every thread (thread_refusal.h): the streamer's job system cannot run, so a
// save says so at once instead of waiting for an I/O thread that does not exist, and destroying
// the streamer does not wait for one either.
TEST(StoreFaults, NoThreadsMakesASaveFailAtOnce) {
    const std::string path = temp_world("no_threads");
    const TerrainGenerator gen(5);
    auto opened = SqliteStore::open({path});
    ASSERT_TRUE(opened.ok()) << opened.error();
    NullSink sink;
    std::optional<ChunkStreamer> s;
    {
        vx::engine::test::RefuseThreads refuse;
        ASSERT_TRUE(refuse.ok()) << "could not set the default thread attributes";
        s.emplace(gen, opened->get(), sink, settings());
    }
    ASSERT_FALSE(s->jobs().start_error().empty());
    const Status saved = s->wait_saved(s->request_save());
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.error().find("no thread to save on"), std::string::npos) << saved.error();
    EXPECT_FALSE(s->flush().ok());
    s.reset();
}
