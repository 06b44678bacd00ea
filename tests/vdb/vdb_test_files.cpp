#include "tests/vdb/vdb_test_files.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <unistd.h>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

namespace vx::vdb::test {
namespace {

// A fog ball: density 1 - |p| / r on voxels with |p| <= r (index space, centred on `centre`).
openvdb::FloatGrid::Ptr fog_ball(openvdb::Coord centre, int r) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    openvdb::FloatGrid::Accessor acc = grid->getAccessor();
    for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
            for (int x = -r; x <= r; ++x) {
                const double d = std::sqrt(double(x * x + y * y + z * z));
                if (d <= r)
                    acc.setValueOn(centre.offsetBy(x, y, z), float(std::max(1.0 - d / r, 0.01)));
            }
    return grid;
}

// A narrow-band level set of the sphere |p| = r (voxels), 3 voxels of band each side.
openvdb::FloatGrid::Ptr level_set_sphere(int r, double voxel) {
    const float band = float(3 * voxel);
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(band);
    grid->setName("ls_sphere");
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    openvdb::FloatGrid::Accessor acc = grid->getAccessor();
    const int n = r + 4;
    for (int z = -n; z <= n; ++z)
        for (int y = -n; y <= n; ++y)
            for (int x = -n; x <= n; ++x) {
                const double d = std::sqrt(double(x * x + y * y + z * z)) - r; // Voxels, < 0 inside.
                if (std::abs(d) < 3)
                    acc.setValueOn({x, y, z}, float(d * voxel));
                else if (d < 0)
                    acc.setValueOff({x, y, z}, -band);
            }
    grid->tree().prune(); // Uniform interior leaves become tiles, as in OpenVDB's own level sets.
    return grid;
}

bool write(const std::string& path, const openvdb::GridPtrVec& grids) {
    try {
        openvdb::io::File(path).write(grids);
        return true;
    } catch (const openvdb::Exception& e) {
        ADD_FAILURE() << "cannot write " << path << ": " << e.what();
        return false;
    }
}

struct Folder {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("vx_vdb_test_files_" + std::to_string(::getpid()));
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

} // namespace

const std::string& test_file(TestFile which) {
    static Folder folder;
    static std::map<TestFile, std::string> written;
    if (auto it = written.find(which); it != written.end())
        return it->second;
    openvdb::initialize();
    std::string path;
    openvdb::GridPtrVec grids;
    switch (which) {
    case TestFile::FogSphere:
        path = (folder.path / "fog_sphere.vdb").string();
        grids.push_back(fog_ball({0, 0, 0}, 12));
        break;
    case TestFile::LevelSetSphere:
        path = (folder.path / "level_set_sphere.vdb").string();
        grids.push_back(level_set_sphere(60, 0.05));
        break;
    case TestFile::ThreeDensities:
        path = (folder.path / "three_densities.vdb").string();
        grids.push_back(fog_ball({0, 0, 0}, 6));
        grids.push_back(fog_ball({0, -4, 1}, 9));
        grids.push_back(fog_ball({20, 0, 0}, 4));
        break;
    case TestFile::ColourField: {
        path = (folder.path / "colour_field.vdb").string();
        openvdb::Vec3SGrid::Ptr cd = openvdb::Vec3SGrid::create();
        cd->setName("Cd");
        cd->denseFill(openvdb::CoordBBox({0, 0, 0}, {3, 3, 3}), openvdb::Vec3s(1.f, 0.5f, 0.f), true);
        grids.push_back(cd);
        break;
    }
    case TestFile::EmptyFog: {
        path = (folder.path / "empty_fog.vdb").string();
        openvdb::FloatGrid::Ptr empty = openvdb::FloatGrid::create(0.f);
        empty->setName("density");
        empty->setGridClass(openvdb::GRID_FOG_VOLUME);
        grids.push_back(empty);
        break;
    }
    case TestFile::Truncated: {
        path = (folder.path / "truncated.vdb").string();
        const std::string& whole = test_file(TestFile::FogSphere);
        std::ifstream in(whole, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
        return written[which] = path;
    }
    case TestFile::FloatBlocks: {
        path = (folder.path / "float_blocks.vdb").string();
        openvdb::FloatGrid::Ptr blocks = openvdb::FloatGrid::create(0.f);
        blocks->setName("blocks");
        blocks->denseFill(openvdb::CoordBBox({0, 0, 0}, {1, 1, 1}), 3.f, true);
        grids.push_back(blocks);
        break;
    }
    case TestFile::InstancedBlocks: {
        path = (folder.path / "instanced_blocks.vdb").string();
        openvdb::Int32Grid::Ptr terrain = openvdb::Int32Grid::create(0);
        terrain->setName("terrain");
        terrain->denseFill(openvdb::CoordBBox({0, 0, 0}, {1, 1, 1}), 3, true);
        openvdb::Int32Grid::Ptr blocks = openvdb::Int32Grid::create(terrain->treePtr());
        blocks->setName("blocks");
        grids.push_back(terrain);
        grids.push_back(blocks);
        break;
    }
    }
    if (!write(path, grids))
        path.clear();
    return written[which] = path;
}

} // namespace vx::vdb::test
