// RecordBatchEncoder: records encoded on several threads are byte for byte the records one
// RecordCodec writes, for every thread count and batch size; batches run back to back (TSan).
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"
#include "world/store/record_batch_encoder.h"

namespace vx::world {
namespace {

std::vector<Chunk> mixed_chunks(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Chunk> chunks;
    for (size_t i = 0; i < n; ++i) {
        if (i % 7 == 3)
            chunks.emplace_back(BlockId(i % 5)); // Uniform (air included).
        else
            chunks.push_back(test::random_chunk(rng, 0.05 + 0.9 * double(i % 10) / 10.0, 1 + int(i % 40)));
    }
    return chunks;
}

TEST(RecordBatchEncoder, RecordsEqualOneCodecsForEveryThreadCount) {
    const std::vector<Chunk> chunks = mixed_chunks(70, 1);
    RecordCodec serial(1);
    std::vector<std::vector<uint8_t>> expected(chunks.size());
    for (size_t i = 0; i < chunks.size(); ++i)
        serial.encode(ChunkCoord(int(i), -int(i), 3), chunks[i], expected[i]);
    for (unsigned threads : {1u, 2u, 3u, 8u}) {
        RecordBatchEncoder encoder(1, threads);
        EXPECT_EQ(encoder.threads(), threads);
        RecordCodec caller(1);
        // Sizes around the sharing threshold, and the whole set.
        for (size_t n : {size_t(0), size_t(1), RecordBatchEncoder::kMinShared - 1, RecordBatchEncoder::kMinShared,
                         size_t(33), chunks.size()}) {
            std::vector<std::vector<uint8_t>> out(n, std::vector<uint8_t>{0xEE});
            std::vector<RecordBatchEncoder::Job> jobs;
            for (size_t i = 0; i < n; ++i)
                jobs.push_back({ChunkCoord(int(i), -int(i), 3), &chunks[i], &out[i]});
            encoder.encode(jobs, caller);
            for (size_t i = 0; i < n; ++i)
                ASSERT_EQ(out[i], expected[i]) << "threads " << threads << ", batch " << n << ", record " << i;
        }
    }
}

TEST(RecordBatchEncoder, ManyBatchesBackToBackLoseNoRecord) {
    // Small and large batches alternate, so helpers that woke late for one batch meet the next.
    const std::vector<Chunk> chunks = mixed_chunks(24, 2);
    RecordCodec serial(1), caller(1);
    std::vector<std::vector<uint8_t>> expected(chunks.size());
    for (size_t i = 0; i < chunks.size(); ++i)
        serial.encode(ChunkCoord(int(i), 0, 0), chunks[i], expected[i]);
    RecordBatchEncoder encoder(1, 4);
    for (int round = 0; round < 300; ++round) {
        const size_t n = round % 3 == 0 ? 2 : RecordBatchEncoder::kMinShared + size_t(round % 17);
        std::vector<std::vector<uint8_t>> out(n);
        std::vector<RecordBatchEncoder::Job> jobs;
        for (size_t i = 0; i < n; ++i)
            jobs.push_back({ChunkCoord(int(i), 0, 0), &chunks[i], &out[i]});
        encoder.encode(jobs, caller);
        for (size_t i = 0; i < n; ++i)
            ASSERT_EQ(out[i], expected[i]) << "round " << round << ", record " << i;
    }
}

TEST(RecordBatchEncoder, BatchKeepsEachCoordinatesLastWrite) {
    const Chunk a(1), b(2), c(3);
    std::vector<uint8_t> out_a, out_b, out_c;
    RecordBatchEncoder::Batch batch;
    batch.supersede({0, 0, 0});
    batch.add({0, 0, 0}, a, out_a);
    batch.supersede({1, 0, 0});
    batch.add({1, 0, 0}, b, out_b);
    batch.supersede({0, 0, 0}); // An erase or a pre-encoded record of (0,0,0): its job goes.
    batch.supersede({1, 0, 0});
    batch.add({1, 0, 0}, c, out_c); // Written again: the new chunk, the job's first place.
    const std::span<const RecordBatchEncoder::Job> jobs = batch.jobs();
    ASSERT_EQ(jobs.size(), 1u);
    EXPECT_EQ(jobs[0].coord, ChunkCoord(1, 0, 0));
    EXPECT_EQ(jobs[0].chunk, &c);
    EXPECT_EQ(jobs[0].out, &out_c);
}

// Coarse chunks (save_lod): one chunk coordinate at two levels is two jobs, and every record is
// what RecordCodec::encode_lod writes for its level, on the helpers as on the caller.
TEST(RecordBatchEncoder, LevelsAreDistinctJobsAndSeedTheirRecords) {
    std::mt19937 rng(5);
    const size_t n = 2 * RecordBatchEncoder::kMinShared; // Shared with the helpers.
    std::vector<Chunk> chunks;
    for (size_t i = 0; i < n; ++i)
        chunks.push_back(test::random_chunk(rng, 0.5, 3));
    std::vector<std::vector<uint8_t>> out(n);
    RecordBatchEncoder::Batch batch;
    for (size_t i = 0; i < n; ++i) {
        const LodCoord c{1 + int(i % 2), ChunkCoord(int(i / 2), -1, 0)}; // (i/2, -1, 0) at levels 1 and 2.
        batch.supersede(c);
        batch.add(c, chunks[i], out[i]);
    }
    const std::span<const RecordBatchEncoder::Job> jobs = batch.jobs();
    ASSERT_EQ(jobs.size(), n);
    RecordBatchEncoder encoder(1, 4);
    RecordCodec caller(1), reference(1);
    encoder.encode(jobs, caller);
    for (size_t i = 0; i < n; ++i) {
        const LodCoord c{1 + int(i % 2), ChunkCoord(int(i / 2), -1, 0)};
        std::vector<uint8_t> want;
        reference.encode_lod(c, chunks[i], want);
        EXPECT_EQ(out[i], want) << "record " << i;
        EXPECT_TRUE(reference.decode_lod(out[i], c).ok());
    }
}

} // namespace
} // namespace vx::world
