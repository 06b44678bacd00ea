// Runs the vx binary as a user would: exit codes, messages and outputs.
#include <algorithm>
#include <array>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "world/store/sqlite_store.h"
#include <glm/glm.hpp>

#include "cli_run.h"

namespace {

using cli_test::read_file;

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
