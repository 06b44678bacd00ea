// vx_vdb_accuracy [--samples N] [--grid I] [file.vdb ...]: accuracy and time of volume import at block sizes 1, 2, 4, 8
// against an 8³-supersampled reference, for the given files or every real sample file.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "world/vdb/vdb_accuracy.h"

int main(int argc, char** argv) {
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
