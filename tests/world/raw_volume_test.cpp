#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "world/io/raw_volume.h"

using namespace vx::world;

namespace {

std::string temp_path(const char* name) {
    return (std::filesystem::temp_directory_path() / (std::string("vx_raw_") + name)).string();
}

} // namespace

TEST(RawVolume, RoundTripsU16AtFarOrigin) {
    std::mt19937 rng(9);
    World src;
    const BlockPos origin(kWorldMinBlock + 5, 17, kWorldMaxBlock - 70); // The world's far corners.
    const glm::i64vec3 dims(45, 33, 70);
    for (int i = 0; i < 4000; ++i)
        src.set_block(origin + BlockPos(rng() % 45, rng() % 33, rng() % 70), BlockId(1 + rng() % 1000));
    const std::string path = temp_path("u16.raw");
    ASSERT_TRUE(save_raw_volume(path, {dims, RawType::U16, origin}, src).ok());
    EXPECT_EQ(std::filesystem::file_size(path), uint64_t(45 * 33 * 70 * 2));
    World dst;
    auto r = load_raw_volume(path, {dims, RawType::U16, origin}, dst);
    ASSERT_TRUE(r.ok()) << r.error();
    for (int64_t z = 0; z < dims.z; ++z)
        for (int64_t y = 0; y < dims.y; ++y)
            for (int64_t x = 0; x < dims.x; ++x)
                ASSERT_EQ(dst.get_block(origin + BlockPos(x, y, z)), src.get_block(origin + BlockPos(x, y, z)));
    std::filesystem::remove(path);
}

TEST(RawVolume, ClearErrorsForBadInput) {
    World w;
    const std::string path = temp_path("short.raw");
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_TRUE(f);
        std::fputs("abc", f);
        std::fclose(f);
    }
    auto size = load_raw_volume(path, {glm::i64vec3(2, 2, 2), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(size.ok());
    EXPECT_NE(size.error().find("has 3 bytes"), std::string::npos) << size.error();
    auto missing = load_raw_volume("/nonexistent/x.raw", {glm::i64vec3(1, 1, 1), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().find("cannot open"), std::string::npos);
    auto zero = load_raw_volume(path, {glm::i64vec3(0, 1, 1), RawType::U8, BlockPos(0)}, w);
    EXPECT_FALSE(zero.ok());
    auto huge = load_raw_volume(path, {glm::i64vec3(1 << 20, 1 << 20, 1 << 20), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(huge.ok());
    EXPECT_NE(huge.error().find("too large"), std::string::npos);
    // Within 2^34 blocks but one plane of 2^34: the plane's buffer alone was 32 GiB (bad_alloc).
    auto wide = load_raw_volume(path, {glm::i64vec3(1 << 17, 1 << 17, 1), RawType::U16, BlockPos(0)}, w);
    ASSERT_FALSE(wide.ok());
    EXPECT_NE(wide.error().find("too wide"), std::string::npos) << wide.error();
    auto wide_enough = load_raw_volume(path, {glm::i64vec3(8200, 8200, 1), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(wide_enough.ok()); // Past 8192 x 8192 a plane is still read (here: the size is wrong).
    EXPECT_NE(wide_enough.error().find("has 3 bytes"), std::string::npos) << wide_enough.error();
    auto outside = load_raw_volume(path, {glm::i64vec3(1, 1, 3), RawType::U8, BlockPos(0, 0, kWorldMaxBlock - 1)}, w);
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().find("outside the world"), std::string::npos);
    EXPECT_EQ(w.chunk_count(), 0u); // Nothing half-loaded from refused input.
    std::filesystem::remove(path);
}

// A write that the disk refuses (/dev/full: every write is ENOSPC) is an error naming the file,
// not a success with a cut volume.
TEST(RawVolume, AFullDiskIsAnError) {
    if (!std::filesystem::exists("/dev/full"))
        GTEST_SKIP() << "no /dev/full here to make a write fail";
    World w;
    w.set_block(BlockPos(1, 2, 3), 7);
    const auto s = save_raw_volume("/dev/full", {glm::i64vec3(8, 8, 8), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().find("/dev/full"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find("No space"), std::string::npos) << s.error();
}

// An error half-way through a save (a block id past 255 in a u8 volume) leaves the file that was
// there before, not the rows written up to the error, and no temporary beside it.
TEST(RawVolume, AFailedSaveKeepsThePreviousFile) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_raw_failed_save";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "v.raw").string();
    World w;
    w.set_block(BlockPos(1, 1, 1), 7);
    ASSERT_TRUE(save_raw_volume(path, {glm::i64vec3(4, 4, 4), RawType::U8, BlockPos(0)}, w).ok());
    w.set_block(BlockPos(2, 3, 3), 300); // The last row: every row before it is already written.
    const auto s = save_raw_volume(path, {glm::i64vec3(4, 4, 4), RawType::U8, BlockPos(0)}, w);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().find("does not fit in u8"), std::string::npos) << s.error();
    World back;
    ASSERT_TRUE(load_raw_volume(path, {glm::i64vec3(4, 4, 4), RawType::U8, BlockPos(0)}, back).ok());
    EXPECT_EQ(back.get_block(BlockPos(1, 1, 1)), 7);
    EXPECT_EQ(back.get_block(BlockPos(2, 3, 3)), 0);
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1) << "a temporary was left";
    std::filesystem::remove_all(dir);
}

// A path that is a symbolic link keeps the link: the first save creates the file it names (the
// link dangled), the second replaces that file through a temporary beside it, not the link, and
// the file keeps its mode.
TEST(RawVolume, SavesThroughASymbolicLink) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_raw_link";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "data");
    std::filesystem::create_symlink("data/target.raw", dir / "link.raw");
    const RawVolumeDesc desc{glm::i64vec3(4, 1, 2), RawType::U8, BlockPos(0)};
    for (BlockId id : {9, 11}) {
        World w;
        w.set_block(BlockPos(3, 0, 1), id);
        ASSERT_TRUE(save_raw_volume((dir / "link.raw").string(), desc, w).ok());
        EXPECT_TRUE(std::filesystem::is_symlink(dir / "link.raw"));
        ASSERT_EQ(std::filesystem::file_size(dir / "data" / "target.raw"), 8u);
        World back;
        ASSERT_TRUE(load_raw_volume((dir / "data" / "target.raw").string(), desc, back).ok());
        EXPECT_EQ(back.get_block(BlockPos(3, 0, 1)), id);
        EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "data"), {}), 1);
        const auto target = dir / "data" / "target.raw";
        if (id == 9) // The second save replaces the file: it must keep this mode.
            std::filesystem::permissions(target, std::filesystem::perms(0640));
        else
            EXPECT_EQ(std::filesystem::status(target).permissions(), std::filesystem::perms(0640));
    }
    std::filesystem::remove_all(dir);
}

// A save that cannot start says why and names the path: a folder that does not exist (no
// temporary can be made beside the file) and a path that is a folder. Nothing is created.
TEST(RawVolume, SaveErrorsNameThePathAndCreateNothing) {
    const auto dir = std::filesystem::temp_directory_path() / "vx_raw_bad_paths";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "folder.raw");
    World w;
    const RawVolumeDesc desc{glm::i64vec3(2, 2, 2), RawType::U8, BlockPos(0)};
    const std::string missing = (dir / "no" / "v.raw").string();
    const auto s1 = save_raw_volume(missing, desc, w);
    ASSERT_FALSE(s1.ok());
    EXPECT_NE(s1.error().find(missing), std::string::npos) << s1.error();
    EXPECT_NE(s1.error().find(std::strerror(ENOENT)), std::string::npos) << s1.error();
    const std::string folder = (dir / "folder.raw").string();
    const auto s2 = save_raw_volume(folder, desc, w);
    ASSERT_FALSE(s2.ok());
    EXPECT_NE(s2.error().find(folder), std::string::npos) << s2.error();
    EXPECT_NE(s2.error().find(std::strerror(EISDIR)), std::string::npos) << s2.error();
    EXPECT_TRUE(std::filesystem::is_directory(folder));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
    EXPECT_TRUE(std::filesystem::is_empty(folder));
    std::filesystem::remove_all(dir);
}
