#pragma once
// Helpers shared by the VDB tests: the real-data folder, temporary files, world comparison.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "world/world.h"

namespace vx::vdb::test {

// The folder of the real VDB files: $VX_VDB_DATA_DIR when set, else the build's VX_VDB_DATA_DIR
// (shared/data/vdb beside the repository unless configured otherwise).
inline std::string data_dir() {
    const char* env = std::getenv("VX_VDB_DATA_DIR");
    return env && *env ? env : VX_VDB_DATA_DIR;
}
// Absolute path of a file in that folder.
inline std::string data_path(const std::string& name) { return data_dir() + "/" + name; }
inline bool have_data() { return std::filesystem::is_directory(data_dir()); }

// Ends a test after its part on generated inputs when the real files of other writers are absent,
// saying so in one line (the part before it runs in a clone alone).
#define VX_REAL_VDB_DATA_OR_RETURN()                                                                    \
    do {                                                                                                \
        if (!::vx::vdb::test::have_data()) {                                                            \
            std::printf("generated inputs only: no real VDB files at %s (clone shared/ beside the "     \
                        "repository, or set VX_VDB_DATA_DIR)\n", ::vx::vdb::test::data_dir().c_str()); \
            return;                                                                                     \
        }                                                                                               \
    } while (0)

// Non-air blocks in every chunk of `w`.
inline uint64_t count_solid(const world::World& w) {
    uint64_t n = 0;
    w.for_each_chunk([&](world::ChunkCoord, const world::Chunk& c) {
        for (int i = 0; i < world::kChunkVolume; ++i)
            n += c.get(i) != world::kAir;
    });
    return n;
}

// A fresh directory under the system temp dir, removed with the object.
class TempDir {
public:
    TempDir() {
        m_path = std::filesystem::temp_directory_path() /
                 ("vx_vdb_test_" + std::to_string(::getpid()) + "_" + std::to_string(s_counter++));
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    std::string file(const std::string& name) const { return (m_path / name).string(); }
    const std::filesystem::path& path() const { return m_path; }

private:
    static inline int s_counter = 0;
    std::filesystem::path m_path;
};

// Every block of both worlds equal (absent chunks read as air).
inline ::testing::AssertionResult same_blocks(const world::World& a, const world::World& b) {
    auto check = [](const world::World& x, const world::World& y, const char* which) -> ::testing::AssertionResult {
        ::testing::AssertionResult ok = ::testing::AssertionSuccess();
        bool failed = false;
        x.for_each_chunk([&](world::ChunkCoord c, const world::Chunk& cx) {
            if (failed)
                return;
            const world::Chunk* cy = y.find_chunk(c);
            for (int i = 0; i < world::kChunkVolume; ++i) {
                const world::BlockId vy = cy ? cy->get(i) : world::kAir;
                if (cx.get(i) != vy) {
                    failed = true;
                    ok = ::testing::AssertionFailure() << which << ": chunk (" << c.x << "," << c.y << "," << c.z
                                                       << ") index " << i << ": " << cx.get(i) << " vs " << vy;
                    return;
                }
            }
        });
        return ok;
    };
    if (auto r = check(a, b, "first"); !r)
        return r;
    return check(b, a, "second");
}

} // namespace vx::vdb::test
