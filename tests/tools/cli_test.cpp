// Runs the vx binary as a user would: exit codes, messages and outputs.
#include <algorithm>
#include <array>
#include <iterator>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "cli_run.h"

namespace {

using cli_test::CliRun;
using cli_test::temp_dir;
using cli_test::vx;

// A 40×20×36 u8 volume: a floor, a pillar and a few scattered blocks of 3 types.
std::string write_volume() {
    const auto path = (temp_dir() / "vol.raw").string();
    std::vector<uint8_t> v(40 * 20 * 36, 0);
    for (int z = 0; z < 36; ++z)
        for (int x = 0; x < 40; ++x)
            v[size_t(z * 40 * 20 + x)] = 1;
    for (int y = 1; y < 15; ++y)
        v[size_t(10 * 40 * 20 + y * 40 + 31)] = 2;
    v[size_t(30 * 40 * 20 + 5 * 40 + 3)] = 3;
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size()));
    return path;
}

} // namespace

TEST(Cli, InfoPrintsVersion) {
    const CliRun r = vx("info");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vx "), std::string::npos);
}

// No Vulkan driver (the loader is pointed at a manifest that does not exist): a line, exit 0.
TEST(Cli, InfoWithoutAVulkanDriverStillSucceeds) {
    const CliRun r = vx("info", "VK_DRIVER_FILES=/nonexistent/vx_icd.json VK_ICD_FILENAMES=/nonexistent/vx_icd.json");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vulkan: none ("), std::string::npos) << r.out;
}

TEST(Cli, BadArgumentsExitTwo) {
    EXPECT_EQ(vx("").code, 2);
    EXPECT_EQ(vx("frobnicate").code, 2);
    EXPECT_EQ(vx("mesh").code, 2);
    EXPECT_EQ(vx("mesh --raw /nonexistent.raw --dims 2,2,2").code, 2);
    const std::string vol = write_volume();
    CliRun r = vx("mesh --raw " + vol + " --dims 40,20");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("--dims"), std::string::npos) << r.out;
    r = vx("mesh --raw " + vol + " --dims 41,20,36");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("bytes"), std::string::npos) << r.out;
    EXPECT_EQ(vx("mesh --raw " + vol + " --dims 40,20,36 --mesher fancy").code, 2);
    EXPECT_EQ(vx("mesh --raw " + vol + " --dims 40,20,36 --origin 1,2,x").code, 2);
    const auto edits = (temp_dir() / "bad_edits.txt").string();
    std::ofstream(edits) << "1 2 3 4\n5 6 seven 8\n";
    r = vx("mesh --raw " + vol + " --dims 40,20,36 --edits " + edits);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find(":2:"), std::string::npos) << r.out; // Names the bad line.
    EXPECT_EQ(vx("bench").code, 2);
    r = vx("mesh --raw " + vol + " --dims 40,20,36 --origin 68719476736,0,0");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("outside the world"), std::string::npos) << r.out;
}

TEST(Cli, RenderBadArgumentsExitTwoBeforeTouchingVulkan) {
    const std::string vol = write_volume();
    const std::string base = "render --raw " + vol + " --dims 40,20,36 ";
    auto expect_bad = [&](const std::string& args, const std::string& mentions) {
        const CliRun r = vx(args);
        EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
        EXPECT_NE(r.out.find(mentions), std::string::npos) << args << "\n" << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
    };
    expect_bad("render", "exactly one scene");
    expect_bad("render --scene seed --seed 3", "exactly one scene");
    expect_bad("render --scene castle", "unknown scene");
    expect_bad("render --raw /nonexistent.raw --dims 2,2,2", "/nonexistent.raw");
    expect_bad("render --world /nonexistent/dir/w.db", "/nonexistent/dir/w.db");
    expect_bad(base + "--size 640by480", "--size");
    expect_bad(base + "--size 0x10", "--size");
    expect_bad(base + "--eye 1,2", "--eye");
    expect_bad(base + "--eye 1e3,2,3", "--eye");
    expect_bad(base + "--target 1,2,x", "--target");
    expect_bad(base + "--eye 68719476737,0,0", "--eye"); // Beyond the world's 2^36.
    expect_bad(base + "--eye 0,10,0 --target 0,0,0", "--up"); // Looking straight down the up axis.
    expect_bad(base + "--device fastest", "fastest");
    expect_bad(base + "--fov 0", "--fov");
    EXPECT_EQ(vx(base + "--shading glossy").code, 2);
    EXPECT_EQ(vx(base + "--shadows maybe").code, 2);
}

// The OBJ has 4 vertices per quad, every face is CCW seen from outside (its normal points to
// air) and the totals match the summary; the same volume far from the origin gives the same
// mesh shifted exactly.
TEST(Cli, MeshWritesObjAndEditsMatchFullRemesh) {
    const std::string vol = write_volume();
    const auto edits = (temp_dir() / "edits.txt").string();
    std::ofstream(edits) << "# dig and build\n31 5 10 0\n0 0 0 0\n39 19 35 2\n32 1 1 3\n";
    auto mesh_obj = [&](const std::string& extra, const std::string& name) {
        const auto obj = (temp_dir() / name).string();
        const CliRun r = vx("mesh --raw " + vol + " --dims 40,20,36 --obj " + obj + " " + extra);
        EXPECT_EQ(r.code, 0) << r.out;
        std::ifstream in(obj);
        std::stringstream ss;
        ss << in.rdbuf();
        return std::make_pair(r.out, ss.str());
    };
    auto [summary, obj] = mesh_obj("--edits " + edits, "a.obj");
    std::istringstream lines(obj);
    std::string line;
    std::vector<glm::dvec3> verts;
    int faces = 0;
    while (std::getline(lines, line)) {
        if (line.rfind("v ", 0) == 0) {
            std::istringstream l(line.substr(2));
            glm::dvec3 p;
            l >> p.x >> p.y >> p.z;
            verts.push_back(p);
        } else if (line.rfind("f ", 0) == 0) {
            ++faces;
            const size_t n = verts.size();
            const glm::dvec3 normal = glm::cross(verts[n - 3] - verts[n - 4], verts[n - 1] - verts[n - 4]);
            EXPECT_GT(glm::length(normal), 0.5);
        }
    }
    EXPECT_EQ(verts.size(), size_t(faces) * 4);
    EXPECT_NE(summary.find(std::to_string(faces) + " quads"), std::string::npos) << summary;
    EXPECT_NE(summary.find("4 edits"), std::string::npos) << summary;

    // Edits applied to the volume itself, meshed from scratch, give the same quad count.
    std::ifstream vin(vol, std::ios::binary);
    std::vector<char> v((std::istreambuf_iterator<char>(vin)), {});
    auto at = [&](int x, int y, int z) -> char& { return v[size_t(z * 800 + y * 40 + x)]; };
    at(31, 5, 10) = 0, at(0, 0, 0) = 0, at(39, 19, 35) = 2, at(32, 1, 1) = 3;
    const auto vol2 = (temp_dir() / "vol2.raw").string();
    std::ofstream(vol2, std::ios::binary).write(v.data(), std::streamsize(v.size()));
    const CliRun full = vx("mesh --raw " + vol2 + " --dims 40,20,36");
    EXPECT_NE(full.out.find(std::to_string(faces) + " quads"), std::string::npos) << full.out;

    // Far from the origin: identical quads, vertices shifted by exactly the origin.
    auto [far_summary, far_obj] = mesh_obj("--origin 68719476000,-4294967296,7", "far.obj"); // Near the world's edge, 2^36.
    auto [near_summary, near_obj] = mesh_obj("", "near.obj");
    EXPECT_EQ(std::count(far_obj.begin(), far_obj.end(), '\n'), std::count(near_obj.begin(), near_obj.end(), '\n'));
    EXPECT_NE(far_obj.find("v 68719476000 -4294967296 7"), std::string::npos);
}
