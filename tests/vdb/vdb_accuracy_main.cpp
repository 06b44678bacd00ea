// vx_vdb_accuracy [--samples N] [--grid I] [--analytic] [file.vdb ...]: accuracy and time of volume
// import at block sizes 1, 2, 4, 8 voxels against an 8³-supersampled reference, for the given
// files, or every real sample file and then analytic shapes on rotated, translated and
// non-uniformly scaled grids (compared with the exact shape too: truth_IoU, vol_err, bound_err);
// --analytic: the analytic shapes only.
// vx_vdb_accuracy --world N [--no-zip]: export/import time of an N x 4 x N-chunk terrain world.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "world/vdb/vdb_accuracy.h"
#include "world/vdb/vdb_analytic.h"

namespace {

struct AnalyticCase {
    std::string title;
    vx::vdb::AnalyticVolume shape;
    double unit = 0; // > 0: block size N * unit world units (non-cubic voxels); else N voxels.
};

// The shapes of vdb_transform_test, plus an unrotated sphere and a rotated box on an axis-aligned
// grid for comparison. Voxel 0.1 (fog: 0.05 x 0.025 x 0.075), radius/half edges 2-3 world units.
std::vector<AnalyticCase> analytic_cases() {
    using vx::vdb::AnalyticShape;
    using vx::vdb::axis_rotation;
    std::vector<AnalyticCase> out;
    vx::vdb::AnalyticVolume v;
    v.name = "sphere_axis_aligned";
    v.centre = {10.3, -4.2, 7.7};
    v.half_extent = glm::dvec3(3.0);
    v.index_to_world = glm::dmat3(0.1);
    out.push_back({"level-set sphere r 3, voxel 0.1, axis-aligned grid, no translation", v});
    v.name = "sphere_rotated";
    v.index_to_world = axis_rotation(35, {1, 2, 3}) * 0.1;
    v.translation = {9.87, -4.01, 7.13};
    out.push_back({"level-set sphere r 3, grid rotated 35 deg about (1,2,3) and translated", v});
    v = {};
    v.name = "box_rotated_grid";
    v.shape = AnalyticShape::Box;
    v.centre = {-3.05, 1.63, 2.35};
    v.half_extent = glm::dvec3(2.0);
    v.rotation = axis_rotation(45, {0, 1, 0});
    v.index_to_world = v.rotation * 0.1;
    v.translation = {-3.0, 1.5, 2.0};
    out.push_back({"level-set cube edge 4 rotated 45 deg about y, grid rotated with it", v});
    v.name = "box_axis_grid";
    v.index_to_world = glm::dmat3(0.1);
    v.translation = glm::dvec3(0.0);
    out.push_back({"the same cube sampled on an axis-aligned grid", v});
    v = {};
    v.name = "fog_ellipsoid";
    v.level_set = false;
    v.centre = {0.4, 0.3, -0.6};
    v.half_extent = {0.8, 0.4, 1.2};
    v.index_to_world = glm::dmat3(glm::dvec3(0.05, 0, 0), glm::dvec3(0, 0.025, 0), glm::dvec3(0, 0, 0.075));
    v.translation = v.centre;
    out.push_back({"fog sphere of 16 voxels scaled (0.05, 0.025, 0.075): ellipsoid (0.8, 0.4, 1.2); B x 0.025", v, 0.025});
    return out;
}

int run_analytic(const vx::vdb::VolumeImportOptions& base, const int (&sizes)[4]) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("vx_vdb_accuracy_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    int failures = 0;
    for (const AnalyticCase& c : analytic_cases()) {
        const std::string path = (dir / (c.shape.name + ".vdb")).string();
        vx::vdb::VolumeImportOptions o = base;
        o.block_size = c.unit;
        if (!c.shape.level_set)
            o.threshold = 0.5f; // The written density is 0.5 on the surface.
        vx::Status s = vx::vdb::write_analytic_vdb(path, c.shape);
        vx::Result<std::vector<vx::vdb::AccuracyRow>> rows =
            s ? vx::vdb::measure_vdb_accuracy(path, sizes, o, &c.shape) : vx::Result<std::vector<vx::vdb::AccuracyRow>>(vx::Error{s.error()});
        if (!rows) {
            std::fprintf(stderr, "%s: %s\n", c.title.c_str(), rows.error().c_str());
            ++failures;
            continue;
        }
        std::printf("%s\n%s\n", c.title.c_str(), vx::vdb::format_accuracy_table(*rows).c_str());
        std::fflush(stdout);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    return failures;
}

// Rolling terrain: stone, 3 dirt, grass at height 64 + 20 sin(x/17) cos(z/23); chunks fully below
// it are uniform stone (tiles in the file), above it absent. About 40% of chunks are uniform.
vx::world::World terrain(int n) {
    using namespace vx::world;
    World w;
    std::vector<BlockId> ids(kChunkVolume);
    for (int cz = 0; cz < n; ++cz)
        for (int cx = 0; cx < n; ++cx)
            for (int cy = 0; cy < 4; ++cy) {
                for (int z = 0; z < kChunkSize; ++z)
                    for (int x = 0; x < kChunkSize; ++x) {
                        const int gx = cx * kChunkSize + x, gz = cz * kChunkSize + z;
                        const int h = 64 + int(20 * std::sin(gx / 17.0) * std::cos(gz / 23.0));
                        for (int y = 0; y < kChunkSize; ++y) {
                            const int gy = cy * kChunkSize + y;
                            ids[size_t(local_index(x, y, z))] = gy > h ? kAir : gy == h ? 3 : gy > h - 4 ? 2 : 1;
                        }
                    }
                Chunk c = Chunk::from_dense(ids);
                if (!c.is_empty())
                    w.put_chunk(ChunkCoord(cx, cy, cz), std::move(c));
            }
    return w;
}

int world_bench(int n, bool zip) {
    const vx::world::World w = terrain(n);
    const std::string path = "/tmp/vx_vdb_world_bench.vdb";
    vx::vdb::VdbExportOptions o;
    o.compression = zip ? vx::vdb::VdbCompression::Zip : vx::vdb::VdbCompression::None;
    vx::Result<vx::vdb::WorldRoundTripStats> st = vx::vdb::measure_world_roundtrip(w, path, o);
    std::remove(path.c_str());
    if (!st) {
        std::fprintf(stderr, "%s\n", st.error().c_str());
        return 1;
    }
    const double blocks = double(st->chunks) * vx::world::kChunkVolume;
    std::printf("world %d x 4 x %d, %s: %llu chunks, file %.2f MB (%.2f bytes/chunk), export %.3f s (%.1f Mblocks/s), "
                "import %.3f s (%.1f Mblocks/s), exact %s\n",
                n, n, zip ? "zip" : "no zip", (unsigned long long)st->chunks, st->file_bytes / 1e6, double(st->file_bytes) / double(st->chunks),
                st->export_seconds, blocks / st->export_seconds / 1e6, st->import_seconds,
                blocks / st->import_seconds / 1e6, st->exact ? "yes" : "NO");
    return st->exact ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && std::string(argv[1]) == "--world")
        return world_bench(std::atoi(argv[2]), !(argc == 4 && std::string(argv[3]) == "--no-zip"));
    std::vector<std::string> files;
    vx::vdb::VolumeImportOptions base;
    bool analytic_only = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--analytic")
            analytic_only = true;
        else if (a == "--samples" && i + 1 < argc)
            base.samples_per_axis = std::atoi(argv[++i]);
        else if (a == "--grid" && i + 1 < argc)
            base.grid_index = std::atoi(argv[++i]);
        else
            files.push_back(a);
    }
    const bool analytic = files.empty();
    if (files.empty() && !analytic_only)
        for (const char* f : {"gaffer_vdbtest_sphere.vdb", "arnoldusd_smoke.vdb", "arnoldusd_torus01.vdb",
                              "oiio_sphere.vdb", "gaffer_arnoldtest_sphere.vdb", "arnoldusd_grids.vdb"})
            files.push_back(std::string(VX_VDB_DATA_DIR) + "/" + f);
    const int sizes[] = {1, 2, 4, 8};
    int failures = 0;
    for (const std::string& f : files) {
        vx::Result<std::vector<vx::vdb::AccuracyRow>> rows = vx::vdb::measure_vdb_accuracy(f, sizes, base);
        if (!rows) {
            std::fprintf(stderr, "%s\n", rows.error().c_str());
            ++failures;
            continue;
        }
        std::printf("%s\n%s\n", f.c_str(), vx::vdb::format_accuracy_table(*rows).c_str());
        std::fflush(stdout);
    }
    if (analytic)
        failures += run_analytic(base, sizes);
    return failures ? 1 : 0;
}
