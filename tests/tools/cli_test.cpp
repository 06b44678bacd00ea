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
#include <sqlite3.h>

#include "world/store/sqlite_store.h"
#include "world/vdb/vdb_analytic.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world/vdb/vdb_world.h"
#include <glm/glm.hpp>

#include "cli_run.h"

namespace {

using cli_test::CliRun;
using cli_test::temp_dir;

CliRun run_vx(const std::string& args, const std::string& env = "") { return cli_test::vx(args, env); }

// A 40×20×36 u8 volume: a floor, a pillar and a few scattered blocks of 3 types.
// Named after the running test: ctest runs tests as parallel processes.
std::string write_volume() {
    const auto path =
        (temp_dir() / (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".raw")).string();
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

// A whole file's bytes ("" when it cannot be read).
std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

} // namespace

TEST(Cli, InfoPrintsVersion) {
    const CliRun r = run_vx("info");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vx "), std::string::npos);
}

// No Vulkan driver (the loader is pointed at a manifest that does not exist): a line, exit 0.
TEST(Cli, InfoWithoutAVulkanDriverStillSucceeds) {
    const CliRun r = run_vx("info", "VK_DRIVER_FILES=/nonexistent/vx_icd.json VK_ICD_FILENAMES=/nonexistent/vx_icd.json");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vulkan: none ("), std::string::npos) << r.out;
}

TEST(Cli, BadArgumentsExitTwo) {
    EXPECT_EQ(run_vx("").code, 2);
    EXPECT_EQ(run_vx("frobnicate").code, 2);
    EXPECT_EQ(run_vx("mesh").code, 2);
    EXPECT_EQ(run_vx("mesh --raw /nonexistent.raw --dims 2,2,2").code, 2);
    const std::string vol = write_volume();
    CliRun r = run_vx("mesh --raw " + vol + " --dims 40,20");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("--dims"), std::string::npos) << r.out;
    r = run_vx("mesh --raw " + vol + " --dims 41,20,36");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("bytes"), std::string::npos) << r.out;
    EXPECT_EQ(run_vx("mesh --raw " + vol + " --dims 40,20,36 --mesher fancy").code, 2);
    EXPECT_EQ(run_vx("mesh --raw " + vol + " --dims 40,20,36 --origin 1,2,x").code, 2);
    // More threads than the job system starts (100,000 once aborted when the OS ran out).
    r = run_vx("mesh --raw " + vol + " --dims 40,20,36 --threads 100000");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("--threads"), std::string::npos) << r.out;
    const auto edits = (temp_dir() / "bad_edits.txt").string();
    std::ofstream(edits) << "1 2 3 4\n5 6 seven 8\n";
    r = run_vx("mesh --raw " + vol + " --dims 40,20,36 --edits " + edits);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find(":2:"), std::string::npos) << r.out; // Names the bad line.
    EXPECT_EQ(run_vx("bench").code, 2);
    // The bench commands' own parsers: exit 2 and a "vx:" line (bench vdb exited 105, CLI11's code).
    const std::pair<const char*, const char*> benches[] = {
        {"bench vdb --side 0", "--side"}, {"bench render --repeat 0", "--repeat"}, {"bench lod --repeat 0", "--repeat"}};
    for (const auto& [args, option] : benches) {
        r = run_vx(args);
        EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
        EXPECT_EQ(r.out.rfind("vx: ", 0), 0u) << args << "\n" << r.out;
        EXPECT_NE(r.out.find(option), std::string::npos) << args << "\n" << r.out;
    }
    EXPECT_EQ(run_vx("bench vdb --help").code, 0);
    // Google Benchmark flags it takes badly: -1 repetitions aborted, 0 measured nothing and an
    // unknown format printed the usage, both exiting 0.
    for (const char* flag : {"--benchmark_repetitions=-1", "--benchmark_repetitions=0", "--benchmark_repetitions=x",
                             "--benchmark_format=xx", "--benchmark_out_format=yaml"}) {
        r = run_vx(std::string("bench mesh --benchmark_filter=nothing ") + flag);
        EXPECT_EQ(r.code, 2) << flag << "\n" << r.out;
        if (r.out.find("has no benchmarks") == std::string::npos) {
            EXPECT_NE(r.out.find(std::string(flag).substr(0, std::string(flag).find('='))), std::string::npos)
                << flag << "\n" << r.out;
        }
    }
    // Numbers CLI11 read as something else: -1 and 2^64 as seeds 2^64 - 1, a negative radius or
    // view distance as "not given", a size past 2^32 wrapped (4294967360x48 rendered 64x48), and
    // a trailing "x1" or comma was ignored. Each is refused, naming its option.
    const std::string edits_dir = temp_dir().string();
    const std::pair<std::string, const char*> numbers[] = {
        {"render --seed 1 --size 4294967360x48", "--size"},
        {"render --seed 1 --size 64x48x1", "--size"},
        {"bench render --size 64x48x1", "--size"},
        {"bench lod --size 64x48x1", "--size"},
        {"render --seed -1", "--seed"},
        {"render --seed 18446744073709551616", "--seed"},
        {"world gen " + (temp_dir() / "never.db").string() + " --seed -1", "--seed"},
        {"render --seed 1 --radius -5", "--radius"},
        {"render --seed 1 --view-distance -5", "--view-distance"},
        {"bench lod --view-distance -5", "--view-distance"},
        {"bench render --radius -5", "--radius"},
        {"mesh --raw " + vol + " --dims 40,20,36 --edits " + edits_dir, "cannot read edits file"}};
    for (const auto& [args, option] : numbers) {
        r = run_vx(args);
        EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
        EXPECT_NE(r.out.find(option), std::string::npos) << args << "\n" << r.out;
        EXPECT_EQ(r.out.find("Run 'lod --help'"), std::string::npos) << r.out; // Names the command.
    }
    EXPECT_FALSE(std::filesystem::exists(temp_dir() / "never.db"));
    // A folder where a file belongs says so (SQLite said "disk I/O error", the raw reader that the
    // folder had 2^63 - 1 bytes).
    r = run_vx("world info " + edits_dir);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("is a folder, not a world file"), std::string::npos) << r.out;
    r = run_vx("mesh --raw " + edits_dir + " --dims 2,2,2");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("is not a file"), std::string::npos) << r.out;
    r = run_vx("mesh --raw " + vol + " --dims 40,20,36 --origin 68719476736,0,0");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("outside the world"), std::string::npos) << r.out;
}

TEST(Cli, RenderBadArgumentsExitTwoBeforeTouchingVulkan) {
    const std::string vol = write_volume();
    const std::string base = "render --raw " + vol + " --dims 40,20,36 ";
    auto expect_bad = [&](const std::string& args, const std::string& mentions) {
        const CliRun r = run_vx(args);
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
    // A volume at the world's edge renders (CliRender.FarFromOriginRendersIdentically), but the
    // default eye framing this one would stand outside the world: refused, naming the way out.
    expect_bad(base + "--origin -68719476736,0,0", "--eye"); // The first block of the world.
    // The same for the default light above a volume at the world's top.
    expect_bad(base + "--origin 0,68719476700,0 --eye 50,68719476710,50 --target 0,68719476700,0", "--light");
    expect_bad(base + "--eye 0,10,0 --target 0,0,0", "--up"); // Looking straight down the up axis.
    // Levels of detail from a billion blocks above the terrain asked for billions of chunks.
    expect_bad("render --seed 1 --view-distance 1000 --eye 0,1000000000,0 --target 100,0,100",
               "levels of detail reach at most 65536 blocks");
    expect_bad(base + "--device fastest", "fastest");
    expect_bad(base + "--fov 0", "--fov");
    const CliRun spp = run_vx(base + "--spp 4294967295"); // Ran for hours.
    EXPECT_EQ(spp.code, 2) << spp.out;
    EXPECT_NE(spp.out.find("--spp"), std::string::npos) << spp.out;
    EXPECT_EQ(run_vx(base + "--shading glossy").code, 2);
    EXPECT_EQ(run_vx(base + "--shadows maybe").code, 2);
    // An --out that cannot be written is refused before the render (it failed after it).
    const auto folder = temp_dir() / "render_out_folder";
    std::filesystem::create_directories(folder);
    expect_bad(base + "--out " + folder.string(), "not a file");
    expect_bad(base + "--out /nonexistent/dir/x.png", "folder");
    // The same for vx mesh --obj (checked before loading, the OBJ and its .mtl after meshing).
    expect_bad("mesh --raw " + vol + " --dims 40,20,36 --obj " + folder.string(), "--obj");
    expect_bad("mesh --raw " + vol + " --dims 40,20,36 --obj /nonexistent/dir/x.obj", "folder");
    // An output that is an input (directly, by a link, or a SQLite world's -wal) is refused: the
    // image or the OBJ replaced the world, the volume or the edits, and the command exited 0.
    const std::string size_before = std::to_string(std::filesystem::file_size(vol));
    const auto link = temp_dir() / "volume_link.raw";
    std::filesystem::remove(link);
    std::filesystem::create_symlink(vol, link);
    expect_bad(base + "--out " + vol, "which the render reads");
    expect_bad(base + "--out " + link.string(), "which the render reads");
    const auto world = temp_dir() / "render_reads.db";
    std::ofstream(world.string() + "-wal") << "";
    expect_bad("render --world " + world.string() + " --out " + world.string() + "-wal", "which the render reads");
    const auto edits = temp_dir() / "mesh_edits.txt";
    std::ofstream(edits) << "0 0 0 1\n";
    const std::string mesh = "mesh --raw " + vol + " --dims 40,20,36 --edits " + edits.string();
    expect_bad(mesh + " --obj " + vol, "an input");
    expect_bad(mesh + " --obj " + edits.string(), "an input");
    const auto volume_mtl = temp_dir() / "volume.mtl"; // An input the .mtl beside volume.obj would replace.
    std::filesystem::copy_file(vol, volume_mtl, std::filesystem::copy_options::overwrite_existing);
    expect_bad("mesh --raw " + volume_mtl.string() + " --dims 40,20,36 --obj " + (temp_dir() / "volume.obj").string(),
               "an input");
    EXPECT_EQ(std::to_string(std::filesystem::file_size(vol)), size_before);
    std::ifstream kept(edits);
    std::string line;
    EXPECT_TRUE(std::getline(kept, line) && line == "0 0 0 1");
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
        const CliRun r = run_vx("mesh --raw " + vol + " --dims 40,20,36 --obj " + obj + " " + extra);
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
    const CliRun full = run_vx("mesh --raw " + vol2 + " --dims 40,20,36");
    EXPECT_NE(full.out.find(std::to_string(faces) + " quads"), std::string::npos) << full.out;

    // Far from the origin: identical quads, vertices shifted by exactly the origin.
    auto [far_summary, far_obj] = mesh_obj("--origin 68719476000,-4294967296,7", "far.obj"); // Near the world's edge, 2^36.
    auto [near_summary, near_obj] = mesh_obj("", "near.obj");
    EXPECT_EQ(std::count(far_obj.begin(), far_obj.end(), '\n'), std::count(near_obj.begin(), near_obj.end(), '\n'));
    EXPECT_NE(far_obj.find("v 68719476000 -4294967296 7"), std::string::npos);
}

namespace {
// An empty SQLite world at `path` holding meta `key` = `value`.
void world_with_meta(const std::string& path, const char* key, const char* value) {
    auto world = vx::world::SqliteStore::open({path});
    ASSERT_TRUE(world) << world.error();
    ASSERT_TRUE((*world)->set_meta(key, value));
    ASSERT_TRUE((*world)->flush());
}
} // namespace

// `vx world gen` writes a store that `vx world info --check` verifies; a damaged record turns
// the check's exit code to 1, an unopenable store to 2.
TEST(Cli, WorldGenInfoAndCheck) {
    const auto dir = temp_dir() / "world";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = (dir / "w.db").string();
    CliRun r = run_vx("world gen " + db + " --seed 9 --radius 1 --bottom -1 --top 1");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("27 chunks"), std::string::npos) << r.out; // 3 × 3 × 3.
    r = run_vx("world info " + db);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("chunks stored: 27"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("seed: 9"), std::string::npos) << r.out;
    r = run_vx("world info " + db + " --check");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("records: 27, corrupt: 0"), std::string::npos) << r.out;

    // Another seed into the same store is refused, and so is a world a game's generator made.
    EXPECT_EQ(run_vx("world gen " + db + " --seed 10 --radius 1").code, 2);
    // A box of more than 1,024 chunk layers is refused (2^32 of them once ran for days), and so is
    // the world's outermost layer (its loop once never ended).
    const std::string tall = (dir / "tall.db").string();
    r = run_vx("world gen " + tall + " --seed 9 --radius 0 --bottom -2147483647 --top 2147483646");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("at most 1024 chunk layers, got 4294967294"), std::string::npos) << r.out;
    for (const char* edge : {"--bottom 2147483647 --top 2147483647", "--bottom -2147483648 --top -2147483648"}) {
        r = run_vx("world gen " + tall + " --seed 9 --radius 0 " + edge);
        EXPECT_EQ(r.code, 2) << edge << ": " << r.out;
        EXPECT_NE(r.out.find("outermost chunk layer"), std::string::npos) << r.out;
    }
    const std::string game_db = (dir / "game.db").string();
    ASSERT_NO_FATAL_FAILURE(world_with_meta(game_db, "generator", "game:waves/1"));
    r = run_vx("world gen " + game_db + " --seed 9 --radius 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("made by a game's generator (game:waves/1)"), std::string::npos) << r.out;
    // So is an imported world (terrain went into its box, stamped "terrain"), and a refused
    // command writes no meta.
    const std::string imported = (dir / "imported.db").string();
    ASSERT_NO_FATAL_FAILURE(world_with_meta(imported, "source", "volume.vdb"));
    r = run_vx("world gen " + imported + " --seed 9 --radius 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("was imported (volume.vdb)"), std::string::npos) << r.out;
    {
        auto world = vx::world::SqliteStore::open({imported, /*read_only=*/true, /*create=*/false});
        ASSERT_TRUE(world) << world.error();
        EXPECT_FALSE((*world)->get_meta("generator")->has_value());
        EXPECT_FALSE((*world)->get_meta("seed")->has_value());
    }

    // Flip a byte inside one record's payload.
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(h,
                           "UPDATE chunks SET data = substr(data, 1, length(data) - 1) || "
                           "char((unicode(substr(data, -1)) + 1) % 128) WHERE x = 0 AND y = 0 AND z = 0",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(h);
    r = run_vx("world info " + db + " --check");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("records: 27, corrupt: 1"), std::string::npos) << r.out;

    r = run_vx("world info " + (dir / "missing.db").string() + " --check");
    EXPECT_EQ(r.code, 2) << r.out;
    const std::string garbage = (dir / "garbage.db").string();
    std::ofstream(garbage) << "this is not a database, but it is long enough to look like one to a careless reader";
    r = run_vx("world info " + garbage);
    EXPECT_EQ(r.code, 2) << r.out;

    // Run again over a world it made (one record damaged above), a larger box keeps every chunk it
    // has: a player's edits, and the damaged record for --check to find.
    {
        auto world = vx::world::SqliteStore::open({db});
        ASSERT_TRUE(world) << world.error();
        ASSERT_TRUE((*world)->save(vx::world::ChunkCoord(1, 0, 1), vx::world::Chunk(5)));
        ASSERT_TRUE((*world)->flush());
    }
    r = run_vx("world gen " + db + " --seed 9 --radius 2 --bottom -1 --top 1");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vx world gen: 48 chunks"), std::string::npos) << r.out; // 5 x 5 x 3, less 27.
    EXPECT_NE(r.out.find("kept as stored: 27 chunks"), std::string::npos) << r.out;
    auto world = vx::world::SqliteStore::open({db, /*read_only=*/true, /*create=*/false});
    ASSERT_TRUE(world) << world.error();
    auto edited = (*world)->load(vx::world::ChunkCoord(1, 0, 1));
    ASSERT_TRUE(edited && edited->state == vx::world::LoadState::Present);
    EXPECT_TRUE(*edited->chunk == vx::world::Chunk(5));
}

// --lod-levels N also stores coarse levels 1..N over the box; `world info` counts them per level
// and --check verifies them with the rest.
TEST(Cli, WorldGenStoresCoarseLevels) {
    const auto dir = temp_dir() / "world_lod";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = (dir / "w.db").string();
    EXPECT_EQ(run_vx("world gen " + db + " --radius 1 --lod-levels 11").code, 2);
    EXPECT_EQ(run_vx("world gen " + db + " --radius 1 --lod-levels -1").code, 2);
    CliRun r = run_vx("world gen " + db + " --seed 9 --radius 1 --bottom -1 --top 1 --lod-levels 2");
    ASSERT_EQ(r.code, 0) << r.out;
    // Chunks -1..1 on each axis: -1..0 at levels 1 and 2 (floored shifts), 8 chunks each.
    EXPECT_NE(r.out.find("27 chunks"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 1: 8 coarse chunks"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 2: 8 coarse chunks"), std::string::npos) << r.out;
    r = run_vx("world info " + db);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("chunks stored: 27"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 1 coarse chunks stored: 8"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 2 coarse chunks stored: 8"), std::string::npos) << r.out;
    r = run_vx("world info " + db + " --check");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("records: 43, corrupt: 0"), std::string::npos) << r.out;
}

// --part K/N splits the box into N slabs along x: the parts together are the whole box, and a
// malformed or empty part is one line and exit 2, before any store is touched.
TEST(Cli, WorldGenPartsCoverTheBox) {
    const auto dir = temp_dir() / "parts";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = (dir / "w.db").string();
    CliRun r = run_vx("world gen " + db + " --seed 9 --radius 1 --bottom 0 --top 0 --part 1/2");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(" 3 chunks"), std::string::npos) << r.out; // x = -1 (3 of width 3 * 1 / 2).
    r = run_vx("world gen " + db + " --seed 9 --radius 1 --bottom 0 --top 0 --part 2/2");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(" 6 chunks"), std::string::npos) << r.out; // x = 0 and 1.
    r = run_vx("world info " + db);
    EXPECT_NE(r.out.find("chunks stored: 9"), std::string::npos) << r.out;
    for (const char* bad : {"0/2", "3/2", "1/0", "a/b", "1/2/3"}) {
        r = run_vx("world gen " + db + " --seed 9 --radius 1 --part " + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find("--part"), std::string::npos) << r.out;
    }
    r = run_vx("world gen " + db + " --seed 9 --radius 0 --part 1/2"); // Width 1: the first half is empty.
    EXPECT_EQ(r.code, 2) << r.out;
    // A refused part creates no store (it once left an empty world file behind).
    const std::string fresh = (dir / "fresh.db").string();
    for (const char* bad : {"0/2", "1/2 --radius 0"}) {
        r = run_vx("world gen " + fresh + " --seed 9 --part " + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_FALSE(std::filesystem::exists(fresh)) << bad;
    }
}

// Progress bars draw only on a terminal: piped (as here, and into CI logs) `vx world gen` prints
// no carriage-return frames, just its one summary line.
TEST(Cli, PipedWorldGenPrintsOneSummaryLine) {
    const auto dir = temp_dir() / "piped";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const CliRun r = run_vx("world gen " + (dir / "w.db").string() + " --seed 3 --radius 3 --bottom -2 --top 1");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find('\r'), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find("196 chunks"), std::string::npos) << r.out; // 7 x 4 x 7.
}

namespace {

// Every non-air chunk of a store, for comparisons (the VDB round trip).
[[maybe_unused]] std::map<std::tuple<int, int, int>, vx::world::Chunk> store_chunks(const std::string& path) {
    std::map<std::tuple<int, int, int>, vx::world::Chunk> out;
    auto store = vx::world::SqliteStore::open({path, true, false});
    EXPECT_TRUE(store.ok()) << store.error();
    if (!store)
        return out;
    auto coords = (*store)->list_coords(); // Kept alive: the loop must not range over a temporary's inside.
    EXPECT_TRUE(coords.ok());
    if (!coords)
        return out;
    for (const vx::world::ChunkCoord& c : *coords) {
        auto r = (*store)->load(c);
        if (r && r->chunk && !r->chunk->is_empty())
            out.emplace(std::make_tuple(c.x, c.y, c.z), std::move(*r->chunk));
    }
    return out;
}

} // namespace

#if !VX_WITH_OPENVDB
// Built without OpenVDB: the vdb commands exist and refuse with one line and exit code 2.
TEST(Cli, VdbCommandsSayBuiltWithoutOpenVdb) {
    for (const std::string cmd : {"export-vdb w.db --out w.vdb", "import-vdb w.vdb --out w.db"}) {
        const CliRun r = run_vx(cmd);
        EXPECT_EQ(r.code, 2) << r.out;
        EXPECT_NE(r.out.find("built without OpenVDB"), std::string::npos) << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << r.out;
    }
}
#else
// Store -> VDB -> store is lossless; foreign volumes import; refused files exit 2 and leave an
// existing world untouched.
TEST(Cli, VdbExportImport) {
    const auto dir = temp_dir() / "vdb";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = (dir / "w.db").string(), vdb = (dir / "w.vdb").string(), back = (dir / "back.db").string();
    ASSERT_EQ(run_vx("world gen " + db + " --seed 4 --radius 1 --bottom -1 --top 1").code, 0);
    CliRun r = run_vx("export-vdb " + db + " --out " + vdb);
    ASSERT_EQ(r.code, 0) << r.out;
    r = run_vx("import-vdb " + vdb + " --out " + back);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vx world grid 'blocks'"), std::string::npos) << r.out;
    const auto a = store_chunks(db), b = store_chunks(back);
    EXPECT_EQ(a.size(), b.size());
    for (const auto& [k, chunk] : a) {
        auto it = b.find(k);
        ASSERT_NE(it, b.end());
        EXPECT_TRUE(it->second == chunk);
    }
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 1,2,3").code, 2);
    // The count printed is what the box took, not the store's (it said 27 of an empty box).
    const std::string empty_box = (dir / "empty_box.vdb").string();
    r = run_vx("export-vdb " + db + " --out " + empty_box + " --box 1000,1000,1000,1001,1001,1001");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("vx export-vdb: 0 chunks"), std::string::npos) << r.out;
    // An export over the store it reads (itself, or by a link) is refused: it replaced the store
    // with the VDB file and exited 0.
    const std::string link = (dir / "link.db").string();
    std::filesystem::create_symlink(db, link);
    for (const std::string& out : {db, link}) {
        r = run_vx("export-vdb " + db + " --out " + out);
        EXPECT_EQ(r.code, 2) << r.out;
        EXPECT_NE(r.out.find("which the export reads"), std::string::npos) << r.out;
    }
    EXPECT_EQ(store_chunks(db).size(), a.size());
    // Past 64 bits (strtoll clamped it: an empty export and exit 0) or outside the world.
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 99999999999999999999,0,0,99999999999999999999,1,1")
                  .code,
              2);
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 0,0,0,68719476736,1,1").code, 2);
    // Options are checked before the file is read, and volume options do not pass silently on a
    // vx world (its blocks come back as they were: an --offset would have been ignored).
    const auto refuses = [](const std::string& args, const std::string& says) {
        const CliRun bad = run_vx(args);
        EXPECT_EQ(bad.code, 2) << args << ": " << bad.out;
        EXPECT_NE(bad.out.find(says), std::string::npos) << args << ": " << bad.out;
    };
    for (const std::string threshold : {"nan", "5", "0", "-0.5"})
        refuses("import-vdb /nonexistent.vdb --out " + back + " --threshold " + threshold, "--threshold");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --block 0", "--block");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --index -1", "--index");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --offset 1,2", "--offset");
    for (const char* density : {"0.2:3,", "0.5:3x"}) // Read as 0.2:3 and 0.5:3.
        refuses("import-vdb /nonexistent.vdb --out " + back + " --density " + density, "--density");
    for (const std::string option : {"--offset 32,0,0", "--block 3", "--voxels-per-block 2", "--mode fog"})
        refuses("import-vdb " + vdb + " --out " + back + " " + option, "vx world");
    // Outputs that are folders are refused before any work; no temporary is left beside them.
    const std::string folder = (dir / "folder").string();
    std::filesystem::create_directory(folder);
    refuses("import-vdb " + vdb + " --out " + folder, "not a file");
    refuses("export-vdb " + db + " --out " + folder, "not a file");
    EXPECT_TRUE(std::filesystem::is_directory(folder));
    const auto temporaries = [&dir] {
        int n = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir))
            n += e.path().filename().string().find(".tmp-") != std::string::npos;
        return n;
    };
    EXPECT_EQ(temporaries(), 0);
    {
        // The world open in another process (this one): the import is refused after writing its
        // temporary, which it removes (it was left behind), and the open world is untouched.
        auto open_world = vx::world::SqliteStore::open({back});
        ASSERT_TRUE(open_world) << open_world.error();
        refuses("import-vdb " + vdb + " --out " + back, "open for writing elsewhere");
        EXPECT_EQ(temporaries(), 0);
    }

    // A frustum-transform grid cannot become blocks of one size: refused with a clear line.
    vx::vdb::AnalyticVolume frustum;
    frustum.frustum = true;
    frustum.half_extent = glm::dvec3(4.0);
    const std::string fvdb = (dir / "frustum.vdb").string();
    ASSERT_TRUE(vx::vdb::write_analytic_vdb(fvdb, frustum).ok());
    r = run_vx("import-vdb " + fvdb + " --out " + back);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("vx: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frustum"), std::string::npos) << r.out;

    // Volumes of other tools when shared/data/vdb is present, else the same kinds written here.
    const std::string data = VX_VDB_DATA_DIR;
    std::string grids = data + "/arnoldusd_grids.vdb", sphere_vdb = data + "/gaffer_vdbtest_sphere.vdb",
                fog = data + "/oiio_sphere.vdb";
    std::vector<std::string> refused = {data + "/gaffer_points.vdb", data + "/damaged/oiio_truncated.vdb",
                                        data + "/damaged/oiio_bad-bbox-huge.vdb"};
    if (!std::filesystem::exists(data)) {
        std::printf("generated volumes: no sample VDB files at %s\n", data.c_str());
        grids = (dir / "grids.vdb").string(), sphere_vdb = (dir / "sphere.vdb").string(), fog = (dir / "fog.vdb").string();
        std::vector<vx::vdb::AnalyticVolume> three(3);
        for (size_t i = 0; i < 3; ++i) {
            three[i].name = "density";
            three[i].level_set = false;
            three[i].half_extent = glm::dvec3(4.0 + double(i));
            three[i].centre = glm::dvec3(10.0 * double(i), 0.0, 0.0);
        }
        ASSERT_TRUE(vx::vdb::write_analytic_vdb(grids, std::span<const vx::vdb::AnalyticVolume>(three)));
        vx::vdb::AnalyticVolume ls; // A level set of radius 60 voxels of 0.05.
        ls.name = "ls_sphere";
        ls.half_extent = glm::dvec3(3.0);
        ls.index_to_world = glm::dmat3(0.05);
        ASSERT_TRUE(vx::vdb::write_analytic_vdb(sphere_vdb, ls));
        vx::vdb::AnalyticVolume f = three[0];
        f.index_to_world = glm::dmat3(0.1);
        f.half_extent = glm::dvec3(2.0);
        ASSERT_TRUE(vx::vdb::write_analytic_vdb(fog, f));
        std::ifstream in(fog, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string truncated = (dir / "truncated.vdb").string();
        std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
        refused = {truncated, fvdb};
    }
    r = run_vx("import-vdb " + grids + " --list");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("[2] 'density'"), std::string::npos) << r.out;
    const std::string sphere = (dir / "sphere.db").string();
    r = run_vx("import-vdb " + sphere_vdb + " --out " + sphere + " --voxels-per-block 4");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("levelset"), std::string::npos) << r.out;
    EXPECT_EQ(run_vx("world info " + sphere + " --check").code, 0);
    // --block-size is in the file's world units: 4 voxels of 0.05 = 0.2, the same blocks.
    const std::string solid = r.out.substr(r.out.find("voxels), "), r.out.find(" solid blocks") - r.out.find("voxels), "));
    r = run_vx("import-vdb " + sphere_vdb + " --out " + sphere + " --block-size 0.2");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(solid + " solid blocks"), std::string::npos) << solid << " vs " << r.out;
    for (const std::string bad : {"-0.2", "0", "nan", "inf", "abc"}) {
        r = run_vx("import-vdb " + sphere_vdb + " --out " + sphere + " --block-size " + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    }
    EXPECT_EQ(run_vx("import-vdb " + fog + " --out " + sphere + " --block-size 0.2 --voxels-per-block 2").code, 2);

    // Refused imports over an existing world leave it as it was.
    const auto before = store_chunks(back);
    for (const std::string& bad : refused) {
        r = run_vx("import-vdb " + bad + " --out " + back);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find("vx: "), std::string::npos) << r.out;
    }
    EXPECT_EQ(store_chunks(back).size(), before.size());
    EXPECT_EQ(run_vx("world info " + back + " --check").code, 0);
}

// A VDB world played with edits (its overlay beside it) exports merged; the isolated reader's caps
// are options, and hitting the memory cap names the option.
// A world's own block table (names and materials, ids past the default palette) survives
// import-vdb into a store and export-vdb out of it: the store kept no table and the export wrote
// the default palette's names over the imported ids.
TEST(Cli, VdbBlockTableSurvivesTheStore) {
    const auto dir = temp_dir() / "vdb_registry";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    vx::world::BlockRegistry custom;
    for (int i = 1; i <= 40; ++i) {
        vx::world::BlockInfo b;
        b.name = "rock " + std::to_string(i);
        b.albedo = glm::vec3(float(i) / 41.f, 0.25f, 0.75f);
        b.reflectivity = i % 4 == 0 ? 0.5f : 0.f;
        b.emission = i == 7 ? glm::vec3(2.f, 1.f, 0.5f) : glm::vec3(0.f);
        b.opaque = i % 10 != 0;
        ASSERT_TRUE(custom.add(b).ok());
    }
    vx::world::World w(custom);
    for (int i = 1; i <= 40; ++i)
        w.set_block(vx::world::BlockPos(i, 2, 3), vx::world::BlockId(i));
    const std::string in = (dir / "in.vdb").string(), db = (dir / "w.db").string(), out = (dir / "out.vdb").string();
    ASSERT_TRUE(vx::vdb::export_vdb(w, in).ok());
    CliRun r = run_vx("import-vdb " + in + " --out " + db);
    ASSERT_EQ(r.code, 0) << r.out;
    r = run_vx("export-vdb " + db + " --out " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    auto back = vx::vdb::import_world_vdb(out);
    ASSERT_TRUE(back.ok()) << back.error();
    for (int i = 1; i <= 40; ++i) {
        const vx::world::BlockInfo want = custom.info(vx::world::BlockId(i)), got = back->registry().info(vx::world::BlockId(i));
        EXPECT_EQ(got.name, want.name);
        EXPECT_EQ(got.albedo, want.albedo) << want.name;
        EXPECT_EQ(got.reflectivity, want.reflectivity) << want.name;
        EXPECT_EQ(got.emission, want.emission) << want.name;
        EXPECT_EQ(got.opaque, want.opaque) << want.name;
        EXPECT_EQ(back->get_block(vx::world::BlockPos(i, 2, 3)), vx::world::BlockId(i));
    }
    // The names the engine holds a game's blocks to are recorded too: a game opening the imported
    // world with the default blocks is refused instead of rewriting what ids 1.. mean.
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(raw, "SELECT value FROM meta WHERE key='blocks'", -1, &st, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    const std::string names = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    EXPECT_EQ(names.rfind("rock 1\nrock 2\nrock 3\n", 0), 0u) << names;
    // A damaged table is one line naming it, and no file.
    ASSERT_EQ(sqlite3_exec(raw, "UPDATE meta SET value='rock\t1 1\t0\t0 0 0\t1' WHERE key='registry'", nullptr,
                           nullptr, nullptr),
              SQLITE_OK);
    EXPECT_EQ(sqlite3_changes(raw), 1);
    sqlite3_close(raw);
    const std::string refused = (dir / "refused.vdb").string();
    r = run_vx("export-vdb " + db + " --out " + refused);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("block table line 1"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(refused));
}

TEST(Cli, VdbWorldExportsWithItsEditsAndReaderCapsAreOptions) {
    const auto dir = temp_dir() / "vdb_overlay";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = (dir / "w.db").string(), vdb = (dir / "w.vdb").string();
    const std::string merged = (dir / "merged.vdb").string(), back = (dir / "back.db").string();
    ASSERT_EQ(run_vx("world gen " + db + " --seed 4 --radius 1 --bottom -1 --top 1").code, 0);
    ASSERT_EQ(run_vx("export-vdb " + db + " --out " + vdb).code, 0);
    CliRun r = run_vx("export-vdb " + vdb + " --out " + merged); // No overlay yet: one line.
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    const vx::world::ChunkCoord c(0, 0, 0);
    vx::world::Chunk edited(7);
    {
        auto store =
            vx::vdb::VdbOverlayStore::open({.vdb_path = vdb, .overlay = {}, .read_only = false, .read = {}});
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->save(c, edited));
        ASSERT_TRUE((*store)->erase(vx::world::ChunkCoord(1, 0, 1)));
        ASSERT_TRUE((*store)->flush());
    }
    r = run_vx("export-vdb " + vdb + " --out " + merged + " --compression none");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("with its edits"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("not streamed"), std::string::npos) << r.out; // vx's own file streams.
    ASSERT_EQ(run_vx("import-vdb " + merged + " --out " + back + " --max-memory 8 --max-seconds 300").code, 0);
    auto chunks = store_chunks(back), original = store_chunks(db);
    ASSERT_EQ(chunks.count({0, 0, 0}), 1u);
    EXPECT_TRUE(chunks.at({0, 0, 0}) == edited);
    EXPECT_EQ(chunks.count({1, 0, 1}), 0u); // Erased (an empty chunk is not exported).
    for (const auto& [k, chunk] : original) {
        if (k != std::tuple<int, int, int>{0, 0, 0} && k != std::tuple<int, int, int>{1, 0, 1}) {
            EXPECT_TRUE(chunks.count(k) && chunks.at(k) == chunk);
        }
    }
    EXPECT_EQ(run_vx("export-vdb " + db + " --overlay x.sqlite --out " + merged).code, 2);

    // A reader capped at 1/64 GiB runs out of memory: one line naming the option. Not under
    // ASan: it reserves terabytes of address space, so the reader gets no RLIMIT_AS there
    // (vdb_isolated.cpp) and has no memory cap to hit.
#if !defined(__SANITIZE_ADDRESS__)
    r = run_vx("import-vdb " + merged + " --out " + back + " --max-memory 0.015625");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("--max-memory"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
#endif
    EXPECT_EQ(run_vx("import-vdb " + merged + " --out " + back + " --max-seconds abc").code, 2);
    // A cap that is not a finite size is refused before any reader starts (NaN would reach the
    // cast to bytes: CLI::Range lets it through).
    for (const char* bad : {"nan", "inf", "-1", "8x"}) {
        r = run_vx("import-vdb " + merged + " --out " + back + " --max-memory=" + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find("--max-memory"), std::string::npos) << r.out;
    }

    // A reader capped at 1 s of CPU on an import of about a minute (a level set of radius 150
    // voxels at one voxel per block: ~15x the 3-4 s of radius 60 here) stops with one line naming
    // the option; the cap, not the machine's speed, ends it.
    vx::vdb::AnalyticVolume big;
    big.half_extent = glm::dvec3(7.5);
    big.index_to_world = glm::dmat3(0.05);
    const std::string big_vdb = (dir / "big.vdb").string();
    ASSERT_TRUE(vx::vdb::write_analytic_vdb(big_vdb, big));
    r = run_vx("import-vdb " + big_vdb + " --out " + back + " --voxels-per-block 1 --max-seconds 1");
    EXPECT_EQ(r.code, 2) << r.out;
    const size_t line = r.out.find("vx: "); // After the "importing ..." progress line.
    ASSERT_NE(line, std::string::npos) << r.out;
    EXPECT_NE(r.out.find("CPU time limit of 1 s (raise --max-seconds", line), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin() + std::ptrdiff_t(line), r.out.end(), '\n'), 1) << r.out;
}
// `vx bench vdb --dir D` makes its scratch folder inside D and removes only that: it once removed
// D itself, with whatever the user kept there (or a file named as D). A base that is a file is
// refused with exit 2 and left alone; an unusable $TMPDIR no longer aborts --help.
TEST(Cli, BenchVdbRemovesOnlyTheFolderItMade) {
    const auto dir = temp_dir() / "bench_vdb_keep";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "notes.txt") << "kept\n";
    CliRun r = run_vx("bench vdb --side 1 --dir " + dir.string());
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(read_file(dir / "notes.txt"), "kept\n");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1)
        << "the scratch folder is gone, the note stays";
    r = run_vx("bench vdb --side 1 --dir " + (dir / "notes.txt").string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("cannot make a scratch folder in"), std::string::npos) << r.out;
    EXPECT_EQ(read_file(dir / "notes.txt"), "kept\n");
    r = run_vx("bench vdb --help", "TMPDIR=" + (dir / "notes.txt").string());
    EXPECT_EQ(r.code, 0) << r.out;
    // An --exe that is no vx (missing, or /bin/true: exit 0, no file) is an error, not figures of
    // 0 MB and 18446744073709.6 MB.
    for (const std::string exe : {"/nonexistent/vx", "/bin/true"}) {
        r = run_vx("bench vdb --side 1 --dir " + dir.string() + " --exe " + exe);
        EXPECT_EQ(r.code, 2) << exe << ": " << r.out;
        EXPECT_NE(r.out.find("is not a vx"), std::string::npos) << r.out;
        EXPECT_EQ(r.out.find("peak RSS"), std::string::npos) << r.out;
    }
    // One that refuses a missing file as vx does, then "exports" without writing anything.
    const auto fake = dir / "fake_vx.sh";
    std::ofstream(fake) << "#!/bin/sh\n[ -e \"$2\" ] || exit 2\nexit 0\n";
    std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
    r = run_vx("bench vdb --side 1 --dir " + dir.string() + " --exe " + fake.string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("wrote no"), std::string::npos) << r.out;
}
#endif

// `vx bench store` with an unusable $TMPDIR (here a file) reports that its scratch folder cannot
// be made and touches nothing: it once fell back to /tmp and removed all of /tmp at exit. The
// benchmark that could not run makes the exit 1 (Google Benchmark alone exits 0 after it).
TEST(Cli, BenchStoreWithAnUnusableTmpdirTouchesNothing) {
    if (run_vx("bench store --help").code != 0)
        GTEST_SKIP() << "this build has no benchmarks (VX_BUILD_BENCHMARKS=OFF)";
    const auto dir = temp_dir() / "bench_store_tmpdir";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto file = dir / "not_a_folder";
    std::ofstream(file) << "kept\n";
    const CliRun r = run_vx("bench store --benchmark_filter=store/sqlite_save_chunks_per_commit/64", "TMPDIR=" + file.string());
    EXPECT_NE(r.out.find("cannot make a scratch folder in '" + file.string() + "'"), std::string::npos) << r.out;
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("vx: benchmark failed, no figure: store/sqlite_save_chunks_per_commit/64"), std::string::npos) << r.out;
    EXPECT_EQ(read_file(file), "kept\n");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
}
