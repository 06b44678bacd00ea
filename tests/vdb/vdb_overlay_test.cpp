// A VDB world that keeps its edits (VdbOverlayStore, WorldSource::vdb): edits survive reopening,
// unloading and kill -9; erases hide the file's chunk; the merged export equals the edited world
// block for block; an overlay is refused against another file and accepted on a copy; a damaged
// file is one line from Engine::create; temporary files are unique and never left behind.
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vx/vx.h>

#include "tests/engine/facade_test_util.h"
#include "tests/vdb/vdb_test_util.h"
#include "world/gen/terrain.h"
#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world/vdb/vdb_world.h"

namespace vx::vdb {
namespace {

using vx::test::settle;

using test::same_blocks;
using test::TempDir;
using world::Chunk;
using world::ChunkCoord;
using world::LoadState;

// 4 x 2 x 4 chunks of terrain (seed 6): mixed chunks, uniform rock and air.
world::World terrain_world() {
    const world::TerrainGenerator gen(6);
    world::World w;
    for (int y = -1; y <= 0; ++y)
        for (int z = -2; z < 2; ++z)
            for (int x = -2; x < 2; ++x)
                w.put_chunk(ChunkCoord(x, y, z), gen.generate(ChunkCoord(x, y, z)));
    return w;
}

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// Files in `dir` whose name holds ".tmp-" (a temporary left behind).
int temporaries(const TempDir& dir) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        n += e.path().filename().string().find(".tmp-") != std::string::npos;
    return n;
}

Chunk edited(const Chunk& c, int index, world::BlockId id) {
    Chunk out = c;
    out.set(index, id);
    return out;
}

TEST(VdbOverlay, EditsPersistErasesHideTheFileAndTheFileIsNeverWritten) {
    TempDir dir;
    const std::string path = dir.file("w.vdb");
    const world::World src = terrain_world();
    ASSERT_TRUE(export_vdb(src, path));
    const std::string before = read_bytes(path);
    const ChunkCoord a(0, -1, 0), b(1, -1, 1), untouched(-2, 0, -2), outside(9, 9, 9);
    const Chunk a_new = edited(*src.find_chunk(a), 100, 7);
    {
        auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = false, .read = {}});
        ASSERT_TRUE(store) << store.error();
        EXPECT_FALSE((*store)->read_only());
        ASSERT_TRUE((*store)->save(a, a_new));
        ASSERT_TRUE((*store)->erase(b));
        ASSERT_TRUE((*store)->save(outside, Chunk(3)));
        // Read back before the commit, then made durable.
        EXPECT_TRUE(*(*store)->load(a)->chunk == a_new);
        ASSERT_TRUE((*store)->flush());
        // 32 file chunks + 1 outside the file (b is stored as air, still one coordinate).
        EXPECT_EQ(*(*store)->count(), src.chunk_count() + 1);
    }
    auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = false, .read = {}});
    ASSERT_TRUE(store) << store.error();
    auto la = (*store)->load(a), lb = (*store)->load(b), lu = (*store)->load(untouched), lo = (*store)->load(outside);
    ASSERT_TRUE(la && lb && lu && lo);
    ASSERT_EQ(la->state, LoadState::Present);
    EXPECT_TRUE(*la->chunk == a_new);
    ASSERT_EQ(lb->state, LoadState::Present);
    EXPECT_TRUE(lb->chunk->is_empty()); // The erase hides the file's chunk.
    ASSERT_EQ(lu->state, LoadState::Present);
    EXPECT_TRUE(*lu->chunk == *src.find_chunk(untouched));
    ASSERT_EQ(lo->state, LoadState::Present);
    EXPECT_TRUE(*lo->chunk == Chunk(3));
    EXPECT_EQ((*store)->load(ChunkCoord(50, 0, 0))->state, LoadState::Absent);
    EXPECT_EQ(read_bytes(path), before);
    EXPECT_TRUE(std::filesystem::exists(path + ".edits.sqlite"));
}

// Coarse levels: a bare VDB keeps none (the ChunkStore defaults); an overlay keeps them in its
// store, the VDB file untouched.
TEST(VdbOverlay, CoarseLevelsLiveInTheOverlay) {
    TempDir dir;
    const std::string path = dir.file("w.vdb");
    ASSERT_TRUE(export_vdb(terrain_world(), path));
    const std::string before = read_bytes(path);
    const world::LodCoord c{2, ChunkCoord(-1, 0, 0)}, mark{3, ChunkCoord(-1, 0, 0)};
    {
        auto bare = VdbStore::open(path);
        ASSERT_TRUE(bare) << bare.error();
        EXPECT_FALSE((*bare)->supports_lod());
        EXPECT_EQ((*bare)->load_lod(c)->state, LoadState::Absent);
        EXPECT_FALSE((*bare)->save_lod(c, Chunk(4)).ok());
        EXPECT_TRUE((*bare)->list_lod_dirty()->empty());
    }
    {
        auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = false, .read = {}});
        ASSERT_TRUE(store) << store.error();
        EXPECT_TRUE((*store)->supports_lod());
        EXPECT_EQ((*store)->load_lod(c)->state, LoadState::Absent);
        ASSERT_TRUE((*store)->save_lod(c, Chunk(4)));
        ASSERT_TRUE((*store)->mark_lod_dirty(std::span(&mark, 1)));
        ASSERT_TRUE((*store)->flush());
    }
    auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = true, .read = {}});
    ASSERT_TRUE(store) << store.error();
    auto l = (*store)->load_lod(c);
    ASSERT_TRUE(l && l->state == LoadState::Present);
    EXPECT_TRUE(*l->chunk == Chunk(4));
    EXPECT_EQ((*store)->list_lod_coords()->size(), 1u);
    ASSERT_EQ((*store)->list_lod_dirty()->size(), 1u);
    EXPECT_EQ((*store)->list_lod_dirty()->front(), mark);
    EXPECT_EQ(read_bytes(path), before);
}

TEST(VdbOverlay, RefusedAgainstAnotherFileAcceptedOnACopy) {
    TempDir dir;
    const std::string path = dir.file("a.vdb"), other = dir.file("b.vdb"), copy = dir.file("copy.vdb");
    const world::World src = terrain_world();
    ASSERT_TRUE(export_vdb(src, path));
    world::World changed = src;
    changed.set_block({0, 0, 0}, 5);
    ASSERT_TRUE(export_vdb(changed, other));
    const std::string overlay = path + ".edits.sqlite";
    const Chunk a_new = edited(*src.find_chunk(ChunkCoord(0, -1, 0)), 5, 9);
    {
        auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = false, .read = {}});
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->save(ChunkCoord(0, -1, 0), a_new));
        ASSERT_TRUE((*store)->flush());
    }
    auto refused =
        VdbOverlayStore::open({.vdb_path = other, .overlay = overlay, .read_only = false, .read = {}});
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("another VDB file"), std::string::npos) << refused.error();
    EXPECT_NE(refused.error().find(other), std::string::npos) << refused.error();
    EXPECT_EQ(refused.error().find('\n'), std::string::npos) << refused.error();
    // The same bytes under another name and time: the same world.
    std::this_thread::sleep_for(std::chrono::milliseconds(20)); // A later mtime on coarse clocks.
    std::filesystem::copy_file(path, copy);
    auto accepted =
        VdbOverlayStore::open({.vdb_path = copy, .overlay = overlay, .read_only = false, .read = {}});
    ASSERT_TRUE(accepted) << accepted.error();
    EXPECT_TRUE(*(*accepted)->load(ChunkCoord(0, -1, 0))->chunk == a_new);
}

TEST(VdbOverlay, MergedExportEqualsTheEditedWorld) {
    TempDir dir;
    const std::string path = dir.file("w.vdb"), out = dir.file("merged.vdb");
    world::World expected = terrain_world();
    ASSERT_TRUE(export_vdb(expected, path));
    {
        auto store = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = false, .read = {}});
        ASSERT_TRUE(store) << store.error();
        // Edits in a mixed chunk, one uniform chunk replaced, one erased, one chunk beyond the file.
        const ChunkCoord mixed(1, -1, -1), uniform(-2, -1, -2), gone(0, 0, 0), beyond(5, 0, 5);
        const Chunk m = edited(*expected.find_chunk(mixed), 4000, 11);
        ASSERT_TRUE((*store)->save(mixed, m));
        ASSERT_TRUE((*store)->save(uniform, Chunk(4)));
        ASSERT_TRUE((*store)->erase(gone));
        ASSERT_TRUE((*store)->save(beyond, edited(Chunk(), 0, 2)));
        ASSERT_TRUE((*store)->flush());
        expected.put_chunk(mixed, m);
        expected.put_chunk(uniform, Chunk(4));
        expected.remove_chunk(gone);
        expected.put_chunk(beyond, edited(Chunk(), 0, 2));
    }
    auto merged = VdbOverlayStore::open({.vdb_path = path, .overlay = {}, .read_only = true, .read = {}});
    ASSERT_TRUE(merged) << merged.error();
    EXPECT_TRUE((*merged)->read_only());
    ASSERT_TRUE(export_store_vdb(**merged, (*merged)->registry(), out));
    Result<world::World> back = import_world_vdb(out);
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(same_blocks(*back, expected));
    EXPECT_EQ(back->registry().size(), expected.registry().size());
    EXPECT_EQ(temporaries(dir), 0);
}

TEST(VdbTempFiles, UniqueExclusiveAndNeverLeftBehind) {
    TempDir dir;
    const std::string base = dir.file("x.vdb");
    Result<std::string> one = detail::create_temp_beside(base), two = detail::create_temp_beside(base);
    ASSERT_TRUE(one && two);
    EXPECT_NE(*one, *two);
    EXPECT_TRUE(std::filesystem::exists(*one) && std::filesystem::exists(*two));
    EXPECT_EQ(one->rfind(base + ".tmp-", 0), 0u) << *one;
    std::filesystem::remove(*one);
    std::filesystem::remove(*two);
    // An export into a folder that cannot take the temporary fails with one line and writes nothing.
    const std::string missing = dir.file("no/such/dir/w.vdb");
    Status s = export_vdb(terrain_world(), missing);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("temporary"), std::string::npos) << s.error();
    EXPECT_EQ(s.error().find('\n'), std::string::npos);
    // A successful export leaves only its file.
    ASSERT_TRUE(export_vdb(terrain_world(), base));
    EXPECT_EQ(temporaries(dir), 0);
    // An output path that is a folder: the export is refused before it writes; the message says
    // why (it once said "Success": the temporary's removal had reset the error first), nothing is
    // left behind.
    const std::string folder = dir.file("folder.vdb");
    std::filesystem::create_directory(folder);
    s = export_vdb(terrain_world(), folder);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find(std::make_error_code(std::errc::is_a_directory).message()), std::string::npos)
        << s.error();
    EXPECT_EQ(s.error().find("Success"), std::string::npos) << s.error();
    EXPECT_TRUE(std::filesystem::is_directory(folder));
    EXPECT_EQ(temporaries(dir), 0);
}

// ---- through the facade ----

vx::EngineCreateInfo small_info(vx::WorldSource source) {
    vx::EngineCreateInfo info;
    info.world = std::move(source);
    info.streaming.view_radius = 2;
    info.streaming.view_radius_vertical = 1;
    info.streaming.unload_margin = 0;
    info.streaming.unload_delay_s = 0.0;
    info.streaming.worker_threads = 2;
    return info;
}

vx::Viewer viewer_at(vx::BlockPos block) {
    vx::Viewer v;
    v.block = block;
    v.forward = {1, -0.2, 0};
    return v;
}

// A stone floor at y = -1 over x, z in [-3, 40) and one gold-ish block (id 8) at (5, 0, 5).
std::string floor_vdb(const TempDir& dir) {
    world::World src;
    for (int64_t x = -3; x < 40; ++x)
        for (int64_t z = -3; z < 40; ++z)
            src.set_block({x, -1, z}, 1);
    src.set_block({5, 0, 5}, 8);
    const std::string path = dir.file("floor.vdb");
    EXPECT_TRUE(export_vdb(src, path));
    return path;
}

TEST(VdbOverlayFacade, EditsSurviveUnloadSaveAndReopen) {
    TempDir dir;
    const std::string path = floor_vdb(dir);
    const vx::BlockPos p{6, 0, 6}, q{5, 0, 5};
    {
        auto engine = vx::Engine::create(small_info(vx::WorldSource::vdb(path)));
        ASSERT_TRUE(engine) << engine.error();
        vx::Engine& e = **engine;
        ASSERT_TRUE(e.set_viewer(viewer_at({4, 4, 4})));
        ASSERT_TRUE(settle(e));
        ASSERT_TRUE(e.set_block(p, 2));
        ASSERT_TRUE(e.set_block(q, vx::kAir));
        // 3,000 blocks away the edited chunk unloads (saved on the way out), then comes back.
        ASSERT_TRUE(e.set_viewer(viewer_at({3004, 4, 4})));
        ASSERT_TRUE(settle(e));
        EXPECT_EQ(e.get_block(p), std::nullopt);
        ASSERT_TRUE(e.set_viewer(viewer_at({4, 4, 4})));
        ASSERT_TRUE(settle(e));
        EXPECT_EQ(e.get_block(p), std::optional<vx::BlockId>(2));
        EXPECT_EQ(e.get_block(q), std::optional<vx::BlockId>(vx::kAir));
        ASSERT_TRUE(e.set_block({7, 0, 7}, 3));
        auto ticket = e.save();
        ASSERT_TRUE(ticket) << ticket.error();
        EXPECT_TRUE(e.wait(*ticket));
        EXPECT_TRUE(e.shutdown());
    }
    auto engine = vx::Engine::create(small_info(vx::WorldSource::vdb(path)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 4, 4})));
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.get_block(p), std::optional<vx::BlockId>(2));
    EXPECT_EQ(e.get_block(q), std::optional<vx::BlockId>(vx::kAir));
    EXPECT_EQ(e.get_block({7, 0, 7}), std::optional<vx::BlockId>(3));
    EXPECT_EQ(e.get_block({20, -1, 20}), std::optional<vx::BlockId>(1)); // From the file.
    EXPECT_TRUE(e.shutdown());
}

// The overlay stores block ids: reopening with other blocks is refused (appending is fine).
TEST(VdbOverlayFacade, OtherBlocksAreRefused) {
    TempDir dir;
    const std::string path = floor_vdb(dir);
    {
        auto engine = vx::Engine::create(small_info(vx::WorldSource::vdb(path)));
        ASSERT_TRUE(engine) << engine.error();
        EXPECT_TRUE((*engine)->shutdown());
    }
    vx::EngineCreateInfo info = small_info(vx::WorldSource::vdb(path));
    info.blocks = vx::default_blocks();
    std::swap(info.blocks[0], info.blocks[1]);
    auto refused = vx::Engine::create(info);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("other blocks"), std::string::npos) << refused.error();
    info.blocks = vx::default_blocks();
    info.blocks.push_back({"extra", glm::vec3(1.f), 0.f, glm::vec3(0.f), true});
    auto appended = vx::Engine::create(info);
    ASSERT_TRUE(appended) << appended.error();
    EXPECT_TRUE((*appended)->shutdown());
    info.world.read_only = true; // No overlay: nothing to keep consistent.
    std::swap(info.blocks[0], info.blocks[1]);
    auto read_only = vx::Engine::create(info);
    EXPECT_TRUE(read_only) << read_only.error();
}

// The child edits, saves, reports the durable save through a pipe, edits again and waits to be
// killed. Exit codes name the step that failed. Never returns.
[[noreturn]] void edit_and_wait(const std::string& path, int ack_fd) {
    auto engine = vx::Engine::create(small_info(vx::WorldSource::vdb(path)));
    if (!engine)
        _exit(3);
    vx::Engine& e = **engine;
    if (!e.set_viewer(viewer_at({4, 4, 4})) || !settle(e) || !e.set_block({6, 0, 6}, 2) || !e.set_block({9, -1, 9}, vx::kAir))
        _exit(4);
    auto ticket = e.save();
    if (!ticket || !e.wait(*ticket))
        _exit(5);
    const char ack = 1;
    if (::write(ack_fd, &ack, 1) != 1)
        _exit(6);
    (void)e.set_block({10, 0, 10}, 4); // Not saved: may or may not survive.
    for (;;) {
        e.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

TEST(VdbOverlayFacade, SavedEditsSurviveKill9) {
    TempDir dir;
    const std::string path = floor_vdb(dir);
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(fds[0]);
        edit_and_wait(path, fds[1]);
    }
    ::close(fds[1]);
    char ack = 0;
    const ssize_t n = ::read(fds[0], &ack, 1); // Blocks until the save is durable or the child dies.
    ::close(fds[0]);
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_EQ(n, 1) << "the child failed before its save was durable (exit " << WEXITSTATUS(status) << ")";
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

    auto engine = vx::Engine::create(small_info(vx::WorldSource::vdb(path)));
    ASSERT_TRUE(engine) << engine.error();
    vx::Engine& e = **engine;
    ASSERT_TRUE(e.set_viewer(viewer_at({4, 4, 4})));
    ASSERT_TRUE(settle(e));
    EXPECT_EQ(e.get_block({6, 0, 6}), std::optional<vx::BlockId>(2));
    EXPECT_EQ(e.get_block({9, -1, 9}), std::optional<vx::BlockId>(vx::kAir));
    EXPECT_EQ(e.get_block({20, -1, 20}), std::optional<vx::BlockId>(1));
    EXPECT_TRUE(e.shutdown());
}

// Issue 17's case: an uncompressed export with bytes of its tree overwritten. Through the facade
// the file is read in the isolated child (4 GiB, 600 s caps: damage that makes OpenVDB allocate
// without bound or crash stays there, see vdb_fuzz_test.cpp), so create() gives one line, with
// the overlay and read-only alike.
TEST(VdbOverlayFacade, DamagedFileIsOneLineFromCreate) {
    TempDir dir;
    const std::string path = dir.file("damaged.vdb");
    VdbExportOptions o;
    o.compression = VdbCompression::None;
    ASSERT_TRUE(export_vdb(terrain_world(), path, o));
    std::string bytes = read_bytes(path);
    ASSERT_GT(bytes.size(), 4096u);
    // Four runs of 0xFF between 50% and 80% of the file: topology and voxel buffers (block ids
    // of -1, or sizes far too large).
    for (int k = 5; k <= 8; ++k)
        for (size_t i = 0; i < 16; ++i)
            bytes[bytes.size() * size_t(k) / 10 + i] = char(0xFF);
    write_bytes(path, bytes);
    for (const bool read_only : {false, true}) {
        vx::WorldSource source = vx::WorldSource::vdb(path);
        source.read_only = read_only;
        auto engine = vx::Engine::create(small_info(source));
        ASSERT_FALSE(engine) << "read_only " << read_only;
        EXPECT_NE(engine.error().find(path), std::string::npos) << engine.error();
        EXPECT_EQ(engine.error().find('\n'), std::string::npos) << engine.error();
    }
    EXPECT_EQ(read_bytes(path), bytes); // Never written.
}

} // namespace
} // namespace vx::vdb
