// The streaming VDB writer and reader (vdb_stream.h) against OpenVDB: files the writer makes read
// back through OpenVDB block for block, and their tree bytes equal OpenVDB's for the same world;
// files OpenVDB writes read back through the streaming reader; a VDB world plus its overlay
// exports merged; damaged files give one line.
#include <algorithm>
#include <array>
#include <csignal>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/vdb/vdb_openvdb_writer.h"
#include "tests/vdb/vdb_test_files.h"
#include "tests/vdb/vdb_test_util.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world/vdb/vdb_stream.h"
#include "world/vdb/vdb_world.h"

namespace vx::vdb {
namespace {

using test::same_blocks;
using test::TempDir;
using world::BlockId;
using world::BlockPos;
using world::Chunk;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

Chunk mixed_chunk(std::mt19937& rng) {
    std::vector<BlockId> ids(kChunkVolume, world::kAir);
    const int density = 1 + int(rng() % 4); // 1 in 1..4 blocks solid; some 8³ slots full.
    for (int i = 0; i < kChunkVolume; ++i)
        if (rng() % unsigned(density) == 0)
            ids[size_t(i)] = BlockId(1 + rng() % 11);
    const BlockId fill = BlockId(1 + rng() % 11);
    for (int z = 0; z < 8; ++z)
        for (int y = 8; y < 16; ++y)
            for (int x = 0; x < 8; ++x)
                ids[size_t(world::local_index(x, y, z))] = fill;
    return Chunk::from_dense(ids);
}

// Mixed and uniform chunks around the origin (negative coordinates included), a 4³ block of one
// uniform id filling one Internal4 node (pruned to a tile of its parent), and chunks far apart in
// other Internal5 nodes and root children.
world::World varied_world(uint32_t seed) {
    std::mt19937 rng(seed);
    world::World w;
    for (int i = 0; i < 40; ++i) {
        const ChunkCoord c(int(rng() % 8) - 4, int(rng() % 6) - 3, int(rng() % 8) - 4);
        if (rng() % 3 == 0)
            w.put_chunk(c, Chunk(BlockId(1 + rng() % 11)));
        else
            w.put_chunk(c, mixed_chunk(rng));
    }
    for (int i = 0; i < 64; ++i) // Node (2, 0, 0) in Internal4 units: chunks (8..11, 0..3, 0..3).
        w.put_chunk(ChunkCoord(8 + i % 4, (i / 4) % 4, i / 16), Chunk(BlockId(4)));
    for (const ChunkCoord far : {ChunkCoord(200, 1, -300), ChunkCoord(-(1 << 20), 5, 1 << 19),
                                 ChunkCoord(1 << 25, -(1 << 25), 3)})
        w.put_chunk(far, mixed_chunk(rng));
    w.put_chunk(ChunkCoord(-1000, -1000, -1000), Chunk(BlockId(2)));
    return w;
}

// `w` clipped to `box`.
world::World boxed(const world::World& w, const BlockBox& box) {
    world::World out(w.registry());
    w.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        for (int i = 0; i < kChunkVolume; ++i) {
            const BlockPos p = world::chunk_origin(c) + BlockPos(i & 31, (i >> 5) & 31, i >> 10);
            if (box.contains(p) && chunk.get(i) != world::kAir)
                out.set_block(p, chunk.get(i));
        }
    });
    return out;
}

// Everything the streaming reader hands out, checking file order on the way.
Result<world::World> stream_read(const std::string& path, const VdbStreamReadOptions& options = {}) {
    auto reader = VdbStreamReader::open(path, options);
    if (!reader)
        return Error{reader.error()};
    world::World w((*reader)->registry());
    std::vector<std::pair<ChunkCoord, Chunk>> node;
    std::optional<ChunkCoord> last;
    for (;;) {
        Result<bool> more = (*reader)->next(node);
        if (!more)
            return Error{more.error()};
        if (!*more)
            return w;
        for (auto& [c, chunk] : node) {
            EXPECT_TRUE(!last || file_order_less(*last, c)) << c.x << " " << c.y << " " << c.z;
            EXPECT_EQ(node_of(c), node_of(node[0].first));
            last = c;
            w.put_chunk(c, std::move(chunk));
        }
    }
}

// The bytes from the transform on: topology and leaf values, no metadata.
std::string tree_bytes(const std::string& path) {
    const std::string b = read_bytes(path);
    const size_t at = b.find("UniformScaleTranslateMap");
    return at == std::string::npos ? std::string() : b.substr(at);
}

TEST(VdbStream, WriterMatchesOpenVdbAndReadsBack) {
    TempDir dir;
    for (uint32_t seed : {1u, 2u}) {
        const world::World w = varied_world(seed);
        for (const VdbCompression comp : {VdbCompression::Zip, VdbCompression::None}) {
            for (const bool with_box : {false, true}) {
                VdbExportOptions o;
                o.compression = comp;
                if (with_box)
                    o.box = BlockBox{BlockPos(-70, -40, -100), BlockPos(300, 45, 17)};
                const std::string ours = dir.file("ours.vdb"), theirs = dir.file("theirs.vdb");
                ASSERT_TRUE(export_vdb(w, ours, o));
                ASSERT_TRUE(test::write_world_openvdb(w, theirs, o));
                const world::World expect = with_box ? boxed(w, *o.box) : w;
                // OpenVDB reads ours; our reader reads both.
                Result<world::World> back = import_world_vdb(ours);
                ASSERT_TRUE(back) << back.error();
                EXPECT_TRUE(same_blocks(expect, *back));
                for (const std::string& f : {ours, theirs}) {
                    Result<world::World> streamed = stream_read(f);
                    ASSERT_TRUE(streamed) << streamed.error();
                    EXPECT_TRUE(same_blocks(expect, *streamed));
                    EXPECT_EQ(streamed->registry().size(), w.registry().size());
                }
                // Same tree, byte for byte; same metadata (OpenVDB's optional delayed-load index is
                // in its file only: OpenVDB's reader drops it from the grid's metadata).
                const std::string a = tree_bytes(ours), b = tree_bytes(theirs);
                ASSERT_FALSE(a.empty());
                EXPECT_TRUE(a == b) << "seed " << seed << ": " << a.size() << " vs " << b.size() << " bytes";
                auto meta_a = test::grid_meta_openvdb(ours), meta_b = test::grid_meta_openvdb(theirs);
                ASSERT_FALSE(meta_a.empty());
                EXPECT_EQ(read_bytes(ours).find("file_delayed_load"), std::string::npos);
                EXPECT_NE(read_bytes(theirs).find("file_delayed_load"), std::string::npos);
                EXPECT_EQ(meta_a, meta_b);
            }
        }
    }
}

TEST(VdbStream, EmptyWorldAndOutOfOrderChunks) {
    TempDir dir;
    const std::string ours = dir.file("empty.vdb"), theirs = dir.file("empty_ovdb.vdb");
    ASSERT_TRUE(export_vdb(world::World(), ours));
    ASSERT_TRUE(test::write_world_openvdb(world::World(), theirs));
    EXPECT_EQ(tree_bytes(ours), tree_bytes(theirs));
    EXPECT_EQ(test::grid_meta_openvdb(ours), test::grid_meta_openvdb(theirs));
    Result<world::World> back = stream_read(ours);
    ASSERT_TRUE(back) << back.error();
    EXPECT_EQ(back->chunk_count(), 0u);

    // The writer refuses chunks out of file order and leaves nothing behind.
    const std::string path = dir.file("order.vdb");
    {
        auto writer = VdbStreamWriter::create(path, world::BlockRegistry::default_registry(), {});
        ASSERT_TRUE(writer) << writer.error();
        ASSERT_TRUE((*writer)->add(ChunkCoord(4, 0, 0), Chunk(BlockId(1))));
        Status s = (*writer)->add(ChunkCoord(0, 0, 0), Chunk(BlockId(1)));
        ASSERT_FALSE(s);
        EXPECT_NE(s.error().find("order"), std::string::npos) << s.error();
        EXPECT_FALSE((*writer)->finish());
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        files += e.path().filename().string().find("order") != std::string::npos ? 1 : 0;
    EXPECT_EQ(files, 0u);
}

// A write that fails (the file-size limit stands in for a full disk) fails the export with one
// line, keeps the old file and leaves no temporary. In a forked child: the limit is per process.
TEST(VdbStream, WriteFailureKeepsTheOldFile) {
    TempDir dir;
    const std::string path = dir.file("keep.vdb");
    world::World small;
    small.set_block(BlockPos(1, 2, 3), 4);
    ASSERT_TRUE(export_vdb(small, path));
    const std::string before = read_bytes(path);
    const world::World big = varied_world(4); // About 1 MB of leaf values with compression none.
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN); // Writes past the limit fail with EFBIG instead.
        const rlimit limit{64 * 1024, 64 * 1024};
        ::setrlimit(RLIMIT_FSIZE, &limit);
        Status s = export_vdb(big, path, {std::nullopt, VdbCompression::None});
        const bool one_line = !s && s.error().find('\n') == std::string::npos &&
                              s.error().find("cannot write") != std::string::npos;
        ::_exit(s ? 1 : one_line ? 0 : 2);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "1: the export succeeded; 2: its error was not one 'cannot write' line";
    EXPECT_EQ(read_bytes(path), before);
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 1u);
}

size_t open_descriptors() {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd"))
        ++n;
    return n;
}

// Exports in one process (a game's, the bench loop) close every file they open: the root
// topology's scratch file once stayed open (and its space on disk, unlinked) after each export.
TEST(VdbStream, ExportsLeaveNoFileOpen) {
    TempDir dir;
    const std::string path = dir.file("many.vdb");
    const world::World w = varied_world(2);
    ASSERT_TRUE(export_vdb(w, path));
    const size_t before = open_descriptors();
    for (int i = 0; i < 20; ++i)
        ASSERT_TRUE(export_vdb(w, path));
    EXPECT_EQ(open_descriptors(), before);
}

// An export to a symbolic link replaces (or creates) the file the link names, keeping its mode,
// and keeps the link. One to a device is refused, and the device stays: the temporary's rename would have
// replaced it (as root, /dev/null itself).
TEST(VdbStream, ExportKeepsALinkAndRefusesADevice) {
    TempDir dir;
    world::World small;
    small.set_block(BlockPos(1, 2, 3), 4);
    ASSERT_TRUE(export_vdb(small, dir.file("end.vdb")));
    std::filesystem::create_symlink("end.vdb", dir.file("link.vdb"));
    std::filesystem::permissions(dir.file("end.vdb"), std::filesystem::perms(0640));
    small.set_block(BlockPos(5, 6, 7), 8);
    ASSERT_TRUE(export_vdb(small, dir.file("link.vdb")));
    EXPECT_TRUE(std::filesystem::is_symlink(dir.file("link.vdb")));
    EXPECT_EQ(std::filesystem::status(dir.file("end.vdb")).permissions(), std::filesystem::perms(0640));
    EXPECT_TRUE(read_bytes(dir.file("end.vdb")) == read_bytes(dir.file("link.vdb")));
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        files += e.is_regular_file() && !e.is_symlink() ? 1 : 0;
    EXPECT_EQ(files, 1u) << "a temporary was left";
    Result<world::World> back = import_world_vdb(dir.file("end.vdb"));
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_EQ(back->get_block(BlockPos(5, 6, 7)), 8);
    // A link to a file not made yet: the export creates that file, and the link stays.
    std::filesystem::create_symlink("later.vdb", dir.file("ahead.vdb"));
    ASSERT_TRUE(export_vdb(small, dir.file("ahead.vdb")));
    EXPECT_TRUE(std::filesystem::is_symlink(dir.file("ahead.vdb")));
    Result<world::World> later = import_world_vdb(dir.file("later.vdb"));
    ASSERT_TRUE(later.ok()) << later.error();
    EXPECT_EQ(later->get_block(BlockPos(5, 6, 7)), 8);

    if (!std::filesystem::exists("/dev/null"))
        GTEST_SKIP() << "no /dev/null here";
    const Status s = export_vdb(small, "/dev/null");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().find("not a regular file"), std::string::npos) << s.error();
    EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
}

TEST(VdbStream, ReaderExpandsRootTilesAndCapsThem) {
    TempDir dir;
    const std::string path = dir.file("root_tile.vdb");
    ASSERT_TRUE(test::write_root_tile_openvdb(path));
    auto reader = VdbStreamReader::open(path);
    ASSERT_TRUE(reader) << reader.error();
    std::vector<std::pair<ChunkCoord, Chunk>> node;
    uint64_t chunks = 0;
    std::optional<ChunkCoord> first, last;
    for (;;) {
        Result<bool> more = (*reader)->next(node);
        ASSERT_TRUE(more) << more.error();
        if (!*more)
            break;
        for (const auto& [c, chunk] : node) {
            if (!first)
                first = c;
            if (last) {
                ASSERT_TRUE(file_order_less(*last, c));
            }
            last = c;
            ++chunks;
            if (c.x >= 0) {
                ASSERT_TRUE(chunk.is_uniform() && chunk.uniform_id() == 3);
            }
        }
    }
    // The voxel at (-1, -1, -1) (chunk (-1, -1, -1), first in file order), then 128³ chunks.
    EXPECT_EQ(chunks, 1u + (uint64_t(1) << 21));
    EXPECT_EQ(*first, ChunkCoord(-1));
    EXPECT_EQ(*last, ChunkCoord(127));

    VdbStreamReadOptions small;
    small.max_tile_chunks = 1000;
    auto capped = VdbStreamReader::open(path, small);
    ASSERT_FALSE(capped);
    EXPECT_NE(capped.error().find("1000 chunks"), std::string::npos) << capped.error();
}

// 128³ chunks of one id fill an Internal5 node: the writer makes it a root tile, as OpenVDB's
// prune() does, with the same tree bytes as OpenVDB writes; the reader expands it again.
TEST(VdbStream, WholeInternal5OfOneIdBecomesARootTile) {
    TempDir dir;
    const std::string ours = dir.file("ours.vdb"), theirs = dir.file("theirs.vdb");
    ASSERT_TRUE(test::write_root_tile_openvdb(theirs));
    {
        auto writer = VdbStreamWriter::create(ours, world::BlockRegistry::default_registry(), {});
        ASSERT_TRUE(writer) << writer.error();
        Chunk corner;
        corner.set(31, 31, 31, 5); // Block (-1, -1, -1).
        ASSERT_TRUE((*writer)->add(ChunkCoord(-1), corner));
        const Chunk three(BlockId(3));
        for (int n = 0; n < 32768; ++n) { // Internal4 nodes of Internal5 (0, 0, 0), x major.
            const ChunkCoord node(n >> 10, (n >> 5) & 31, n & 31);
            for (int k = 0; k < 64; ++k)
                ASSERT_TRUE((*writer)->add(node * 4 + ChunkCoord(k >> 4, (k >> 2) & 3, k & 3), three));
        }
        ASSERT_TRUE((*writer)->finish());
    }
    // From the root on (our transform is a UniformScaleTranslateMap, 144 bytes; OpenVDB's default
    // a UniformScaleMap, 120 bytes).
    const std::string a = read_bytes(ours), b = read_bytes(theirs);
    const size_t at_a = a.find("UniformScaleTranslateMap"), at_b = b.find("UniformScaleMap");
    ASSERT_NE(at_a, std::string::npos);
    ASSERT_NE(at_b, std::string::npos);
    EXPECT_TRUE(a.substr(at_a + 24 + 144) == b.substr(at_b + 15 + 120));
    Result<world::World> small = stream_read(ours, {.max_tile_chunks = 0});
    ASSERT_FALSE(small);
    EXPECT_NE(small.error().find("0 chunks"), std::string::npos) << small.error();
}

// A VDB world with edits in its overlay: replaced, erased, new chunks in an existing node, in a
// new node and in a new root child.
struct EditedWorld {
    std::string vdb;
    world::World expect;
};

EditedWorld make_edited(TempDir& dir, const std::string& name, bool blosc) {
    EditedWorld e;
    e.vdb = dir.file(name);
    world::World w = varied_world(5);
    if (blosc)
        EXPECT_TRUE(test::write_world_openvdb(w, e.vdb, {}, true));
    else
        EXPECT_TRUE(export_vdb(w, e.vdb));
    VdbOverlayOpenInfo info;
    info.vdb_path = e.vdb;
    info.read.isolated = false;
    auto store = VdbOverlayStore::open(info);
    EXPECT_TRUE(store) << store.error();
    if (!store)
        return e;
    std::mt19937 rng(9);
    std::vector<ChunkCoord> present;
    w.for_each_chunk([&](ChunkCoord c, const Chunk&) { present.push_back(c); });
    std::sort(present.begin(), present.end(), file_order_less);
    const ChunkCoord replaced = present[3], erased = present[10];
    const Chunk edited = mixed_chunk(rng);
    EXPECT_TRUE((*store)->save(replaced, edited));
    w.put_chunk(replaced, edited);
    EXPECT_TRUE((*store)->erase(erased));
    w.remove_chunk(erased);
    for (const ChunkCoord added : {ChunkCoord(9, 3, 2) /* node (2,0,0), uniform 4 before */,
                                   ChunkCoord(30, 30, 30), ChunkCoord(5000, 0, 0), ChunkCoord(-5000, 7, -1)}) {
        const Chunk c = mixed_chunk(rng);
        EXPECT_TRUE((*store)->save(added, c));
        w.put_chunk(added, c);
    }
    EXPECT_TRUE((*store)->flush());
    e.expect = std::move(w);
    return e;
}

TEST(VdbStream, MergedExportEqualsTheEditedWorld) {
    TempDir dir;
    EditedWorld e = make_edited(dir, "w.vdb", false);
    VdbOverlayOpenInfo info;
    info.vdb_path = e.vdb;
    info.read.isolated = false;
    for (const VdbCompression comp : {VdbCompression::Zip, VdbCompression::None}) {
        VdbExportOptions o;
        o.compression = comp;
        const std::string out = dir.file("merged.vdb");
        Result<VdbOverlayExport> done = export_overlay_vdb(info, out, o);
        ASSERT_TRUE(done) << done.error();
        EXPECT_EQ(done->fallback, "");
        EXPECT_EQ(done->chunks, e.expect.chunk_count());
        Result<world::World> back = import_world_vdb(out);
        ASSERT_TRUE(back) << back.error();
        EXPECT_TRUE(same_blocks(e.expect, *back));
    }
    // A box: the same blocks as the edited world boxed.
    VdbExportOptions o;
    o.box = BlockBox{BlockPos(-100, -50, -60), BlockPos(400, 120, 90)};
    const std::string out = dir.file("merged_box.vdb");
    Result<VdbOverlayExport> done = export_overlay_vdb(info, out, o);
    ASSERT_TRUE(done) << done.error();
    Result<world::World> back = import_world_vdb(out);
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(same_blocks(boxed(e.expect, *o.box), *back));
}

TEST(VdbStream, MergedExportFallsBackToOpenVdbForFilesTheReaderRefuses) {
    TempDir dir;
    EditedWorld e = make_edited(dir, "blosc.vdb", true); // Blosc: the streaming reader says no.
    auto refused = VdbStreamReader::open(e.vdb);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("Blosc"), std::string::npos) << refused.error();
    VdbOverlayOpenInfo info;
    info.vdb_path = e.vdb;
    info.read.isolated = false;
    const std::string out = dir.file("merged.vdb");
    Result<VdbOverlayExport> done = export_overlay_vdb(info, out);
    ASSERT_TRUE(done) << done.error();
    EXPECT_EQ(done->fallback, refused.error());
    Result<world::World> back = import_world_vdb(out);
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(same_blocks(e.expect, *back));
}

// Offset k of the "blocks" grid in a file of our writer (0: the grid, 1: its leaf values, 2: its
// end). Its layout: header 57 bytes, file metadata 31, grid count 4, descriptor 34, then the three
// offsets (int64 each).
int64_t grid_offset(const std::string& bytes, int k) {
    int64_t at = 0;
    std::memcpy(&at, bytes.data() + 57 + 31 + 4 + 34 + 8 * k, 8);
    return at;
}

// A file OpenVDB reads but the streaming reader finds damaged only inside its leaf values (a
// leaf's copy of its mask differs from the topology's: OpenVDB, seeking, never reads that copy):
// the export starts streaming, then falls back and still writes the edited world.
TEST(VdbStream, MergedExportFallsBackMidStream) {
    TempDir dir;
    world::World w = varied_world(8);
    const std::string vdb = dir.file("odd.vdb");
    ASSERT_TRUE(export_vdb(w, vdb));
    std::string bytes = read_bytes(vdb);
    const int64_t block_pos = grid_offset(bytes, 1); // Where the leaf values start.
    ASSERT_GT(block_pos, 0);
    ASSERT_LT(size_t(block_pos) + 64, bytes.size());
    bytes[size_t(block_pos) + 63] ^= char(0x80); // The first leaf's last voxel, in the copy only.
    write_bytes(vdb, bytes);
    Result<world::World> streamed = stream_read(vdb);
    ASSERT_FALSE(streamed);
    EXPECT_NE(streamed.error().find("damaged"), std::string::npos) << streamed.error();

    VdbOverlayOpenInfo info;
    info.vdb_path = vdb;
    info.read.isolated = false;
    {
        auto store = VdbOverlayStore::open(info);
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->save(ChunkCoord(1, 1, 1), Chunk(BlockId(9))));
        ASSERT_TRUE((*store)->flush());
    }
    w.put_chunk(ChunkCoord(1, 1, 1), Chunk(BlockId(9)));
    const std::string out = dir.file("merged.vdb");
    Result<VdbOverlayExport> done = export_overlay_vdb(info, out);
    ASSERT_TRUE(done) << done.error();
    EXPECT_EQ(done->fallback, streamed.error());
    Result<world::World> back = import_world_vdb(out);
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(same_blocks(w, *back));
}

// Every prefix the reader is given fails with one line; flipped bytes fail with one line or read
// a world (a flip inside a value), never crash or hang.
TEST(VdbStream, DamagedFilesGiveOneLine) {
    TempDir dir;
    world::World w;
    std::mt19937 rng(3);
    w.put_chunk(ChunkCoord(0), mixed_chunk(rng));
    w.put_chunk(ChunkCoord(-1, 0, 2), Chunk(BlockId(6)));
    w.put_chunk(ChunkCoord(300, 0, 0), mixed_chunk(rng));
    for (const VdbCompression comp : {VdbCompression::Zip, VdbCompression::None}) {
        const std::string good = dir.file("good.vdb"), bad = dir.file("bad.vdb");
        ASSERT_TRUE(export_vdb(w, good, {std::nullopt, comp}));
        const std::string bytes = read_bytes(good);
        std::vector<size_t> cuts = {0, 1, 8, 20, 64, 200, bytes.size() / 2, bytes.size() - 1};
        for (int i = 0; i < 120; ++i)
            cuts.push_back(rng() % bytes.size());
        for (const size_t cut : cuts) {
            write_bytes(bad, bytes.substr(0, cut));
            Result<world::World> r = stream_read(bad, {.max_tile_chunks = 0});
            ASSERT_FALSE(r) << "cut at " << cut;
            EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
            EXPECT_LT(r.error().size(), 400u) << r.error();
        }
        int read_anyway = 0;
        for (int i = 0; i < 300; ++i) {
            std::string flipped = bytes;
            for (int k = 0; k < 1 + i % 3; ++k)
                flipped[rng() % flipped.size()] ^= char(1 + rng() % 255);
            write_bytes(bad, flipped);
            Result<world::World> r = stream_read(bad, {.max_tile_chunks = 0});
            if (r)
                ++read_anyway;
            else
                EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
        }
        EXPECT_LT(read_anyway, 300);
    }
    // Not a VDB file at all.
    const std::string junk = dir.file("junk.vdb");
    write_bytes(junk, "this is not a vdb file");
    auto r = VdbStreamReader::open(junk);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("not an OpenVDB file"), std::string::npos) << r.error();
}

// Other grids before "blocks" are skipped, instances among them (OpenVDB writes a grid sharing an
// earlier grid's tree with no tree and a block offset of 0); the reader called such a sound file
// damaged.
TEST(VdbStream, InstancedGridsBeforeTheBlocksAreSkipped) {
    TempDir dir;
    world::World w = varied_world(10);
    const std::string ours = dir.file("ours.vdb"), mixed = dir.file("mixed.vdb");
    ASSERT_TRUE(export_vdb(w, ours));
    Status written = test::prepend_instanced_grids_openvdb(ours, mixed);
    ASSERT_TRUE(written) << written.error();
    Result<world::World> back = stream_read(mixed);
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(same_blocks(w, *back));
}

// Files that are VDB but not vx worlds the streaming reader can read: each is refused with a line
// naming why (a game opening the wrong file learns what is wrong with it), never read as
// something else.
TEST(VdbStream, FilesThatAreNotReadableWorldsAreRefusedNamingWhy) {
    // The file at `path` is refused with a message holding `says`.
    const auto expect_refused = [](const std::string& path, const std::string& says) {
        auto r = VdbStreamReader::open(path);
        const std::string error = r ? std::string("(opened)") : r.error();
        EXPECT_NE(error.find(says), std::string::npos) << "expected \"" << says << "\", got: " << error;
    };
    using test::TestFile;
    expect_refused(test::test_file(TestFile::FogSphere), "no grid named 'blocks'");
    expect_refused(test::test_file(TestFile::FloatBlocks), "grid 'blocks' is a Tree_float_5_4_3, not Tree_int32_5_4_3");
    expect_refused(test::test_file(TestFile::InstancedBlocks), "grid 'blocks' is an instance of another grid");

    // A world of ours with one field changed at a time (grid_offset's layout).
    TempDir dir;
    world::World w = varied_world(9);
    const std::string good = dir.file("good.vdb"), bad = dir.file("bad.vdb");
    ASSERT_TRUE(export_vdb(w, good));
    const std::string bytes = read_bytes(good);
    ASSERT_TRUE(VdbStreamReader::open(good)) << "the unchanged file must open";
    // `bad`: the good file with `size` bytes at `at` replaced by `value`.
    const auto patched = [&](size_t at, const void* value, size_t size) {
        std::string b = bytes;
        std::memcpy(b.data() + at, value, size);
        write_bytes(bad, b);
        return bad;
    };
    const uint32_t future = 999;
    expect_refused(patched(8, &future, 4), "file format version 999 (the streaming reader reads 222..224)");
    const uint8_t no_offsets = 0;
    expect_refused(patched(20, &no_offsets, 1), "the file has no grid offsets");
    const int64_t grid_pos = grid_offset(bytes, 0);
    ASSERT_GT(grid_pos, 0);
    const uint32_t unknown_compression = 0x8;
    expect_refused(patched(size_t(grid_pos), &unknown_compression, 4), "unknown compression flags 8");
    // vx_format_version: its key, the type "int32" (length-prefixed), the size 4, the value.
    const std::string key = "vx_format_version";
    const size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes.substr(at + key.size() + 4, 5), "int32");
    const int32_t newer = 2;
    expect_refused(patched(at + key.size() + 4 + 5 + 4, &newer, 4), "vx-world format version 2, newer than 1");
}

} // namespace
} // namespace vx::vdb
