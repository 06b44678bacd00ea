#include <climits>
#include <cstring>
#include <numeric>
#include <random>

#include <gtest/gtest.h>
#include <zstd.h>

#include "test_util.h"
#include "store_test_util.h"
#include "world/store/chunk_record.h"

using namespace vx::world;
using vx::world::test::poke;
using vx::world::test::random_chunk;
using vx::world::test::reseal;

namespace {

void expect_round_trip(RecordCodec& codec, ChunkCoord c, const Chunk& chunk) {
    std::vector<uint8_t> rec;
    codec.encode(c, chunk, rec);
    vx::Result<Chunk> back = codec.decode(rec, c);
    ASSERT_TRUE(back.ok()) << back.error();
    ASSERT_TRUE(*back == chunk);
    EXPECT_EQ(back->is_uniform(), chunk.distinct_ids() == 1);
    EXPECT_EQ(back->distinct_ids(), chunk.distinct_ids());
    // The decoded chunk is a working chunk: edits behave as on the original.
    Chunk edited = chunk;
    for (int i : {0, 4097, kChunkVolume - 1}) {
        ASSERT_EQ(back->set(i, BlockId(40000 + i)), edited.set(i, BlockId(40000 + i)));
        ASSERT_EQ(back->get(i), BlockId(40000 + i));
    }
    ASSERT_TRUE(*back == edited);
}

const ChunkCoord kFar[] = {{0, 0, 0},          {-1, -1, -1},          {INT32_MAX, INT32_MIN, 7},
                           {INT32_MIN, 0, INT32_MAX}, {123456, -654321, 99}};

// A chunk with 32768 distinct ids: the largest palette a record can hold.
Chunk all_distinct_chunk(uint32_t seed) {
    std::vector<BlockId> ids(kChunkVolume);
    std::iota(ids.begin(), ids.end(), BlockId(1000));
    std::shuffle(ids.begin(), ids.end(), std::mt19937(seed));
    return Chunk::from_dense(ids);
}

} // namespace

TEST(ChunkRecord, RoundTripsRandomChunksOfEveryPaletteShape) {
    std::mt19937 rng(11);
    RecordCodec codec;
    // Types 1 -> 1-bit palettes with air; 255/256/257 straddle the u8/u16 index switch.
    for (int types : {1, 2, 3, 7, 16, 255, 256, 257, 1000, 30000})
        for (double fill : {0.001, 0.3, 0.9})
            for (ChunkCoord c : kFar)
                expect_round_trip(codec, c, random_chunk(rng, fill, types));
    expect_round_trip(codec, {1, 2, 3}, all_distinct_chunk(1));
}

TEST(ChunkRecord, RoundTripsEveryIndexWidth) {
    // Palettes of 2^k and 2^k + 1 entries give every index width 1..15 bits (32768 -> 15).
    std::mt19937 rng(12);
    RecordCodec codec;
    for (int k = 1; k <= 15; ++k)
        for (int n : {1 << k, (1 << k) + 1}) {
            if (n > kChunkVolume)
                continue;
            std::vector<BlockId> ids(kChunkVolume);
            for (int i = 0; i < kChunkVolume; ++i) // Every entry used at least once.
                ids[size_t(i)] = BlockId(i < n ? i : int(rng() % uint32_t(n)));
            std::shuffle(ids.begin(), ids.end(), rng);
            const Chunk chunk = Chunk::from_dense(ids);
            ASSERT_EQ(chunk.distinct_ids(), uint32_t(n));
            expect_round_trip(codec, {k, n, -k}, chunk);
        }
}

TEST(ChunkRecord, UniformChunksAreTiny) {
    RecordCodec codec;
    for (BlockId id : {BlockId(0), BlockId(1), BlockId(65535)}) {
        std::vector<uint8_t> rec;
        codec.encode({5, -6, 7}, Chunk(id), rec);
        EXPECT_EQ(rec.size(), kRecordHeaderSize + 2);
        expect_round_trip(codec, {5, -6, 7}, Chunk(id));
    }
}

TEST(ChunkRecord, DropsUnusedPaletteEntriesWithoutTouchingTheChunk) {
    RecordCodec codec;
    Chunk c;
    for (int i = 0; i < 300; ++i)
        c.set(i, BlockId(i + 1)); // 301 entries, 9-bit indices.
    for (int i = 1; i < 300; ++i)
        c.set(i, kAir); // Leaves 2 used entries: air and id 1.
    const Chunk before = c;
    std::vector<uint8_t> rec;
    codec.encode({0, 0, 0}, c, rec);
    EXPECT_EQ(c.palette()->ids.size(), before.palette()->ids.size());
    vx::Result<RecordHeader> h = read_record_header(rec);
    ASSERT_TRUE(h.ok()) << h.error();
    EXPECT_EQ(h->palette_entries, 2u);
    EXPECT_EQ(h->kind, RecordKind::Palette8);
    expect_round_trip(codec, {0, 0, 0}, c);
}

TEST(ChunkRecord, EveryPaletteEntryUsedOrNotEncodesTheSameBytes) {
    // Every entry used takes the eight-at-a-time path; an unused entry forces the renumbering
    // one: the same blocks must give the same record, for every index width 1..8 (and 9, whose
    // renumbered indices still fit a byte).
    std::mt19937 rng(13);
    RecordCodec codec;
    for (int n : {2, 3, 4, 5, 8, 9, 16, 17, 32, 33, 64, 65, 128, 129, 255, 256}) {
        std::vector<BlockId> ids(kChunkVolume);
        for (int i = 0; i < kChunkVolume; ++i)
            ids[size_t(i)] = BlockId(i < n ? i + 1 : int(1 + rng() % uint32_t(n)));
        std::shuffle(ids.begin(), ids.end(), rng);
        const Chunk used = Chunk::from_dense(ids);
        ASSERT_EQ(used.palette()->ids.size(), size_t(n));
        Chunk unused = used;
        const BlockId old = unused.set(7, BlockId(60000)); // A new entry...
        unused.set(7, old);                               // ...left unused.
        ASSERT_GT(unused.palette()->ids.size(), size_t(n));
        std::vector<uint8_t> a, b;
        codec.encode({n, 0, 0}, used, a);
        codec.encode({n, 0, 0}, unused, b);
        EXPECT_EQ(a, b) << n << " entries";
        expect_round_trip(codec, {n, 0, 0}, used);
    }
}

TEST(ChunkRecord, OneShotHelpersMatchTheCodec) {
    std::mt19937 rng(3);
    const Chunk chunk = random_chunk(rng, 0.5, 5);
    const std::vector<uint8_t> rec = encode_chunk_record({1, 1, 1}, chunk);
    vx::Result<Chunk> back = decode_chunk_record(rec, {1, 1, 1});
    ASSERT_TRUE(back.ok());
    EXPECT_TRUE(*back == chunk);
}

TEST(ChunkRecordFaults, EveryBitFlipIsDetected) {
    std::mt19937 rng(5);
    RecordCodec codec;
    const Chunk chunks[] = {Chunk(4), random_chunk(rng, 0.2, 2), random_chunk(rng, 0.6, 300),
                            test::versioned_chunk({3, 4, 5}, 77)};
    for (const Chunk& chunk : chunks) {
        std::vector<uint8_t> rec;
        codec.encode({3, 4, 5}, chunk, rec);
        for (size_t i = 0; i < rec.size(); ++i) {
            // Every bit of the header; one random bit of each payload byte (keeps the test fast).
            const int bits = i < kRecordHeaderSize ? 8 : 1;
            for (int b = 0; b < bits; ++b) {
                const uint8_t mask = uint8_t(1u << (bits == 8 ? b : int(rng() % 8)));
                rec[i] ^= mask;
                EXPECT_FALSE(codec.decode(rec, {3, 4, 5}).ok()) << "flip at byte " << i;
                rec[i] ^= mask;
            }
        }
        ASSERT_TRUE(codec.decode(rec, {3, 4, 5}).ok());
    }
}

TEST(ChunkRecordFaults, EveryTruncationAndExtensionIsDetected) {
    std::mt19937 rng(6);
    RecordCodec codec;
    for (const Chunk& chunk : {Chunk(9), random_chunk(rng, 0.4, 20)}) {
        std::vector<uint8_t> rec;
        codec.encode({-7, 8, -9}, chunk, rec);
        for (size_t n = 0; n < rec.size(); ++n)
            EXPECT_FALSE(codec.decode(std::span(rec.data(), n), {-7, 8, -9}).ok()) << "length " << n;
        rec.push_back(0);
        EXPECT_FALSE(codec.decode(rec, {-7, 8, -9}).ok());
    }
    std::vector<uint8_t> huge(max_record_bytes() + 1, 0);
    vx::Result<Chunk> r = codec.decode(huge, {0, 0, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("too long"), std::string::npos) << r.error();
}

TEST(ChunkRecordFaults, WrongCoordinatesAreDetected) {
    std::mt19937 rng(7);
    RecordCodec codec;
    std::vector<uint8_t> rec;
    codec.encode({1, 2, 3}, random_chunk(rng, 0.5, 4), rec);
    for (ChunkCoord other : {ChunkCoord(1, 2, 4), ChunkCoord(-1, 2, 3), ChunkCoord(1, 3, 3), ChunkCoord(0)}) {
        vx::Result<Chunk> r = codec.decode(rec, other);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("filed under"), std::string::npos) << r.error();
    }
}

// Records with a valid checksum but hostile fields: each must be refused with a message naming
// what is wrong (the check that caught it, not a later one tripping on its consequences).
TEST(ChunkRecordFaults, HostileFieldsBehindAValidChecksumAreRefused) {
    std::mt19937 rng(8);
    RecordCodec codec;
    std::vector<uint8_t> good;
    codec.encode({0, 0, 0}, random_chunk(rng, 0.5, 3), good); // Palette of 4: air + 3.
    // `rec` is refused with a message holding `says`.
    const auto expect_refused = [&](const std::vector<uint8_t>& rec, const std::string& says) {
        vx::Result<Chunk> r = codec.decode(rec, {0, 0, 0});
        const std::string error = r.ok() ? std::string("(decoded)") : r.error();
        EXPECT_NE(error.find(says), std::string::npos) << "expected \"" << says << "\", got: " << error;
    };
    auto refused = [&](auto edit, const std::string& says) {
        std::vector<uint8_t> rec = good;
        edit(rec);
        reseal(rec);
        expect_refused(rec, says);
    };
    refused([](auto& r) { poke<uint16_t>(r, 4, 2); }, "unsupported format version 2");
    refused([](auto& r) { r[6] = 9; }, "unknown record kind 9");
    refused([](auto& r) { r[7] = 9; }, "unknown codec 9");
    refused([](auto& r) { poke<uint32_t>(r, 20, 0); }, "bad palette size 0");
    refused([](auto& r) { poke<uint32_t>(r, 20, 1); }, "bad palette size 1");
    refused([](auto& r) { poke<uint32_t>(r, 20, 40000); }, "bad palette size 40000");
    refused([](auto& r) { poke<uint32_t>(r, 20, 3); }, "does not match the palette"); // Fewer entries than stored.
    refused([](auto& r) { poke<uint32_t>(r, 24, 0xFFFFFFFFu); }, "raw size 4294967295 does not match the palette");
    refused([](auto& r) { r[7] = 0; }, "raw payload size mismatch"); // Raw codec on compressed bytes.
    refused([](auto& r) { r[6] = 0; }, "malformed uniform record");  // Uniform kind, palette payload.
    refused([&](auto& r) { std::fill(r.begin() + kRecordHeaderSize, r.end(), uint8_t(rng())); }, "zstd: ");
    // Unsealed: the header's own checks come before the checksum's.
    std::vector<uint8_t> rec = good;
    rec[0] ^= 1;
    expect_refused(rec, "bad magic (not a vx chunk record)");
    rec = good;
    rec.push_back(0);
    expect_refused(rec, "length mismatch: header says");
    rec.assign(good.begin(), good.begin() + 12);
    expect_refused(rec, "truncated to 12 bytes");
    // Raw payloads with bad content, compressed properly, or payloads of the wrong size.
    const auto sealed_raw = [&](std::span<const uint8_t> payload, uint32_t n, uint32_t raw_size) {
        std::vector<uint8_t> out(kRecordHeaderSize + payload.size());
        std::copy(good.begin(), good.begin() + kRecordHeaderSize, out.begin());
        std::copy(payload.begin(), payload.end(), out.begin() + kRecordHeaderSize);
        poke<uint32_t>(out, 20, n);
        poke<uint32_t>(out, 24, raw_size);
        poke<uint32_t>(out, 28, uint32_t(payload.size()));
        reseal(out);
        return out;
    };
    const auto zstd = [](const std::vector<uint8_t>& raw) {
        std::vector<uint8_t> z(ZSTD_compressBound(raw.size()));
        const size_t size = ZSTD_compress(z.data(), z.size(), raw.data(), raw.size(), 1);
        EXPECT_FALSE(ZSTD_isError(size));
        z.resize(ZSTD_isError(size) ? 0 : size);
        return z;
    };
    auto refused_raw = [&](const std::vector<uint8_t>& raw, uint32_t n, const std::string& says) {
        expect_refused(sealed_raw(zstd(raw), n, uint32_t(raw.size())), says);
    };
    std::vector<uint8_t> raw(2 * 2 + kChunkVolume, 0);
    raw[0] = 1;                                               // ids {1, 0}
    raw[4] = 1;                                               // index 0 -> entry 1, rest entry 0
    raw[100] = 2;                                             // entry 2 of 2
    refused_raw(raw, 2, "palette index out of range");
    raw[100] = 255;                                           // far out, counted by compares
    refused_raw(raw, 2, "palette index out of range");
    raw[100] = 0;
    {   // A palette of 12 entries (counted by histogram, not by compares), index 12 and 200 out.
        std::vector<uint8_t> wide(2 * 12 + kChunkVolume, 0);
        for (int e = 0; e < 12; ++e) {
            wide[size_t(2 * e)] = uint8_t(e + 1);
            wide[size_t(2 * 12 + e)] = uint8_t(e); // Every entry used once at least.
        }
        for (uint8_t bad : {uint8_t(12), uint8_t(200)}) {
            wide[2 * 12 + 500] = bad;
            refused_raw(wide, 12, "palette index out of range");
        }
    }
    raw[0] = 0;                                               // ids {0, 0}
    refused_raw(raw, 2, "palette repeats block id 0");
    raw[0] = 1;
    raw[4] = 0;                                               // entry 1 never used
    refused_raw(raw, 2, "unused palette entry 1");
    raw[4] = 1;
    // A payload that decompresses short of the size the palette implies.
    const std::vector<uint8_t> half(raw.begin(), raw.begin() + std::ptrdiff_t(raw.size() / 2));
    expect_refused(sealed_raw(zstd(half), 2, uint32_t(raw.size())),
                   "payload decompressed to 16386 bytes, expected 32772");
    // A payload larger than zstd's bound for that size: refused before decompressing.
    const std::vector<uint8_t> bloated(ZSTD_compressBound(raw.size()) + 1, 7);
    expect_refused(sealed_raw(bloated, 2, uint32_t(raw.size())), "compressed payload larger than the bound");
    raw.push_back(0);
    refused_raw(raw, 2, "raw size 32773 does not match the palette");
    // The sealing above is sound: the good record's fields rebuilt the same way decode.
    std::vector<uint8_t> good_raw(raw.begin(), raw.end() - 1);
    EXPECT_TRUE(codec.decode(sealed_raw(zstd(good_raw), 2, uint32_t(good_raw.size())), {0, 0, 0}).ok());
}

TEST(ChunkRecordFaults, RandomGarbageNeverCrashes) {
    std::mt19937 rng(9);
    RecordCodec codec;
    std::vector<uint8_t> good;
    codec.encode({2, 2, 2}, random_chunk(rng, 0.5, 40), good);
    for (int i = 0; i < 3000; ++i) {
        std::vector<uint8_t> rec;
        if (i % 3 == 0) { // Pure garbage, sometimes with a valid magic.
            rec.resize(rng() % 200);
            for (uint8_t& b : rec)
                b = uint8_t(rng());
            if (rec.size() >= 4 && i % 2)
                poke<uint32_t>(rec, 0, kRecordMagic);
        } else { // A real record with a few bytes changed, then resealed half the time.
            rec = good;
            for (int k = 0; k < 1 + int(rng() % 4); ++k)
                rec[rng() % rec.size()] = uint8_t(rng());
            if (i % 2)
                reseal(rec);
        }
        vx::Result<Chunk> r = codec.decode(rec, {2, 2, 2});
        if (r.ok()) { // Only when resealed and the content passed every check: it must be sound.
            std::vector<uint8_t> again;
            codec.encode({2, 2, 2}, *r, again);
            vx::Result<Chunk> r2 = codec.decode(again, {2, 2, 2});
            ASSERT_TRUE(r2.ok());
            EXPECT_TRUE(*r2 == *r);
        }
    }
    ASSERT_TRUE(codec.decode(good, {2, 2, 2}).ok());
}

// Coarse levels: the level seeds the header hash (seed = level), so level 0 writes exactly the
// records of worlds made before levels existed, and a record read as another level fails.
TEST(ChunkRecordLevels, LevelSeedsTheChecksumAndLevelZeroIsUnchanged) {
    std::mt19937 rng(21);
    RecordCodec codec;
    for (const Chunk& chunk : {Chunk(7), random_chunk(rng, 0.5, 5)}) {
        for (int level : {0, 1, 2, kMaxLodLevel}) {
            const ChunkCoord c(-3, 9, INT32_MIN);
            std::vector<uint8_t> rec;
            codec.encode_lod({level, c}, chunk, rec);
            // checksum = XXH64(payload, XXH64(header[0..32), level)), derived here independently.
            const uint64_t want = XXH64(rec.data() + kRecordHeaderSize, rec.size() - kRecordHeaderSize,
                                        XXH64(rec.data(), 32, XXH64_hash_t(level)));
            uint64_t got = 0;
            std::memcpy(&got, rec.data() + 32, 8);
            EXPECT_EQ(got, want) << "level " << level;
            if (level == 0) {
                std::vector<uint8_t> plain;
                codec.encode(c, chunk, plain);
                EXPECT_EQ(rec, plain); // Byte-identical to the level-less encoder.
                EXPECT_EQ(encode_chunk_record(c, chunk), plain);
            }
            vx::Result<Chunk> back = codec.decode_lod(rec, {level, c});
            ASSERT_TRUE(back.ok()) << back.error();
            EXPECT_TRUE(*back == chunk);
            EXPECT_TRUE(read_record_header(rec, level).ok());
            for (int other : {0, 1, 2, 3, kMaxLodLevel}) {
                if (other == level)
                    continue;
                vx::Result<Chunk> wrong = codec.decode_lod(rec, {other, c});
                ASSERT_FALSE(wrong.ok()) << "level " << level << " read as " << other;
                EXPECT_NE(wrong.error().find("checksum"), std::string::npos) << wrong.error();
            }
            EXPECT_FALSE(codec.decode_lod(rec, {kMaxLodLevel + 1, c}).ok());
            EXPECT_FALSE(codec.decode_lod(rec, {-1, c}).ok());
        }
    }
}
