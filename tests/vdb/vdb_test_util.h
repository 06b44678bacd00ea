#pragma once
// Helpers shared by the VDB tests: the real-data folder, temporary files, world comparison.

#include <filesystem>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "world/world.h"

namespace vx::vdb::test {

// Absolute path of a file in shared/data/vdb (beside the repository).
inline std::string data_path(const std::string& name) { return std::string(VX_VDB_DATA_DIR) + "/" + name; }
inline bool have_data() { return std::filesystem::is_directory(VX_VDB_DATA_DIR); }

#define VX_REQUIRE_VDB_DATA()                                                                                \
    do {                                                                                                     \
        if (!::vx::vdb::test::have_data())                                                                   \
            GTEST_SKIP() << "real VDB files not found at " VX_VDB_DATA_DIR " (shared/ beside the repository)"; \
    } while (0)

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
