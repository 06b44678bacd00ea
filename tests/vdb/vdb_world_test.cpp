// World -> VDB -> World: exact round trips, boxes, registry metadata, range limits, and that
// Debian's vdb_print reads what we write.

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string_view>

#include <gtest/gtest.h>

#include "tests/vdb/vdb_openvdb_writer.h"
#include "tests/vdb/vdb_test_util.h"
#include "world/vdb/vdb_volume.h"
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

// `types` block types with varied materials (ids 1..types).
world::BlockRegistry big_registry(int types) {
    world::BlockRegistry r;
    for (int i = 1; i <= types; ++i) {
        world::BlockInfo b;
        b.name = "t";
        b.name += std::to_string(i);
        b.albedo = glm::vec3(float(i % 7) / 7.f, float(i % 11) / 11.f, 0.1f + float(i) * 1e-3f);
        b.reflectivity = float(i % 5) * 0.2f;
        b.emission = i % 9 == 0 ? glm::vec3(1.5f, 0.25f, float(i)) : glm::vec3(0.f);
        b.opaque = i % 4 != 0;
        EXPECT_TRUE(r.add(b).ok());
    }
    return r;
}

// A chunk of one of several shapes: random ids, an 8³-aligned uniform block inside noise, or a
// sparse scatter.
Chunk random_chunk(std::mt19937& rng, int types) {
    std::vector<BlockId> ids(kChunkVolume, world::kAir);
    std::uniform_int_distribution<int> type(1, types);
    const int shape = int(rng() % 3);
    for (int i = 0; i < kChunkVolume; ++i) {
        const bool solid = shape == 0 ? rng() % 2 == 0 : shape == 1 ? rng() % 5 == 0 : rng() % 200 == 0;
        ids[size_t(i)] = solid ? BlockId(type(rng)) : world::kAir;
    }
    if (shape == 1) { // One 8³ leaf slot all one id (becomes a tile), one 16³ region too.
        const BlockId fill = BlockId(type(rng));
        for (int z = 8; z < 16; ++z)
            for (int y = 0; y < 8; ++y)
                for (int x = 16; x < 24; ++x)
                    ids[size_t(world::local_index(x, y, z))] = fill;
    }
    return Chunk::from_dense(ids);
}

world::World random_world(uint32_t seed, int types, std::span<const ChunkCoord> origins) {
    std::mt19937 rng(seed);
    world::World w(big_registry(types));
    for (ChunkCoord base : origins)
        for (int i = 0; i < 6; ++i) {
            const ChunkCoord c = base + ChunkCoord(int(rng() % 4) - 2, int(rng() % 4) - 2, int(rng() % 4) - 2);
            const int kind = int(rng() % 4);
            if (kind == 0)
                w.put_chunk(c, Chunk(BlockId(1 + rng() % unsigned(types)))); // Uniform: tiles.
            else
                w.put_chunk(c, random_chunk(rng, types));
        }
    return w;
}

void expect_same_registry(const world::BlockRegistry& a, const world::BlockRegistry& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 1; i < a.size(); ++i) {
        const world::BlockInfo x = a.info(BlockId(i)), y = b.info(BlockId(i));
        EXPECT_EQ(x.name, y.name);
        EXPECT_EQ(x.albedo, y.albedo);
        EXPECT_EQ(x.reflectivity, y.reflectivity);
        EXPECT_EQ(x.emission, y.emission);
        EXPECT_EQ(x.opaque, y.opaque);
    }
}

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

TEST(VdbWorld, RoundTripRandomWorldsExact) {
    // 2^30 blocks = 2^25 chunks: far from the origin yet inside OpenVDB's int32 index space.
    const std::array<ChunkCoord, 5> origins = {ChunkCoord(0), ChunkCoord(-3, 1, -7), ChunkCoord(1 << 25, 0, 0),
                                               ChunkCoord(-(1 << 25), (1 << 25) - 8, 5),
                                               ChunkCoord(12345, -(1 << 24), 1 << 25)};
    TempDir dir;
    for (uint32_t seed : {1u, 2u, 3u}) {
        const world::World w = random_world(seed, 300, origins);
        const std::string path = dir.file("w" + std::to_string(seed) + ".vdb");
        VdbExportOptions o;
        o.compression = seed == 3 ? VdbCompression::None : VdbCompression::Zip;
        ASSERT_TRUE(export_vdb(w, path, o).ok());
        Result<world::World> back = import_world_vdb(path);
        ASSERT_TRUE(back.ok()) << back.error();
        EXPECT_TRUE(same_blocks(w, *back));
        expect_same_registry(w.registry(), back->registry());
    }
}

TEST(VdbWorld, UniformChunksBecomeTilesNotVoxels) {
    // 64 uniform chunks of 4 ids: as voxels (4 bytes each, 2M of them) the file would take
    // megabytes; as tiles it is a few kilobytes.
    world::World w;
    for (int i = 0; i < 64; ++i)
        w.put_chunk(ChunkCoord(i % 4, (i / 4) % 4, i / 16), Chunk(BlockId(1 + i % 4)));
    TempDir dir;
    const std::string path = dir.file("tiles.vdb");
    ASSERT_TRUE(export_vdb(w, path).ok());
    EXPECT_LT(std::filesystem::file_size(path), 64u * 1024);
    Result<std::vector<GridInfo>> grids = list_grids(path);
    ASSERT_TRUE(grids.ok()) << grids.error();
    ASSERT_EQ(grids->size(), 1u);
    EXPECT_EQ((*grids)[0].name, "blocks");
    EXPECT_EQ((*grids)[0].value_type, "int32");
    EXPECT_EQ((*grids)[0].active_voxels, 64u * kChunkVolume);
    EXPECT_EQ((*grids)[0].bbox_min, glm::ivec3(0));
    EXPECT_EQ((*grids)[0].bbox_max, glm::ivec3(4 * kChunkSize - 1));
    Result<world::World> back = import_world_vdb(path);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_TRUE(same_blocks(w, *back));
    EXPECT_EQ(back->chunk_count(), 64u);
    back->for_each_chunk([](ChunkCoord, const Chunk& c) { EXPECT_TRUE(c.is_uniform()); });
}

// A root tile (4096³ blocks of one id: what the exporter writes for any such region) imports as
// uniform chunks without reading its 2^36 voxels one by one (a 3 KB file took minutes of CPU);
// a box through it reads its edge chunks voxel by voxel and the rest as uniform chunks.
TEST(VdbWorld, RootTilesImportAsUniformChunks) {
    TempDir dir;
    const std::string path = dir.file("root_tile.vdb");
    ASSERT_TRUE(test::write_root_tile_openvdb(path));
    Result<world::World> all = import_world_vdb(path);
    ASSERT_TRUE(all.ok()) << all.error();
    EXPECT_EQ(all->chunk_count(), 1u + (size_t(1) << 21)); // The voxel at (-1, -1, -1), then 128³ chunks.
    const Chunk* inside = all->find_chunk(ChunkCoord(77, 3, 127));
    ASSERT_NE(inside, nullptr);
    EXPECT_TRUE(inside->is_uniform() && inside->uniform_id() == 3);
    EXPECT_EQ(all->get_block(BlockPos(4095, 4095, 4095)), 3);
    EXPECT_EQ(all->get_block(BlockPos(4096, 0, 0)), world::kAir);

    VdbWorldImportOptions part;
    part.box = BlockBox{BlockPos(-5, 10, 20), BlockPos(70, 40, 33)};
    Result<world::World> box = import_world_vdb(path, part);
    ASSERT_TRUE(box.ok()) << box.error();
    for (int64_t z : {19, 20, 33, 34})
        for (int64_t y : {9, 10, 40, 41})
            for (int64_t x : {-1, 0, 70, 71}) {
                const bool in = part.box->contains(BlockPos(x, y, z)) && x >= 0;
                EXPECT_EQ(box->get_block(BlockPos(x, y, z)), in ? 3 : world::kAir) << x << " " << y << " " << z;
            }
}

// A box import reads the same blocks as a whole import clipped to the box, whatever the grid's
// transform (blocks are index coordinates): the box was passed to OpenVDB's partial read as world
// coordinates of unit voxels, so a grid of voxel size 4 lost most of the blocks in the box.
TEST(VdbWorld, PartialImportOfAScaledGridEqualsTheClippedWholeImport) {
    const std::array<ChunkCoord, 2> origins = {ChunkCoord(0), ChunkCoord(-1, 0, 2)};
    const world::World w = random_world(11, 40, origins);
    TempDir dir;
    const std::string unit = dir.file("unit.vdb"), scaled = dir.file("scaled.vdb");
    ASSERT_TRUE(export_vdb(w, unit).ok());
    ASSERT_TRUE(test::rescale_openvdb(unit, scaled, 4.0).ok());
    const BlockBox box{BlockPos(-20, 3, 30), BlockPos(40, 25, 90)};
    Result<world::World> whole = import_world_vdb(scaled);
    ASSERT_TRUE(whole.ok()) << whole.error();
    EXPECT_TRUE(same_blocks(w, *whole));
    VdbWorldImportOptions part;
    part.box = box;
    Result<world::World> got = import_world_vdb(scaled, part);
    ASSERT_TRUE(got.ok()) << got.error();
    world::World expect(w.registry());
    uint64_t inside = 0;
    w.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        for (int i = 0; i < kChunkVolume; ++i) {
            const BlockPos p = world::chunk_origin(c) + BlockPos(i & 31, (i >> 5) & 31, i >> 10);
            if (box.contains(p) && chunk.get(i) != world::kAir) {
                expect.set_block(p, chunk.get(i));
                ++inside;
            }
        }
    });
    ASSERT_GT(inside, 300u);
    EXPECT_TRUE(same_blocks(expect, *got));
}

// A file whose block table holds a NaN, infinite or out-of-range material is refused at import,
// naming the block: it imported, then rendered NaN (or light from nothing) and made the store's
// table unexportable. The registry refuses such materials, so the file is written with a good one
// and the float's bytes are then replaced (VDB metadata is stored uncompressed).
TEST(VdbWorld, MaterialsOutOfRangeAreRefused) {
    TempDir dir;
    const float kSentinel = 0.4453125f; // Exact in binary; appears once, as block 1's reflectivity.
    const std::pair<float, const char*> cases[] = {
        {std::nanf(""), "reflectivity must be 0..1"},
        {INFINITY, "reflectivity must be 0..1"},
        {2.f, "reflectivity must be 0..1, got 2"},
    };
    for (const auto& [bad, says] : cases) {
        world::BlockRegistry r;
        ASSERT_TRUE(r.add(world::BlockInfo{"odd", glm::vec3(0.5f), kSentinel}).ok());
        world::World w(r);
        w.set_block(BlockPos(1, 2, 3), 1);
        const std::string path = dir.file("odd.vdb");
        ASSERT_TRUE(export_vdb(w, path).ok());
        std::string bytes;
        {
            std::ifstream in(path, std::ios::binary);
            bytes.assign(std::istreambuf_iterator<char>(in), {});
        }
        const std::string_view from(reinterpret_cast<const char*>(&kSentinel), sizeof(float));
        const size_t at = bytes.find(from);
        ASSERT_NE(at, std::string::npos);
        ASSERT_EQ(bytes.find(from, at + 1), std::string::npos);
        bytes.replace(at, sizeof(float), reinterpret_cast<const char*>(&bad), sizeof(float));
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
        Result<world::World> back = import_world_vdb(path);
        ASSERT_FALSE(back.ok()) << says;
        EXPECT_NE(back.error().find(std::string("block 1 in the file's registry: ") + says), std::string::npos)
            << back.error();
    }
}

TEST(VdbWorld, ExportBoxKeepsOnlyBlocksInside) {
    const std::array<ChunkCoord, 1> origins = {ChunkCoord(0)};
    const world::World w = random_world(7, 20, origins);
    const BlockBox box{BlockPos(-40, -13, 5), BlockPos(17, 30, 40)};
    TempDir dir;
    const std::string path = dir.file("box.vdb");
    ASSERT_TRUE(export_vdb(w, path, {box}).ok());
    Result<world::World> back = import_world_vdb(path);
    ASSERT_TRUE(back.ok()) << back.error();
    world::World expect(w.registry());
    w.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        for (int i = 0; i < kChunkVolume; ++i) {
            const BlockPos p = world::chunk_origin(c) + BlockPos(i & 31, (i >> 5) & 31, i >> 10);
            if (box.contains(p) && chunk.get(i) != world::kAir)
                expect.set_block(p, chunk.get(i));
        }
    });
    EXPECT_TRUE(same_blocks(expect, *back));
}

TEST(VdbWorld, PartialImportByBox) {
    const std::array<ChunkCoord, 2> origins = {ChunkCoord(0), ChunkCoord(1 << 24, 3, -(1 << 24))};
    const world::World w = random_world(11, 50, origins);
    TempDir dir;
    const std::string path = dir.file("all.vdb");
    ASSERT_TRUE(export_vdb(w, path).ok());
    const BlockPos far = world::chunk_origin(ChunkCoord(1 << 24, 3, -(1 << 24)));
    for (const BlockBox& box : {BlockBox{BlockPos(-33, -2, -70), BlockPos(40, 9, 3)},
                                BlockBox{far - BlockPos(50), far + BlockPos(20, 7, 64)}}) {
        Result<world::World> part = import_world_vdb(path, {box});
        ASSERT_TRUE(part.ok()) << part.error();
        Result<world::World> ref = import_world_vdb(dir.file("all.vdb"));
        ASSERT_TRUE(ref.ok());
        // Expected: the export, boxed.
        const std::string boxed = dir.file("boxed.vdb");
        ASSERT_TRUE(export_vdb(w, boxed, {box}).ok());
        Result<world::World> expect = import_world_vdb(boxed);
        ASSERT_TRUE(expect.ok());
        EXPECT_TRUE(same_blocks(*expect, *part));
        EXPECT_GT(part->chunk_count(), 0u);
    }
    // A box past the file's 32-bit range reads nothing (its ends were cast to 32 bits unclamped).
    const int64_t past = int64_t(1) << 33;
    Result<world::World> beyond = import_world_vdb(path, {BlockBox{BlockPos(past, 0, 0), BlockPos(past + 100, 10, 10)}});
    ASSERT_TRUE(beyond.ok()) << beyond.error();
    EXPECT_EQ(beyond->chunk_count(), 0u);
}

TEST(VdbWorld, EmptyWorldRoundTrips) {
    TempDir dir;
    const std::string path = dir.file("empty.vdb");
    world::World w;
    ASSERT_TRUE(export_vdb(w, path).ok());
    Result<world::World> back = import_world_vdb(path);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_EQ(back->chunk_count(), 0u);
    expect_same_registry(w.registry(), back->registry());
}

TEST(VdbWorld, BeyondInt32RangeFailsAndLeavesFileUntouched) {
    TempDir dir;
    const std::string path = dir.file("keep.vdb");
    world::World small;
    small.set_block(BlockPos(1, 2, 3), 4);
    ASSERT_TRUE(export_vdb(small, path).ok());
    const std::string before = read_bytes(path);

    world::World far;
    far.set_block(BlockPos(int64_t(1) << 31, 0, 0), 1);
    Status s = export_vdb(far, path);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().find("32-bit"), std::string::npos) << s.error();
    EXPECT_EQ(read_bytes(path), before);
    // No temporary left behind.
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 1u);
    // Boxing the far block out makes it exportable.
    EXPECT_TRUE(export_vdb(far, path, {BlockBox{BlockPos(-10), BlockPos(10)}}).ok());
}

TEST(VdbWorld, BadPathsAndForeignFilesGiveErrors) {
    TempDir dir;
    world::World w;
    w.set_block(BlockPos(0), 1);
    Status s = export_vdb(w, dir.file("no/such/dir/x.vdb"));
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(s.error().find('\n'), std::string::npos);

    Result<world::World> r = import_world_vdb(dir.file("missing.vdb"));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("no such file"), std::string::npos) << r.error();

    const std::string junk = dir.file("junk.vdb");
    std::ofstream(junk) << "this is not a vdb file";
    r = import_world_vdb(junk);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().find('\n'), std::string::npos);

    if (test::have_data()) {
        r = import_world_vdb(test::data_path("arnoldusd_smoke.vdb"));
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("'blocks'"), std::string::npos) << r.error();
    }
}

TEST(VdbWorld, DebianVdbPrintReadsExport) {
    const std::string tool = VX_VDB_PRINT;
    if (tool.empty() || !std::filesystem::exists(tool))
        GTEST_SKIP() << "vdb_print not installed (Debian package libopenvdb-tools)";
    world::World w;
    w.put_chunk(ChunkCoord(0), Chunk(BlockId(3)));
    w.set_block(BlockPos(40, 1, 2), 5);
    TempDir dir;
    const std::string path = dir.file("print.vdb");
    ASSERT_TRUE(export_vdb(w, path).ok());
    const std::string cmd = tool + " -l -m '" + path + "' 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[512];
    while (size_t n = std::fread(buf, 1, sizeof buf, p))
        out.append(buf, n);
    const int rc = ::pclose(p);
    ASSERT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("Name: blocks"), std::string::npos) << out;
    EXPECT_NE(out.find("Tree_int32_5_4_3"), std::string::npos) << out;
    EXPECT_NE(out.find("32,769"), std::string::npos) << out; // 32³ + 1 active voxels.
    EXPECT_NE(out.find("vx_block_3_name: grass"), std::string::npos) << out;
    EXPECT_NE(out.find("Number of active tiles:        64"), std::string::npos) << out;
}

} // namespace
} // namespace vx::vdb
