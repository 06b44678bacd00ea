// vx_vdb_accuracy [--samples N] [--grid I] [file.vdb ...]: accuracy and time of volume import at
// block sizes 1, 2, 4, 8 against an 8³-supersampled reference, for the given files or every real
// sample file.
// vx_vdb_accuracy --world N [--no-zip]: export/import time of an N x 4 x N-chunk terrain world.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "world/vdb/vdb_accuracy.h"

namespace {

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
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--samples" && i + 1 < argc)
            base.samples_per_axis = std::atoi(argv[++i]);
        else if (a == "--grid" && i + 1 < argc)
            base.grid_index = std::atoi(argv[++i]);
        else
            files.push_back(a);
    }
    if (files.empty())
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
    return failures ? 1 : 0;
}
