// The vx CLI's VDB commands (export-vdb, import-vdb, bench vdb), run as a user would.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <span>
#include <sstream>
#include <string>
#include <tuple>
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

using cli_test::read_file;

using cli_test::CliRun;
using cli_test::temp_dir;

CliRun run_vx(const std::string& args, const std::string& env = "") { return cli_test::vx(args, env); }


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
namespace {

// `vx <args>` is refused: exit 2, and the output says `says`.
void refuses(const std::string& args, const std::string& says) {
    const CliRun bad = run_vx(args);
    EXPECT_EQ(bad.code, 2) << args << ": " << bad.out;
    EXPECT_NE(bad.out.find(says), std::string::npos) << args << ": " << bad.out;
}

// Exports of the round trip's world `db` (holding `stored` chunks) that take nothing or are refused,
// the world left as it was.
void expect_export_refusals(const std::filesystem::path& dir, const std::string& db, const std::string& vdb,
                            size_t stored) {
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 1,2,3").code, 2);
    // The count printed is what the box took, not the store's (it said 27 of an empty box).
    const std::string empty_box = (dir / "empty_box.vdb").string();
    CliRun r = run_vx("export-vdb " + db + " --out " + empty_box + " --box 1000,1000,1000,1001,1001,1001");
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
    EXPECT_EQ(store_chunks(db).size(), stored);
    // Past 64 bits (strtoll clamped it: an empty export and exit 0) or outside the world.
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 99999999999999999999,0,0,99999999999999999999,1,1")
                  .code,
              2);
    EXPECT_EQ(run_vx("export-vdb " + db + " --out " + vdb + " --box 0,0,0,68719476736,1,1").code, 2);
}

// Options are checked before the file is read, and volume options do not pass silently on a
// vx world (its blocks come back as they were: an --offset would have been ignored).
void expect_import_option_refusals(const std::string& vdb, const std::string& back) {
    for (const std::string threshold : {"nan", "5", "0", "-0.5"})
        refuses("import-vdb /nonexistent.vdb --out " + back + " --threshold " + threshold, "--threshold");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --block 0", "--block");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --index -1", "--index");
    refuses("import-vdb /nonexistent.vdb --out " + back + " --offset 1,2", "--offset");
    for (const char* density : {"0.2:3,", "0.5:3x"}) // Read as 0.2:3 and 0.5:3.
        refuses("import-vdb /nonexistent.vdb --out " + back + " --density " + density, "--density");
    for (const std::string option : {"--offset 32,0,0", "--block 3", "--voxels-per-block 2", "--mode fog"})
        refuses("import-vdb " + vdb + " --out " + back + " " + option, "vx world");
}

// Volumes of other tools import: a file's grids listed, a level set by voxels per block and by block
// size (the same blocks), bad block sizes refused.
void expect_foreign_imports(const std::filesystem::path& dir, const std::string& grids, const std::string& sphere_vdb,
                            const std::string& fog) {
    CliRun r = run_vx("import-vdb " + grids + " --list");
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
}

} // namespace

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
    expect_export_refusals(dir, db, vdb, a.size());
    expect_import_option_refusals(vdb, back);
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
    expect_foreign_imports(dir, grids, sphere_vdb, fog);

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

// A VDB world played with edits (its overlay beside it) exports merged; the isolated reader's caps
// are options, and hitting the memory cap names the option.
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
