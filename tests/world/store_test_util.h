#pragma once
// Helpers shared by the chunk record and store tests: temporary directories, chunks whose
// content encodes a version number, raw record surgery.

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <xxhash.h>

#include "world/chunk.h"
#include "world/store/chunk_record.h"

namespace vx::world::test {

// A fresh directory under $TMPDIR (or /tmp), removed with its contents on destruction.
class TempDir {
public:
    TempDir() {
        const char* base = std::getenv("TMPDIR");
        std::string tmpl = std::string(base && *base ? base : "/tmp") + "/vx_store_test_XXXXXX";
        std::vector<char> buf(tmpl.begin(), tmpl.end());
        buf.push_back('\0');
        const char* made = mkdtemp(buf.data());
        EXPECT_NE(made, nullptr);
        m_path = made ? made : "";
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return m_path; }
    std::string file(const std::string& name) const { return m_path + "/" + name; }

private:
    std::string m_path;
};

// Version bits live in the 32 blocks of row (y = 0, z = 0): id 1 + bit i at x = i.
inline constexpr int kVersionBits = 32;

inline uint64_t mix(uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
}

// A terrain-like chunk whose content depends on (c, version) and from which the version can be
// read back (versioned_chunk_version). Cheap: one from_dense.
inline Chunk versioned_chunk(ChunkCoord c, uint32_t version) {
    std::vector<BlockId> ids(kChunkVolume, kAir);
    const uint64_t seed = mix(uint64_t(uint32_t(c.x)) * 73856093u ^ uint64_t(uint32_t(c.y)) * 19349663u ^
                              uint64_t(uint32_t(c.z)) * 83492791u ^ (uint64_t(version) << 32));
    const int ground = 4 + int(seed % 24);
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < ground; ++y)
            for (int x = 0; x < kChunkSize; ++x)
                ids[local_index(x, y, z)] = y + 3 < ground ? 3 : 4; // "stone" under "dirt"
    std::mt19937 rng{uint32_t(seed)};
    const int extras = 20 + int(seed >> 40) % 200;
    for (int i = 0; i < extras; ++i)
        ids[rng() % kChunkVolume] = BlockId(5 + rng() % 12);
    for (int i = 0; i < kVersionBits; ++i)
        ids[local_index(i, 0, 0)] = BlockId(1 + ((version >> i) & 1));
    return Chunk::from_dense(ids);
}

// The version encoded by versioned_chunk, or -1 when the row does not hold one.
inline int64_t versioned_chunk_version(const Chunk& chunk) {
    uint32_t v = 0;
    for (int i = 0; i < kVersionBits; ++i) {
        const BlockId b = chunk.get(i, 0, 0);
        if (b != 1 && b != 2)
            return -1;
        v |= uint32_t(b - 1) << i;
    }
    return v;
}

// Recomputes a record's checksum after the test edited it (to reach checks behind the checksum).
inline void reseal(std::vector<uint8_t>& rec) {
    ASSERT_GE(rec.size(), kRecordHeaderSize);
    const uint64_t h = XXH64(rec.data() + kRecordHeaderSize, rec.size() - kRecordHeaderSize,
                             XXH64(rec.data(), 32, 0));
    std::memcpy(rec.data() + 32, &h, 8);
}

template <class T> void poke(std::vector<uint8_t>& rec, size_t offset, T value) {
    std::memcpy(rec.data() + offset, &value, sizeof(T));
}

} // namespace vx::world::test
