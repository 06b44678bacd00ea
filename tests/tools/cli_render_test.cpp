// `vx render` end to end on lavapipe (CTest label `vulkan`): the PNG it writes, its exit codes,
// and the 64-bit camera. Every render runs with the validation layer (VX_VALIDATION=1) and the
// CLI prints its error count, which must be 0.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "cli_run.h"
#include "world/block_registry.h"
#include "world/gen/seed_scene.h"
#include "world/store/sqlite_store.h"

namespace {

using cli_test::read_file;

using cli_test::CliRun;
using cli_test::vx;

const std::string kEnv = "VX_VALIDATION=1";

std::string dir() { return cli_test::temp_dir("vx_cli_render_test").string(); }


// A 24×12×20 u8 volume: a stone floor (id 1) and a grass pillar (id 3) on it.
// Named after the running test: ctest runs tests as parallel processes.
std::string write_volume() {
    const std::string path = dir() + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".raw";
    std::vector<uint8_t> v(24 * 12 * 20, 0);
    for (int z = 0; z < 20; ++z)
        for (int x = 0; x < 24; ++x)
            v[size_t(z * 24 * 12 + x)] = 1;
    for (int y = 1; y < 10; ++y)
        v[size_t(8 * 24 * 12 + y * 24 + 12)] = 3;
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size()));
    return path;
}

struct Png {
    int w = 0, h = 0;
    std::vector<uint8_t> rgba;
    uint32_t at(int x, int y) const {
        const uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
        return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16;
    }
};

Png read_png(const std::string& path) {
    Png png;
    int n = 0;
    if (uint8_t* data = stbi_load(path.c_str(), &png.w, &png.h, &n, 4)) {
        png.rgba.assign(data, data + size_t(png.w) * png.h * 4);
        stbi_image_free(data);
    }
    return png;
}

CliRun render(const std::string& args) {
    CliRun r = vx("render " + args, kEnv);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("validation errors: 0"), std::string::npos) << r.out;
    return r;
}

// `vx render ARGS--OPTION=VALUE` for each bad value: exit 2 and a message naming the option;
// with one_line, on one line.
void expect_refused(const std::string& args, const std::string& option,
                    std::initializer_list<const char*> bad, bool one_line) {
    for (const char* value : bad) {
        const CliRun r = vx("render " + args + option + "=" + value, kEnv);
        EXPECT_EQ(r.code, 2) << value << ": " << r.out;
        EXPECT_NE(r.out.find(option), std::string::npos) << r.out;
        if (one_line) {
            EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
        }
    }
}

TEST(CliRender, RawVolumeToPng) {
    const std::string vol = write_volume(), out = dir() + "/full.png";
    const CliRun r = render("--raw " + vol + " --dims 24,12,20 --size 48x32 --spp 2 --out " + out);
    EXPECT_NE(r.out.find("trace"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 chunks"), std::string::npos) << r.out; // 24×12×20 fits one chunk.
    const Png png = read_png(out);
    ASSERT_EQ(png.w, 48);
    ASSERT_EQ(png.h, 32);
    // The default camera looks at the volume from above: the top-left corner is sky, and the
    // centre pixels show blocks, so plenty of pixels differ from the sky.
    const uint32_t sky = png.at(0, 0);
    EXPECT_NE(png.at(24, 16), sky);
    int other = 0;
    for (int y = 0; y < png.h; ++y)
        for (int x = 0; x < png.w; ++x)
            other += png.at(x, y) != sky;
    EXPECT_GT(other, png.w * png.h / 10);
}

// `vx render` says when it traced with the coincident-face probe (two different see-through blocks
// touch: render/touching_pairs.h): glass (6) on water (5), and not for glass beside the water
// with air between.
TEST(CliRender, SaysWhenSeeThroughBlocksTouch) {
    for (bool touching : {true, false}) {
        const std::string vol = write_volume(), out = dir() + "/touch.png";
        {
            std::fstream f(vol, std::ios::binary | std::ios::in | std::ios::out);
            const auto put = [&](int x, int y, int z, char id) {
                f.seekp(std::streamoff(z * 24 * 12 + y * 24 + x));
                f.put(id);
            };
            put(4, 1, 4, 5);
            put(4, touching ? 2 : 3, 4, 6);
        }
        const CliRun r = render("--raw " + vol + " --dims 24,12,20 --size 32x24 --spp 1 --out " + out);
        EXPECT_EQ(r.out.find("see-through blocks touch") != std::string::npos, touching) << r.out;
    }
}

// `vx render --see-through-check on` traces a view with water in it first without the see-through
// code and says how many pixels it traced again; the picture is the one `off` draws, which says
// nothing of a check. A bad value of either flag is one line and exit 2.
TEST(CliRender, SeeThroughCheckSaysWhatItTracedAgain) {
    const std::string vol = write_volume();
    {
        std::fstream f(vol, std::ios::binary | std::ios::in | std::ios::out);
        for (int x = 2; x < 10; ++x) { // A strip of water on the floor, in front of the pillar.
            f.seekp(std::streamoff(4 * 24 * 12 + 1 * 24 + x));
            f.put(5);
        }
    }
    const std::string args = "--raw " + vol + " --dims 24,12,20 --size 32x24 --spp 2 --reflections 1 ";
    const CliRun on = render(args + "--see-through-check on --out " + dir() + "/check_on.png");
    const CliRun off = render(args + "--see-through-check off --out " + dir() + "/check_off.png");
    const size_t at = on.out.find("see-through check: ");
    ASSERT_NE(at, std::string::npos) << on.out;
    const unsigned long pixels = std::stoul(on.out.substr(at + 19));
    EXPECT_GT(pixels, 0u) << on.out;
    EXPECT_LT(pixels, 32u * 24u) << on.out;
    EXPECT_NE(on.out.find("pixels traced again with the see-through code"), std::string::npos) << on.out;
    EXPECT_EQ(off.out.find("see-through check"), std::string::npos) << off.out;
    const Png a = read_png(dir() + "/check_on.png"), b = read_png(dir() + "/check_off.png");
    ASSERT_EQ(a.rgba.size(), size_t(32 * 24 * 4));
    EXPECT_EQ(a.rgba, b.rgba);
    for (const char* bad : {"--see-through-check maybe", "--see-through-check-share 2",
                            "--see-through-check-share -0.5", "--see-through-check-share nan"}) {
        const CliRun r = vx("render " + args + bad, kEnv);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find("--see-through-check"), std::string::npos) << r.out;
    }
}

// `vx render --pipeline-report` prints every pipeline variant's stacks after the frame, and either
// the driver's statistics or why there are none (lavapipe offers none). Without the flag: nothing.
TEST(CliRender, PipelineReportListsEveryVariant) {
    const std::string vol = write_volume(), out = dir() + "/report.png";
    const std::string args = "--raw " + vol + " --dims 24,12,20 --size 32x24 --spp 1 --out " + out;
    const CliRun r = render(args + " --pipeline-report");
    for (const char* name : {"rt pipeline, opaque only\n", "rt pipeline, emitter faces, opaque only\n",
                             "rt pipeline\n", "rt pipeline, emitter faces\n", "rt pipeline, probes\n",
                             "rt pipeline, emitter faces, probes\n"})
        EXPECT_NE(r.out.find(name), std::string::npos) << name << r.out;
    EXPECT_NE(r.out.find("    raygen flat"), std::string::npos) << r.out;
    const bool none = r.out.find("no executable statistics: ") != std::string::npos;
    EXPECT_NE(none, r.out.find("  executable ") != std::string::npos) << r.out;
    EXPECT_EQ(render(args).out.find("stack bytes"), std::string::npos);
}

// `vx render` tells the renderer the block the eye lies in (RenderSettings::eye_block): the floor
// under water six deep seen from inside the water, 3.5 blocks over it, is the floor seen from above
// less the 2.5 blocks of water the view no longer crosses (on its slant: 6 / cos and 3.5 / cos,
// Beer-Lambert), channel by channel in Flat mode's linear bytes. Without it, the eye in the water
// saw the floor untinted.
TEST(CliRender, AnEyeUnderWaterSeesTheFloorAsFromAbove) {
    const std::string vol = write_volume();
    {
        std::fstream f(vol, std::ios::binary | std::ios::in | std::ios::out);
        for (int z = 0; z < 20; ++z)
            for (int y = 1; y < 7; ++y)
                for (int x = 0; x < 10; ++x) {
                    f.seekp(std::streamoff(z * 24 * 12 + y * 24 + x));
                    f.put(5); // Water, left of the pillar.
                }
    }
    uint32_t centre[2] = {};
    for (int under = 0; under < 2; ++under) {
        const std::string out = dir() + "/eye" + std::to_string(under) + ".png";
        render("--raw " + vol + " --dims 24,12,20 --size 32x24 --shading flat --eye 4.5," +
               (under ? "4.5" : "10.5") + ",4.5 --target 5,0,5 --out " + out);
        const Png png = read_png(out);
        ASSERT_EQ(png.w, 32);
        centre[under] = png.at(16, 12);
    }
    // The centre pixels' rays, from each eye towards (5, 0, 5): their paths in the water.
    const double above_path = 6.0 * std::sqrt(10.5 * 10.5 + 0.5) / 10.5;
    const double under_path = 3.5 * std::sqrt(4.5 * 4.5 + 0.5) / 4.5;
    const glm::vec3 water = vx::world::BlockRegistry::default_registry().info(5).albedo;
    for (int c = 0; c < 3; ++c) {
        const int above = int(centre[0] >> (8 * c) & 255), under = int(centre[1] >> (8 * c) & 255);
        const double expected = above / std::pow(double(water[c]), above_path - under_path);
        EXPECT_LE(std::abs(under - expected), 2.0)
            << "channel " << c << ": from above " << above << ", under " << under << ", expected " << expected;
    }
}

// `vx info`'s ray-tracing devices: (memory, largest buffer), GiB each.
std::vector<std::pair<double, double>> ray_tracing_device_sizes(const std::string& info) {
    std::vector<std::pair<double, double>> out;
    std::istringstream lines(info);
    for (std::string line; std::getline(lines, line);) {
        double memory = 0, largest = 0;
        const size_t at = line.find("ray tracing: yes, memory ");
        const char* format = "ray tracing: yes, memory %lf GiB, largest buffer %lf GiB";
        if (at != std::string::npos && std::sscanf(line.c_str() + at, format, &memory, &largest) == 2)
            out.emplace_back(memory, largest);
    }
    return out;
}

// A frame the device cannot hold (a 4096² frame's light cache needs 4.8 GB of records, past
// lavapipe's 4 GiB largest buffer) is one error line and exit 1, no image: the buffer's create
// call was VK_CHECKed, and `vx render` asserted on the frame's error, so both aborted. Skipped
// where the device holds such a buffer (an H100: 80 GiB, largest buffer 1 TiB).
TEST(CliRender, AFrameTheDeviceCannotHoldIsAnErrorNotAnAbort) {
    const double records_gib = 4.8e9 / double(1ull << 30);
    for (const auto& [memory, largest] : ray_tracing_device_sizes(vx("info").out))
        if (std::min(memory, largest) > records_gib)
            GTEST_SKIP() << "this device holds the light cache's 4.8 GB buffer (memory " << int(memory)
                         << " GiB, largest buffer " << int(largest) << " GiB): the refusal needs a smaller one";
    const std::string vol = write_volume(), out = dir() + "/too_large.png";
    std::filesystem::remove(out);
    const CliRun r = vx("render --raw " + vol + " --dims 24,12,20 --size 4096x4096 --light-cache on --reflections 8 "
                        "--validation --out " + out, kEnv);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("vx: cannot render: out of GPU memory for the light cache"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// A frame larger than the device (lavapipe: host memory) is refused before it is made: a 16384²
// one took all of this machine's memory and the kernel killed the process (vx render, bench
// render and bench lod alike).
TEST(CliRender, AFrameLargerThanTheDeviceIsRefusedFirst) {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    meminfo >> key >> kib; // "MemTotal: N kB"
    if (key != "MemTotal:" || kib > (uint64_t(48) << 20))
        GTEST_SKIP() << "this machine's memory could hold a 16384x16384 frame (60 GiB); the refusal needs less";
    const std::string vol = write_volume();
    const std::string scene = "--raw " + vol + " --dims 24,12,20 --size 16384x16384 ";
    for (const std::string& cmd : {"render " + scene + "--out " + dir() + "/huge.png",
                                   "bench render " + scene + "--out " + dir() + "/huge_bench",
                                   "bench lod --size 16384x16384 --view-distance 64 --out " + dir() + "/huge_lod"}) {
        const CliRun r = vx(cmd, kEnv);
        EXPECT_EQ(r.code, 2) << cmd << "\n" << r.out;
        EXPECT_NE(r.out.find("choose a smaller size"), std::string::npos) << cmd << "\n" << r.out;
    }
}

// --pipeline raster draws the same flat image as the ray tracer (coverage and block colours of
// this simple view agree except at most a few edge pixels); --denoise and --accumulate run.
TEST(CliRender, RasterPipelineAndDenoiser) {
    const std::string vol = write_volume(), rt = dir() + "/flat_rt.png", raster = dir() + "/flat_raster.png";
    const std::string view = "--raw " + vol + " --dims 24,12,20 --size 48x32 --shading flat ";
    render(view + "--out " + rt);
    const CliRun r = render(view + "--pipeline raster --out " + raster);
    EXPECT_NE(r.out.find("pipeline: raster"), std::string::npos) << r.out;
    const Png a = read_png(rt), b = read_png(raster);
    ASSERT_EQ(a.w, 48);
    ASSERT_EQ(b.w, 48);
    int differ = 0;
    for (int y = 0; y < a.h; ++y)
        for (int x = 0; x < a.w; ++x)
            differ += a.at(x, y) != b.at(x, y);
    EXPECT_LE(differ, 8);
    const CliRun d = render("--raw " + vol + " --dims 24,12,20 --size 48x32 --spp 1 --denoise on --accumulate 3 --out " +
                            dir() + "/denoised.png");
    EXPECT_NE(d.out.find("accumulated frames 2..3"), std::string::npos) << d.out;
    // --repeat's medians name the denoiser's passes only where they ran.
    const std::string repeat = "--raw " + vol + " --dims 24,12,20 --size 48x32 --spp 1 --repeat 2 --out " + dir() +
                               "/repeat.png";
    const CliRun with = render(repeat + " --denoise on"), without = render(repeat);
    EXPECT_NE(with.out.find("frames 2..2 (medians of 1): TLAS"), std::string::npos) << with.out;
    EXPECT_NE(with.out.find(", denoiser "), std::string::npos) << with.out;
    EXPECT_NE(without.out.find("frames 2..2 (medians of 1): TLAS"), std::string::npos) << without.out;
    EXPECT_EQ(without.out.find(", denoiser "), std::string::npos) << without.out;
    // A reference's plain mean: --history-clamp off renders; anything but on / off is refused.
    const CliRun plain = render("--raw " + vol + " --dims 24,12,20 --size 48x32 --spp 1 --accumulate 3 "
                                "--history-clamp off --out " + dir() + "/plain.png");
    EXPECT_NE(plain.out.find("accumulated frames 2..3"), std::string::npos) << plain.out;
    EXPECT_EQ(vx("render --raw " + vol + " --dims 24,12,20 --history-clamp maybe").code, 2);
    // --fov's documented ends 1 and 179 render (they were refused); past them is refused.
    for (const char* fov : {"1", "179"})
        EXPECT_EQ(render(view + "--fov " + fov + " --out " + dir() + "/fov.png").code, 0) << fov;
    EXPECT_EQ(vx("render " + view + "--fov 179.5").code, 2);
}

// Flat shading is exact, so the same volume and camera up to 2^36 blocks from the origin give the
// same image bit for bit: camera and volume positions are parsed as 64-bit integers + fraction.
TEST(CliRender, FarFromOriginRendersIdentically) {
    const std::string vol = write_volume();
    const int64_t ox = 68719470000, oy = 4294967296, oz = 34359738373; // 2^35 + 5.
    const int64_t edge = -68719476736; // -2^36: the world's first block, chunk INT32_MIN.
    // n + quarters / 4 as an exact decimal ("-9.5" is block -10 plus 0.5).
    auto exact = [](int64_t n, int quarters) {
        static const char* const kFrac[] = {"", ".25", ".5", ".75"};
        if (n >= 0 || quarters == 0)
            return std::to_string(n) + kFrac[quarters];
        return (n + 1 == 0 ? std::string("-0") : std::to_string(n + 1)) + kFrac[4 - quarters];
    };
    auto run = [&](int64_t x, int64_t y, int64_t z, const std::string& name) {
        const std::string out = dir() + "/" + name;
        // Eye at (30.5, 20.25, 28.75) + origin, target (12, 2, 10) + origin.
        const std::string eye = exact(x + 30, 2) + "," + exact(y + 20, 1) + "," + exact(z + 28, 3);
        const std::string target = std::to_string(x + 12) + "," + std::to_string(y + 2) + "," + std::to_string(z + 10);
        render("--raw " + vol + " --dims 24,12,20 --size 40x30 --shading flat --origin " + std::to_string(x) + "," +
               std::to_string(y) + "," + std::to_string(z) + " --eye " + eye + " --target " + target + " --out " + out);
        return read_png(out);
    };
    const Png near = run(0, 0, 0, "near.png"), far = run(ox, oy, oz, "far.png");
    // The world's corner: the chunks there have no neighbours beyond the edge (air).
    const Png corner = run(edge, edge, edge, "corner.png");
    ASSERT_EQ(near.w, 40);
    ASSERT_EQ(far.w, 40);
    ASSERT_EQ(corner.w, 40);
    EXPECT_TRUE(near.rgba == far.rgba);
    EXPECT_TRUE(near.rgba == corner.rgba);
    EXPECT_NE(near.at(20, 15), near.at(0, 0)); // Not all sky.
}

// Negative decimals: "-9.5" is block -10 plus 0.5. The same view from (-9.5, 20.25, -7.75) of a
// volume at the origin and from (90.5, 20.25, 92.25) of the volume at (100, 0, 100) is identical.
TEST(CliRender, NegativeFractionalEyeParsesExactly) {
    const std::string vol = write_volume();
    auto run = [&](const std::string& origin, const std::string& eye, const std::string& target,
                   const std::string& name) {
        const std::string out = dir() + "/" + name;
        render("--raw " + vol + " --dims 24,12,20 --size 40x30 --shading flat --origin " + origin + " --eye " + eye +
               " --target " + target + " --out " + out);
        return read_png(out);
    };
    const Png a = run("0,0,0", "-9.5,20.25,-7.75", "12,2,10", "neg_a.png");
    const Png b = run("100,0,100", "90.5,20.25,92.25", "112,2,110", "neg_b.png");
    ASSERT_EQ(a.w, 40);
    EXPECT_TRUE(a.rgba == b.rgba);
    EXPECT_NE(a.at(20, 15), a.at(0, 0));
}

// A target 1e-30 blocks from the eye is a direction like any other: the same image as a target a
// block away along it (in float the direction's square underflowed, and the camera was NaN: a
// flat image and exit 0).
TEST(CliRender, ATargetATinyDistanceAwayIsADirection) {
    const std::string vol = write_volume();
    auto run = [&](const std::string& target, const std::string& name) {
        const std::string out = dir() + "/" + name;
        render("--raw " + vol + " --dims 24,12,20 --origin 10,0,0 --size 40x30 --shading flat --eye 0,3,8.5 --target " +
               target + " --out " + out);
        return read_png(out);
    };
    const Png unit = run("1,3,8.5", "tiny_unit.png");
    const Png tiny = run("0.000000000000000000000000000001,3,8.5", "tiny_1e-30.png");
    ASSERT_EQ(unit.w, 40);
    EXPECT_TRUE(unit.rgba == tiny.rgba);
    EXPECT_NE(unit.at(20, 15), unit.at(20, 0)) << "the pillar is in view, the sky above it";
}

// A stored world of 3 chunks (one of them all air): every stored chunk is loaded and meshed.
TEST(CliRender, StoredWorldRendersEveryChunk) {
    const std::string path = dir() + "/world.db";
    std::filesystem::remove(path);
    {
        auto store = vx::world::SqliteStore::open({.path = path});
        ASSERT_TRUE(store.ok()) << store.error();
        for (int x = 0; x < 2; ++x)
            ASSERT_TRUE((*store)->save({x, 0, 0}, vx::world::random_fill_chunk(uint64_t(x + 1), 20, 1)).ok());
        ASSERT_TRUE((*store)->save({0, 1, 0}, vx::world::Chunk()).ok());
        ASSERT_TRUE((*store)->flush().ok());
    }
    const std::string out = dir() + "/world.png";
    const CliRun r = render("--world " + path + " --size 32x24 --shading flat --out " + out);
    EXPECT_NE(r.out.find("every stored chunk (3)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("3 chunks (2 with triangles)"), std::string::npos) << r.out;
    const Png png = read_png(out);
    ASSERT_EQ(png.w, 32);
    EXPECT_NE(png.at(16, 12), png.at(0, 0)); // Blocks in the middle, sky in the corner.
    // A world of no chunks has nothing to frame: said so (render said "--target must differ from
    // --eye", neither given; bench render measured a degenerate camera and exited 0).
    const std::string empty = dir() + "/empty_world.db";
    std::filesystem::remove(empty);
    {
        auto store = vx::world::SqliteStore::open({.path = empty});
        ASSERT_TRUE(store.ok()) << store.error();
        ASSERT_TRUE((*store)->flush().ok());
    }
    for (const std::string& cmd : {"render --world " + empty + " --size 8x8 --out " + dir() + "/empty.png",
                                  "bench render --world " + empty + " --size 8x8 --out " + dir() + "/empty_bench"}) {
        const CliRun e = vx(cmd, kEnv);
        EXPECT_EQ(e.code, 2) << cmd << "\n" << e.out;
        EXPECT_NE(e.out.find("holds no chunk to"), std::string::npos) << e.out;
    }
}

TEST(CliRender, DeviceOutOfRangeIsAClearError) {
    const CliRun r = vx("render --raw " + write_volume() + " --dims 24,12,20 --device 99", kEnv);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("99"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
}

// --exposure: an EV100 within -10..30 or auto; anything else is one line and exit 2. Two stops
// more exposure (a lower EV100) brighten the picture; auto meters it and says so.
TEST(CliRender, ExposureIsAnEv100OrAuto) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 ";
    expect_refused(view, "--exposure", {"bright", "40", "14.7x", "-11"}, true);
    const std::string dark = dir() + "/ev16.png", bright = dir() + "/ev14.png";
    const CliRun manual = render(view + "--exposure 16 --out " + dark);
    EXPECT_NE(manual.out.find("EV100 16.00 (manual)"), std::string::npos) << manual.out;
    render(view + "--exposure 14 --out " + bright);
    const Png a = read_png(dark), b = read_png(bright);
    ASSERT_EQ(a.rgba.size(), b.rgba.size());
    long sum_a = 0, sum_b = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i)
        if (i % 4 != 3) {
            sum_a += a.rgba[i];
            sum_b += b.rgba[i];
        }
    EXPECT_GT(sum_b, sum_a + sum_a / 4);
    EXPECT_NE(render(view + "--exposure auto --out " + dark).out.find("(auto: metered, key 0.18)"),
              std::string::npos);
}

// --light-cache-pixels: the renderer's bounds (1/64 to 4096) or exit 2 naming the option, NaN and
// infinities included; a width inside them renders.
TEST(CliRender, LightCachePixelsOutsideTheRendererBoundsIsAnError) {
    const std::string view =
        "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 --light-cache on ";
    expect_refused(view, "--light-cache-pixels", {"0", "-1", "5000", "nan", "inf", "3x"}, false);
    render(view + "--light-cache-pixels 0.5 --out " + dir() + "/cache_half.png");
}

// --denoise-passes 1..8: outside is one line naming the option and exit 2; the ends render.
TEST(CliRender, DenoisePassesOutsideOneToEightIsAnError) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 --denoise on ";
    expect_refused(view, "--denoise-passes", {"0", "9", "-1", "3x"}, false);
    for (const char* edge : {"1", "8"})
        render(view + "--denoise-passes " + edge + " --out " + dir() + "/passes.png");
}

// --versus-raw S (1..65536): out of range is refused; S = 2 with --repeat 2 prints two pairs' ratio.
TEST(CliRender, VersusRawPrintsThePairsRatioAndRefusesZero) {
    const std::string view =
        "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 --denoise on ";
    expect_refused(view, "--versus-raw", {"0", "65537", "-1", "2x"}, false);
    const CliRun r = render(view + "--repeat 2 --versus-raw 2 --out " + dir() + "/versus.png");
    EXPECT_NE(r.out.find("versus 2 spp raw, frames interleaved (2 pairs): frame "), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("less time (pair ratios: median; quartiles "), std::string::npos) << r.out;
}

// --haze on|off and --visibility BLOCKS (>= 1 or inf): a bad distance is one line and exit 2;
// off and infinite visibility are the same picture; a thick haze (visibility 8 blocks, the view
// some 20 blocks away) changes it.
TEST(CliRender, HazeAndVisibility) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 ";
    expect_refused(view, "--visibility", {"far", "0", "-5", "nan", "12x"}, true);
    EXPECT_NE(vx("render " + view + "--haze maybe", kEnv).code, 0);
    const std::string off = dir() + "/haze_off.png", clear = dir() + "/haze_inf.png", thick = dir() + "/haze_8.png";
    EXPECT_EQ(render(view + "--haze off --out " + off).out.find("haze:"), std::string::npos);
    EXPECT_NE(render(view + "--visibility inf --out " + clear).out.find("haze: visibility inf"), std::string::npos);
    render(view + "--visibility 8 --out " + thick);
    EXPECT_EQ(read_png(off).rgba, read_png(clear).rgba);
    EXPECT_NE(read_png(off).rgba, read_png(thick).rgba);
}

// A sun direction is a direction at any length: 1e308 long was infinite in float, the sun NaN, and
// the image differed from the unit direction's.
TEST(CliRender, ASunDirectionOfAnyLengthIsTheSameSun) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 ";
    const std::string unit = dir() + "/sun_unit.png", huge = dir() + "/sun_huge.png";
    render(view + "--sun 1,1,0 --out " + unit);
    render(view + "--sun 1e308,1e308,0 --out " + huge);
    EXPECT_FALSE(read_png(unit).rgba.empty());
    EXPECT_EQ(read_png(unit).rgba, read_png(huge).rgba);
}

// --lighting thesis: 25 shadow samples at every hit, 5 reflections, no sun and no sky light;
// options given explicitly win. With the area light off too nothing lights the blocks: only
// the sky colour of missed primary rays is left (the centre pixel, a block, is black), where the
// default lighting's sun and sky still light it. A bad preset is one line and exit 2.
TEST(CliRender, ThesisLightingIsTheAreaLightAlone) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 ";
    const std::string one = "--lighting thesis --spp 1 --bounce-spp 1 ";
    const CliRun thesis = render(view + one + "--out " + dir() + "/t1.png");
    EXPECT_NE(thesis.out.find("shadows on (1 samples, 1 on bounces), reflections 5"), std::string::npos)
        << thesis.out;
    EXPECT_NE(thesis.out.find("lights (--lighting thesis): sun off, sky term x0, area light on"),
              std::string::npos)
        << thesis.out;
    const CliRun preset = render(view + "--lighting thesis --out " + dir() + "/t.png");
    EXPECT_NE(preset.out.find("(25 samples, 25 on bounces), reflections 5"), std::string::npos) << preset.out;
    const std::string dark = dir() + "/thesis_dark.png", lit = dir() + "/default_lit.png";
    render(view + "--lighting thesis --area-light off --spp 1 --bounce-spp 1 --out " + dark);
    render(view + "--area-light off --spp 1 --out " + lit);
    const Png a = read_png(dark), b = read_png(lit);
    ASSERT_EQ(a.w, 32);
    ASSERT_EQ(b.w, 32);
    EXPECT_EQ(a.at(16, 12), 0u);
    EXPECT_NE(b.at(16, 12), 0u);
    EXPECT_NE(a.at(0, 0), 0u); // The sky.
    const CliRun bad = vx("render " + view + "--lighting moon", kEnv);
    EXPECT_EQ(bad.code, 2) << bad.out;
    EXPECT_NE(bad.out.find("--lighting"), std::string::npos) << bad.out;
    // Samples by weight (render::RenderSettings::samples_by_weight): said so; a bad value is one line.
    const CliRun weighted = render(view + "--lighting thesis --samples-by weight --out " + dir() + "/w.png");
    EXPECT_EQ(weighted.code, 0) << weighted.out;
    EXPECT_NE(weighted.out.find("(25 samples x each hit's weight), reflections 5"), std::string::npos)
        << weighted.out;
    const CliRun weighted_08 =
        render(view + "--lighting thesis --samples-by weight --weight-exponent 0.8 --out " + dir() + "/w08.png");
    EXPECT_EQ(weighted_08.code, 0) << weighted_08.out;
    EXPECT_NE(weighted_08.out.find("(25 samples x each hit's weight^0.8), reflections 5"), std::string::npos)
        << weighted_08.out;
    for (const char* e : {"0", "1.5", "nan", "-nan", "inf", "0.8x"}) { // NaN once rendered.
        const CliRun bad_exponent = vx("render " + view + "--samples-by weight --weight-exponent=" + e, kEnv);
        EXPECT_EQ(bad_exponent.code, 2) << e << ": " << bad_exponent.out;
        EXPECT_NE(bad_exponent.out.find("--weight-exponent"), std::string::npos) << bad_exponent.out;
    }
    const CliRun too_deep = vx("render " + view + "--reflections 17", kEnv); // Past kMaxMirrorBounces.
    EXPECT_EQ(too_deep.code, 2) << too_deep.out;
    EXPECT_NE(too_deep.out.find("--reflections"), std::string::npos) << too_deep.out;
    const CliRun bad_by = vx("render " + view + "--samples-by luck", kEnv);
    EXPECT_EQ(bad_by.code, 2) << bad_by.out;
    EXPECT_NE(bad_by.out.find("--samples-by"), std::string::npos) << bad_by.out;
    // Hits in passes of their own (render::RenderSettings::split_hits; --first-hit-pass on is
    // --split-hits 1): the same picture; a bad value is exit 2.
    const std::string one_pass = dir() + "/one_pass.png", two_passes = dir() + "/two_passes.png",
                      four_passes = dir() + "/four_passes.png";
    render(view + one + "--first-hit-pass off --out " + one_pass);
    render(view + one + "--first-hit-pass on --out " + two_passes);
    render(view + one + "--split-hits 3 --out " + four_passes);
    EXPECT_EQ(read_png(one_pass).rgba, read_png(two_passes).rgba);
    EXPECT_EQ(read_png(one_pass).rgba, read_png(four_passes).rgba);
    EXPECT_FALSE(read_png(one_pass).rgba.empty());
    const CliRun bad_pass = vx("render " + view + "--first-hit-pass twice", kEnv);
    EXPECT_EQ(bad_pass.code, 2) << bad_pass.out;
    EXPECT_NE(bad_pass.out.find("--first-hit-pass"), std::string::npos) << bad_pass.out;
    const CliRun bad_split = vx("render " + view + "--split-hits -1", kEnv);
    EXPECT_EQ(bad_split.code, 2) << bad_split.out;
    EXPECT_NE(bad_split.out.find("--split-hits"), std::string::npos) << bad_split.out;
}

// --sample-seed: the same seed gives the same picture, another seed other samples (1 spp: every
// lit pixel's noise changes); a seed that is no number is exit 2.
TEST(CliRender, SampleSeedPicksTheSamples) {
    const std::string view = "--raw " + write_volume() + " --dims 24,12,20 --size 32x24 --spp 1 ";
    const std::string a = dir() + "/seed5a.png", b = dir() + "/seed5b.png", c = dir() + "/seed6.png";
    render(view + "--sample-seed 5 --out " + a);
    render(view + "--sample-seed 5 --out " + b);
    render(view + "--sample-seed 6 --out " + c);
    EXPECT_EQ(read_png(a).rgba, read_png(b).rgba);
    EXPECT_NE(read_png(a).rgba, read_png(c).rgba);
    EXPECT_EQ(vx("render " + view + "--sample-seed five", kEnv).code, 2);
}

// --view-distance (terrain to 200 blocks; level 0 within 2 chunks, coarse rings of 2): with LOD
// the levels' lines (level 2: cells of 4 blocks), without it full detail alone and more chunks;
// bad values are one line and exit 2.
TEST(CliRender, ViewDistanceWithAndWithoutLod) {
    const std::string base = "--seed 1 --view-distance 200 --radius 2 --vradius 1 --lod-ring 2 --size 24x16 "
                             "--shading flat --out " + dir() + "/lod.png";
    const CliRun lod = render(base + " --lod on");
    EXPECT_NE(lod.out.find("level 0 (cells of 1 blocks)"), std::string::npos) << lod.out;
    EXPECT_NE(lod.out.find("level 2 (cells of 4 blocks)"), std::string::npos) << lod.out;
    const CliRun full = render(base + " --lod off");
    EXPECT_NE(full.out.find("full detail"), std::string::npos) << full.out;
    EXPECT_NE(full.out.find("level 0 (cells of 1 blocks)"), std::string::npos) << full.out;
    EXPECT_EQ(full.out.find("level 1 ("), std::string::npos) << full.out;
    for (const char* bad : {"--seed 1 --lod off", "--seed 1 --view-distance 0", "--seed 1 --view-distance 16385",
                            "--scene seed --view-distance 100", "--seed 1 --view-distance 100 --lod-ring 65"}) {
        const CliRun r = vx(std::string("render ") + bad + " --out " + dir() + "/bad.png", kEnv);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
    }
}

// `vx bench lod` (tiny): a full-detail row and a row per radius, no uncovered pixel, the CSV and
// the picture pairs.
TEST(CliRender, BenchLodReport) {
    const std::string out = dir() + "/bench_lod";
    const CliRun r = vx("bench lod --seed 1 --view-distance 160 --radii 1,2 --vradius 1 --lod-ring 2 --size 24x16 "
                        "--repeat 1 --out " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string text = read_file(out + "/lod_report.md");
    for (const char* row : {"| full detail | 160 | 0 |", "| LOD r=1 | 32 |", "| LOD r=2 | 64 |"})
        EXPECT_NE(text.find(row), std::string::npos) << row << "\n" << text;
    std::ifstream csv(out + "/lod_bench.csv");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) {
        if (line.rfind("scene,", 0) == 0)
            continue;
        ++rows;
        // The uncovered column (16th) is 0: LOD leaves no ground pixel of full detail as sky.
        std::stringstream ss(line);
        std::string cell;
        for (int i = 0; i < 16; ++i)
            std::getline(ss, cell, ',');
        EXPECT_EQ(cell, "0") << line;
    }
    EXPECT_EQ(rows, 3);
    for (const char* png : {"/full_flat.png", "/full_full.png", "/lod_r1_flat.png", "/lod_r2_full.png"})
        EXPECT_EQ(read_png(out + png).w, 24) << png;
    for (const char* bad : {"--radii 2,x", "--eye 0,100,0", "--size 0x9"}) {
        const CliRun b = vx(std::string("bench lod ") + bad);
        EXPECT_EQ(b.code, 2) << bad << ": " << b.out;
        EXPECT_EQ(std::count(b.out.begin(), b.out.end(), '\n'), 1) << "one line: " << b.out;
    }
    // A picture that cannot be written (a folder in its place) is named, and the exit is 1.
    const std::string blocked = dir() + "/bench_lod_blocked";
    std::filesystem::remove_all(blocked);
    std::filesystem::create_directories(blocked + "/full_flat.png");
    const CliRun lost = vx("bench lod --seed 1 --view-distance 160 --radii 1 --vradius 1 --lod-ring 2 --size 24x16 "
                           "--repeat 1 --out " + blocked);
    EXPECT_EQ(lost.code, 1) << lost.out;
    EXPECT_NE(lost.out.find("not written: " + blocked + "/full_flat.png"), std::string::npos) << lost.out;
    EXPECT_NE(read_file(blocked + "/lod_report.md").find("| LOD r=1 | 32 |"), std::string::npos); // The rest is.
}

TEST(CliRender, InfoListsTheRayTracingDevice) {
    const CliRun r = vx("info");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("ray tracing: yes"), std::string::npos) << r.out;
    const auto sizes = ray_tracing_device_sizes(r.out);
    ASSERT_FALSE(sizes.empty()) << r.out;
    for (const auto& [memory, largest] : sizes) {
        EXPECT_GT(memory, 0.0) << r.out;
        EXPECT_GE(largest, 1.0) << r.out; // Vulkan 1.3's minimum maxBufferSize: 1 GiB.
    }
}

} // namespace
