#include <algorithm>
#include <map>
#include <random>
#include <tuple>

#include <cmath>

#include <gtest/gtest.h>

#include "world/chunk.h"
#include "world/world.h"

using namespace vx::world;

TEST(PackedArray, RoundTripsEveryWidthAcrossWordBoundaries) {
    std::mt19937 rng(1);
    for (uint32_t bits = 1; bits <= 16; ++bits) {
        PackedArray a(1000, bits);
        std::vector<uint32_t> ref(1000);
        for (int pass = 0; pass < 3; ++pass)
            for (uint32_t i = 0; i < 1000; ++i) {
                ref[i] = rng() & ((1u << bits) - 1);
                a.set(i, ref[i]);
            }
        for (uint32_t i = 0; i < 1000; ++i)
            ASSERT_EQ(a.get(i), ref[i]) << "bits " << bits << " index " << i;
        PackedArray wider = a.resized(bits == 16 ? 16 : bits + 1);
        for (uint32_t i = 0; i < 1000; ++i)
            ASSERT_EQ(wider.get(i), ref[i]);
    }
}

TEST(PackedArray, SetAllMatchesSetForEveryWidthAndLength) {
    std::mt19937 rng(7);
    for (uint32_t bits = 1; bits <= 16; ++bits)
        for (uint32_t count : {1u, 2u, 63u, 64u, 65u, 127u, 200u, 1000u}) {
            std::vector<uint16_t> values(count);
            for (uint16_t& v : values)
                v = uint16_t(rng()); // Bits above the width must be ignored.
            PackedArray a(count, bits), b(count, bits);
            for (uint32_t i = 0; i < count; ++i)
                a.set(i, values[i] & ((1u << bits) - 1));
            std::fill(b.words(), b.words() + b.word_count(), ~uint64_t(0)); // set_all must clear.
            b.set_all(values.data());
            for (uint32_t w = 0; w < a.word_count(); ++w) // Including the zero padding word.
                ASSERT_EQ(a.words()[w], b.words()[w]) << "bits " << bits << " count " << count << " word " << w;
        }
}

TEST(Chunk, FromDensePaletteCountsMatchContents) {
    std::mt19937 rng(8);
    for (int types : {2, 5, 40, 300}) // Past 32 entries the palette search switches to a map.
        for (int run : {1, 7, 100}) {
            std::vector<BlockId> ids(kChunkVolume);
            for (int i = 0; i < kChunkVolume; ++i)
                ids[i] = i % run == 0 ? BlockId(rng() % types) : ids[i - 1];
            const Chunk c = Chunk::from_dense(ids);
            if (c.is_uniform())
                continue;
            const ChunkPalette* pal = c.palette();
            std::vector<uint32_t> recount(pal->ids.size(), 0);
            for (int i = 0; i < kChunkVolume; ++i)
                ++recount[pal->indices.get(uint32_t(i))];
            ASSERT_EQ(pal->counts.size(), pal->ids.size());
            for (size_t e = 0; e < recount.size(); ++e)
                ASSERT_EQ(pal->counts[e], recount[e]) << "types " << types << " run " << run << " entry " << e;
        }
}

TEST(Chunk, UniformChunkIsSmall) {
    Chunk c(7);
    EXPECT_TRUE(c.is_uniform());
    EXPECT_EQ(c.get(5, 6, 7), 7);
    EXPECT_LE(c.memory_bytes(), 16u);
    EXPECT_EQ(c.distinct_ids(), 1u);
}

TEST(Chunk, SetGrowsPaletteAndMatchesDense) {
    std::mt19937 rng(2);
    Chunk c;
    std::vector<BlockId> ref(kChunkVolume, kAir);
    for (int i = 0; i < 20000; ++i) {
        const int idx = int(rng() % kChunkVolume);
        const BlockId id = BlockId(rng() % 300); // Forces widths up to 9 bits.
        EXPECT_EQ(c.set(idx, id), ref[idx]);
        ref[idx] = id;
    }
    std::vector<BlockId> dense(kChunkVolume);
    c.to_dense(dense);
    EXPECT_EQ(dense, ref);
    Chunk d = Chunk::from_dense(ref);
    EXPECT_TRUE(c == d);
    c.compact();
    c.to_dense(dense);
    EXPECT_EQ(dense, ref);
}

TEST(Chunk, BecomesUniformWhenFilledBlockByBlock) {
    Chunk c;
    c.set(0, 0, 0, 3);
    EXPECT_FALSE(c.is_uniform());
    c.set(0, 0, 0, kAir);
    EXPECT_TRUE(c.is_uniform()); // Every block air again.
    EXPECT_EQ(c.uniform_id(), kAir);
    for (int i = 0; i < kChunkVolume; ++i)
        c.set(i, 5);
    EXPECT_TRUE(c.is_uniform());
    EXPECT_EQ(c.uniform_id(), 5);
}

TEST(Chunk, CompactDropsUnusedEntriesAndNarrows) {
    Chunk c;
    for (int i = 0; i < 16; ++i)
        c.set(i, BlockId(i + 1)); // 17 ids: 5 bits.
    ASSERT_EQ(c.palette()->indices.bits(), 5u);
    for (int i = 2; i < 16; ++i)
        c.set(i, kAir);
    c.compact();
    EXPECT_EQ(c.distinct_ids(), 3u);
    EXPECT_EQ(c.palette()->indices.bits(), 2u);
    EXPECT_EQ(c.get(0), 1);
    EXPECT_EQ(c.get(1), 2);
    EXPECT_EQ(c.get(2), kAir);
}

TEST(Chunk, TerrainLikeChunkCostsTwelveKiB) {
    // Five block types need 3 bits per block: 32768 * 3 / 8 = 12 KiB of indices.
    std::vector<BlockId> ids(kChunkVolume);
    for (int i = 0; i < kChunkVolume; ++i)
        ids[i] = BlockId(i % 5);
    Chunk c = Chunk::from_dense(ids);
    EXPECT_EQ(c.palette()->indices.bits(), 3u);
    EXPECT_LT(c.memory_bytes(), 12 * 1024 + 256);
}

TEST(Coords, FloorDivisionForNegativeBlocks) {
    EXPECT_EQ(chunk_of(BlockPos(-1, 0, 31)), ChunkCoord(-1, 0, 0));
    EXPECT_EQ(local_of(BlockPos(-1, 0, 31)), LocalPos(31, 0, 31));
    EXPECT_EQ(chunk_of(BlockPos(-32, -33, 32)), ChunkCoord(-1, -2, 1));
    const int64_t far = int64_t(1) << 40;
    EXPECT_EQ(chunk_of(BlockPos(far, -far, 0)), ChunkCoord(int32_t(far >> 5), int32_t(-far >> 5), 0));
    EXPECT_EQ(chunk_origin(ChunkCoord(-2, 3, 0)), BlockPos(-64, 96, 0));
}

TEST(World, BlocksAcrossChunkBorders) {
    World w;
    std::mt19937 rng(3);
    std::vector<std::pair<BlockPos, BlockId>> edits;
    for (int i = 0; i < 5000; ++i) {
        BlockPos p(int64_t(rng() % 97) - 48, int64_t(rng() % 97) - 48, int64_t(rng() % 97) - 48);
        p += BlockPos(int64_t(1) << 33, -(int64_t(1) << 30), 7); // Far from the origin too.
        const BlockId id = BlockId(rng() % 6);
        w.set_block(p, id);
        edits.emplace_back(p, id);
    }
    std::map<std::tuple<int64_t, int64_t, int64_t>, BlockId> last;
    for (auto& [p, id] : edits)
        last[{p.x, p.y, p.z}] = id;
    for (auto& [k, id] : last)
        ASSERT_EQ(w.get_block(BlockPos(std::get<0>(k), std::get<1>(k), std::get<2>(k))), id);
    EXPECT_EQ(w.get_block(BlockPos(0, 0, 0)), kAir); // Absent chunk reads as air.
    ChunkCoord lo, hi;
    ASSERT_TRUE(w.chunk_bounds(lo, hi));
    EXPECT_LE(hi.x - lo.x, 4);
}

TEST(BlockRegistry, RejectsDuplicatesAndGivesFallbacks) {
    BlockRegistry r;
    BlockInfo b;
    b.name = "stone";
    ASSERT_TRUE(r.add(b).ok());
    EXPECT_FALSE(r.add(b).ok());
    b.name = "";
    EXPECT_FALSE(r.add(b).ok());
    // Stored worlds record names one per line: "a\nb", "c" and "a", "b\nc" read the same, so a
    // world reopened with the other list passed the check while its ids changed meaning.
    for (const char* bad : {"a\nb", "tab\there", "nul\x01", "del\x7f"}) {
        b.name = bad;
        auto added = r.add(b);
        ASSERT_FALSE(added.ok()) << bad;
        EXPECT_NE(added.error().find("control character"), std::string::npos) << added.error();
    }
    b.name = "snow block (white)";
    EXPECT_TRUE(r.add(b).ok());
    EXPECT_FALSE(r.set(kAir, BlockInfo{"x"}).ok());
    EXPECT_TRUE(r.is_opaque(999)); // Unknown ids mesh as opaque.
    EXPECT_FALSE(r.is_opaque(kAir));
    EXPECT_EQ(r.info(999).name, "block_999");
    EXPECT_NE(fallback_albedo(3), fallback_albedo(4));
    const BlockRegistry& d = BlockRegistry::default_registry();
    ASSERT_TRUE(d.find("water").has_value());
    EXPECT_FALSE(d.is_opaque(*d.find("water")));
    EXPECT_GT(d.info(*d.find("mirror")).reflectivity, 0.5f);
    ASSERT_TRUE(d.find("glazed").has_value()); // The thesis's material: 3 parts own light, 1 reflected.
    EXPECT_FLOAT_EQ(d.info(*d.find("glazed")).reflectivity, 0.25f);
    EXPECT_TRUE(d.is_opaque(*d.find("glazed")));
}

// A name set again at its own id frees the old name; the index and the table agree.
TEST(BlockRegistry, RenamingInPlaceFreesTheOldName) {
    BlockRegistry r;
    ASSERT_TRUE(r.set(5, BlockInfo{"old"}).ok());
    ASSERT_TRUE(r.set(5, BlockInfo{"new"}).ok());
    EXPECT_FALSE(r.find("old").has_value());
    EXPECT_EQ(r.find("new"), std::optional<BlockId>(5));
    EXPECT_FALSE(r.find("").has_value()); // Ids 1..4 are gaps, not blocks named "".
    auto again = r.add(BlockInfo{"old"});
    ASSERT_TRUE(again.ok()) << again.error();
    EXPECT_EQ(*again, BlockId(6));
    EXPECT_FALSE(r.set(7, BlockInfo{"new"}).ok()); // Still a duplicate at another id.
}

// Every way a table is filled goes through set(): a material out of BlockInfo's ranges is refused
// there (a store's text table or a VDB file's metadata once carried albedo 2 or emission -1 in).
TEST(BlockRegistry, RefusesMaterialsOutOfRange) {
    const float nan = std::nanf("");
    const std::pair<BlockInfo, const char*> cases[] = {
        {{"a", glm::vec3(1.5f, 0.5f, 0.5f)}, "albedo must be 0..1"},
        {{"a", glm::vec3(0.5f, -0.1f, 0.5f)}, "albedo must be 0..1"},
        {{"a", glm::vec3(0.5f, nan, 0.5f)}, "albedo must be 0..1"},
        {{"a", glm::vec3(0.5f), 1.01f}, "reflectivity must be 0..1"},
        {{"a", glm::vec3(0.5f), nan}, "reflectivity must be 0..1"},
        {{"a", glm::vec3(0.5f), 0.f, glm::vec3(0.f, -1.f, 0.f)}, "emission must be finite and >= 0"},
        {{"a", glm::vec3(0.5f), 0.f, glm::vec3(INFINITY, 0.f, 0.f)}, "emission must be finite and >= 0"},
    };
    for (const auto& [info, says] : cases) {
        BlockRegistry r;
        vx::Status s = r.set(3, info);
        ASSERT_FALSE(s.ok()) << says;
        EXPECT_NE(s.error().find(says), std::string::npos) << s.error();
        EXPECT_FALSE(r.contains(3));
        EXPECT_FALSE(r.find("a").has_value());
    }
    BlockRegistry r; // The ranges' ends are in range.
    EXPECT_TRUE(r.add({"edge", glm::vec3(0.f, 1.f, 0.f), 1.f, glm::vec3(1e30f)}).ok());
}
