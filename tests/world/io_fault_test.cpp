// The world's file writers under injected stdio failures. This binary links with
// -Wl,--wrap=fclose (tests/world/CMakeLists.txt): every fclose in it, the writers' included, goes
// through __wrap_fclose below, which can make a chosen close fail after it has closed the file,
// as close(2) does when NFS or a quota reports a lost write there (EIO). No file system here fails
// a close on demand, and /dev/full cannot stand in for an OBJ export (its .mtl goes beside it).
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "world/io/obj_export.h"
#include "world/io/raw_volume.h"

namespace {

// The close to fail, counted from the arming: 0 the next one; -1 none.
std::atomic<int> g_closes_until_failure{-1};

void fail_close(int nth) { g_closes_until_failure = nth; }

} // namespace

// Names fixed by the linker's --wrap (ld(1)): reserved identifiers, on purpose.
extern "C" int __real_fclose(std::FILE* f);
extern "C" int __wrap_fclose(std::FILE* f) {
    const int r = __real_fclose(f);
    if (g_closes_until_failure.load() >= 0 && g_closes_until_failure.fetch_sub(1) == 0) {
        errno = EIO;
        return EOF;
    }
    return r;
}

using namespace vx::world;

namespace {

std::filesystem::path temp_dir() {
    const auto d = std::filesystem::temp_directory_path() / "vx_io_fault";
    std::filesystem::create_directories(d);
    return d;
}

std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Two blocks of two types in one chunk, meshed: 12 faces (no face between them is shared).
struct TwoBlocks {
    World world{BlockRegistry{}}; // Empty: the two types get ids 1 and 2.
    MeshMap meshes;
    TwoBlocks() {
        BlockInfo red, blue;
        red.name = "red";
        red.albedo = {0.8f, 0.1f, 0.1f};
        blue.name = "blue";
        blue.albedo = {0.1f, 0.2f, 0.9f};
        EXPECT_TRUE(world.registry().add(red).ok());
        EXPECT_TRUE(world.registry().add(blue).ok());
        world.set_block(BlockPos(1, 1, 1), 1);
        world.set_block(BlockPos(5, 1, 1), 2);
        EditMesher().mesh_chunk(world, ChunkCoord(0, 0, 0), meshes);
    }
};

} // namespace

TEST(IoFault, ObjExportWritesEveryFaceWithItsMaterial) {
    TwoBlocks s;
    const auto obj = temp_dir() / "two.obj";
    auto r = write_obj(obj.string(), s.meshes, s.world.registry());
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->quads, 12u);
    EXPECT_EQ(r->vertices, 48u);
    const std::string text = read_text(obj), mtl = read_text(temp_dir() / "two.mtl");
    EXPECT_NE(text.find("mtllib two.mtl"), std::string::npos);
    EXPECT_NE(text.find("usemtl block_1"), std::string::npos);
    EXPECT_NE(text.find("usemtl block_2"), std::string::npos);
    EXPECT_NE(text.find("v 6 2 2"), std::string::npos) << "the blue block's far corner";
    EXPECT_NE(mtl.find("newmtl block_2\nKd 0.1000 0.2000 0.9000"), std::string::npos) << mtl;
    std::filesystem::remove(obj);
    std::filesystem::remove(temp_dir() / "two.mtl");
}

// The names in `dir`, sorted: a failed write must leave no temporary behind.
std::vector<std::string> names_in(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::filesystem::path fresh_dir(const char* name) {
    const auto d = temp_dir() / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

void write_text(const std::filesystem::path& p, const std::string& text) { std::ofstream(p) << text; }

// A close that fails is an error naming the file, for each of the export's two files, and leaves
// the previous export as it was: no cut file, no temporary. The injection is checked to have
// fired (the wrap is in force) before the result is judged.
TEST(IoFault, ObjExportReportsAFailedCloseAndKeepsThePreviousFiles) {
    TwoBlocks s;
    const auto dir = fresh_dir("obj_close");
    const auto obj = dir / "closing.obj", mtl = dir / "closing.mtl";
    write_text(obj, "previous obj\n");
    write_text(mtl, "previous mtl\n");
    for (int nth : {0, 1}) { // The .mtl is closed first, then the .obj.
        fail_close(nth);
        auto r = write_obj(obj.string(), s.meshes, s.world.registry());
        ASSERT_EQ(g_closes_until_failure.load(), -1) << "the injected failure did not fire";
        ASSERT_FALSE(r.ok()) << "close " << nth;
        const std::string file = nth == 0 ? "closing.mtl" : "closing.obj";
        EXPECT_NE(r.error().find("closing '"), std::string::npos) << r.error();
        EXPECT_NE(r.error().find(file), std::string::npos) << r.error();
        EXPECT_NE(r.error().find(std::strerror(EIO)), std::string::npos) << r.error();
        EXPECT_EQ(read_text(obj), "previous obj\n") << "close " << nth;
        EXPECT_EQ(read_text(mtl), "previous mtl\n") << "close " << nth;
        EXPECT_EQ(names_in(dir), (std::vector<std::string>{"closing.mtl", "closing.obj"})) << "close " << nth;
    }
    ASSERT_TRUE(write_obj(obj.string(), s.meshes, s.world.registry()).ok()); // The injection is spent.
    EXPECT_NE(read_text(obj).find("mtllib closing.mtl"), std::string::npos);
    EXPECT_NE(read_text(mtl).find("newmtl block_1"), std::string::npos);
    EXPECT_EQ(names_in(dir), (std::vector<std::string>{"closing.mtl", "closing.obj"}));
    std::filesystem::remove_all(dir);
}

// Where nothing was exported before, a failed export leaves nothing: no pair half written.
TEST(IoFault, AFailedFirstObjExportLeavesNoFile) {
    TwoBlocks s;
    const auto dir = fresh_dir("obj_first");
    fail_close(1); // The .obj's close: the .mtl was whole, but without its .obj it goes too.
    auto r = write_obj((dir / "first.obj").string(), s.meshes, s.world.registry());
    ASSERT_EQ(g_closes_until_failure.load(), -1) << "the injected failure did not fire";
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(names_in(dir).empty()) << names_in(dir).front();
    std::filesystem::remove_all(dir);
}

TEST(IoFault, RawVolumeReportsAFailedCloseAndKeepsThePreviousFile) {
    World w;
    w.set_block(BlockPos(1, 2, 3), 7);
    const auto dir = fresh_dir("raw_close");
    const std::string path = (dir / "closing.raw").string();
    write_text(path, "previous");
    fail_close(0);
    const vx::Status st = save_raw_volume(path, {glm::i64vec3(8, 8, 8), RawType::U8, BlockPos(0)}, w);
    ASSERT_EQ(g_closes_until_failure.load(), -1) << "the injected failure did not fire";
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().find("closing '" + path + "'"), std::string::npos) << st.error();
    EXPECT_NE(st.error().find(std::strerror(EIO)), std::string::npos) << st.error();
    EXPECT_EQ(read_text(path), "previous");
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"closing.raw"});
    ASSERT_TRUE(save_raw_volume(path, {glm::i64vec3(8, 8, 8), RawType::U8, BlockPos(0)}, w).ok());
    EXPECT_EQ(std::filesystem::file_size(path), 512u);
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"closing.raw"});
    std::filesystem::remove_all(dir);
}
