// The facade's write_png: failed writes reported, and the previous image kept whole.
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include <sys/resource.h>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_checks_util.h"

using vx::test::checks_world;

// write_png reports a failed write: stb's file writer ignored fwrite's errors, so a full disk
// (/dev/full) gave success and a cut file. A good write starts with the PNG signature.
TEST(FacadeChecks, WritePngReportsFailedWrites) {
    vx::Image image;
    image.width = 4;
    image.height = 3;
    image.rgba.assign(4 * 3 * 4, 200);
    const auto dir = std::filesystem::path(checks_world("png")).parent_path();
    std::filesystem::create_directories(dir);
    const std::string good = (dir / "ok.png").string();
    ASSERT_TRUE(vx::write_png(good, image));
    std::FILE* f = std::fopen(good.c_str(), "rb");
    ASSERT_NE(f, nullptr);
    unsigned char head[8] = {};
    EXPECT_EQ(std::fread(head, 1, 8, f), 8u);
    std::fclose(f);
    EXPECT_EQ(head[1], 'P');
    EXPECT_EQ(head[2], 'N');
    EXPECT_EQ(head[3], 'G');
    vx::Status s = vx::write_png((dir / "no" / "such" / "x.png").string(), image);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("cannot write PNG"), std::string::npos) << s.error();
    image.rgba.pop_back();
    EXPECT_FALSE(vx::write_png(good, image)); // Pixel count and size disagree.
    image.rgba.push_back(200);
    if (!std::filesystem::exists("/dev/full"))
        GTEST_SKIP() << "no /dev/full here to make a write fail";
    s = vx::write_png("/dev/full", image);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find(std::strerror(ENOSPC)), std::string::npos) << s.error();
}

// A PNG is written whole or not at all: a write that fails half-way (here the process's file size
// limit, RLIMIT_FSIZE, which fails write(2) with EFBIG as a full disk fails it with ENOSPC) keeps
// the previous image byte for byte and leaves no temporary beside it. Before, the cut file was
// removed, so the previous image was lost too.
TEST(FacadeChecks, AFailedPngWriteKeepsThePreviousImage) {
    const auto dir = std::filesystem::path(checks_world("png_keep")).parent_path() / "png_keep";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "shot.png").string();
    vx::Image image;
    image.width = 2;
    image.height = 2;
    image.rgba.assign(2 * 2 * 4, 90);
    ASSERT_TRUE(vx::write_png(path, image));
    const auto before_size = std::filesystem::file_size(path);
    ASSERT_LT(before_size, 200u); // A 2×2 flat image: well under the limit set below.

    // 128×128 of noise does not compress below the limit.
    vx::Image big;
    big.width = 128;
    big.height = 128;
    big.rgba.resize(size_t(128) * 128 * 4);
    uint32_t state = 12345;
    for (auto& byte : big.rgba) {
        state = state * 1664525u + 1013904223u;
        byte = uint8_t(state >> 24);
    }
    rlimit old_limit{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    rlimit small = old_limit;
    small.rlim_cur = 4096;
    const auto old_handler = std::signal(SIGXFSZ, SIG_IGN); // Else the kernel's signal ends the test.
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    const vx::Status s = vx::write_png(path, big);
    setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_handler);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().find("cannot write PNG"), std::string::npos) << s.error();
    EXPECT_NE(s.error().find(std::strerror(EFBIG)), std::string::npos) << s.error();
    ASSERT_TRUE(std::filesystem::exists(path));
    EXPECT_EQ(std::filesystem::file_size(path), before_size);
    size_t files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir))
        ++files;
    EXPECT_EQ(files, 1u); // No temporary left.
    // With the limit gone the same image is written and replaces the old one.
    ASSERT_TRUE(vx::write_png(path, big));
    EXPECT_GT(std::filesystem::file_size(path), 4096u);
}
