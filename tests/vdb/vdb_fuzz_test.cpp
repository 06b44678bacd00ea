// Mutated copies of the real VDB files (bit flips, byte overwrites, truncation) must import or be
// refused with an error: never crash, hang or use more than a memory cap. Each import runs in a
// forked child (with RLIMIT_AS and RLIMIT_CPU), so a crash is caught and reported instead of
// killing the test. The parent never touches OpenVDB (no TBB threads exist when it forks).

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <new>
#include <random>
#include <sstream>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "tests/vdb/vdb_test_util.h"
#include "world/vdb/vdb_volume.h"
#include "world/vdb/vdb_world.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kCapMemory = false; // Sanitizers reserve terabytes of address space.
#else
constexpr bool kCapMemory = true;
#endif

namespace vx::vdb {
namespace {

constexpr rlim_t kMemoryCap = rlim_t(1) << 30; // Address space per child.
constexpr rlim_t kCpuSeconds = 20;             // A child over this is a hang.

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string mutate(std::string bytes, std::mt19937& rng) {
    switch (rng() % 4) {
    case 0: // Bit flips.
        for (int i = 0, n = 1 + int(rng() % 8); i < n; ++i)
            bytes[rng() % bytes.size()] ^= char(1u << (rng() % 8));
        break;
    case 1: // Random bytes over a short run (lengths, counts, type names).
        for (size_t i = rng() % bytes.size(), n = 1 + rng() % 8; n > 0 && i < bytes.size(); --n, ++i)
            bytes[i] = char(rng());
        break;
    case 2: // Truncation.
        bytes.resize(rng() % bytes.size());
        break;
    default: // A header-region flip: the first 512 bytes hold the most structure.
        bytes[rng() % std::min<size_t>(512, bytes.size())] ^= char(1u << (rng() % 8));
        break;
    }
    return bytes;
}

// OpenVDB's node destructors allocate (Tree::clear collects node pointers in vectors), so a
// bad_alloc at the cap would become std::terminate while the half-read tree unwinds. An emergency
// reserve, released by the new-handler at the first failed allocation (which then throws), gives
// the unwinding room. Re-armed before each call.
constexpr size_t kReserveBytes = size_t(256) << 20;
void* g_reserve = nullptr;

void release_reserve() {
    // Fail this allocation (a retry would let the reader eat the reserve) and free the reserve
    // for the unwinding that follows.
    std::free(g_reserve);
    g_reserve = nullptr;
    std::set_new_handler(nullptr);
    throw std::bad_alloc();
}

void arm_reserve() {
    if (!g_reserve)
        g_reserve = std::malloc(kReserveBytes);
    std::set_new_handler(release_reserve);
}

// Runs every reader on `path` in a child; returns its wait status.
int import_in_child(const std::string& path) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (kCapMemory) {
            const rlimit mem{kMemoryCap, kMemoryCap};
            ::setrlimit(RLIMIT_AS, &mem);
        }
        const rlimit cpu{kCpuSeconds, kCpuSeconds};
        ::setrlimit(RLIMIT_CPU, &cpu);
        VolumeImportOptions o;
        o.max_blocks = uint64_t(1) << 24; // Bounds the work a corrupt bbox can ask for.
        arm_reserve();
        (void)list_grids(path);
        arm_reserve();
        (void)import_volume(path, o);
        o.block_size = 4;
        arm_reserve();
        (void)import_volume(path, o);
        VdbWorldImportOptions w;
        w.max_chunks = 1 << 12;
        arm_reserve();
        (void)import_world_vdb(path, w);
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

TEST(VdbFuzz, MutatedFilesNeverCrash) {
    VX_REQUIRE_VDB_DATA();
    // Small files (and the 0.8 MB level set now and then), so 160 children take ~20 s on 2 cores.
    const char* files[] = {"gaffer_arnoldtest_sphere.vdb", "oiio_sphere.vdb", "arnoldusd_torus01.vdb",
                           "arnoldusd_grids.vdb", "gaffer_points.vdb", "oiio_sphereCd.vdb"};
    test::TempDir dir;
    // VX_VDB_FUZZ_SEED / VX_VDB_FUZZ_ITERATIONS explore further by hand; CTest uses the defaults.
    const char* seed = std::getenv("VX_VDB_FUZZ_SEED");
    const char* iters = std::getenv("VX_VDB_FUZZ_ITERATIONS");
    std::mt19937 rng(seed ? uint32_t(std::atoll(seed)) : 12345u);
    const int iterations = iters ? std::atoi(iters) : 160;
    int crashes = 0;
    for (int it = 0; it < iterations; ++it) {
        // Every 25th iteration mutates the level set (larger: 0.8 MB, ~1 s per child).
        const char* name = it % 25 == 24 ? "gaffer_vdbtest_sphere.vdb" : files[size_t(it) % std::size(files)];
        const std::string original = read_bytes(test::data_path(name));
        ASSERT_FALSE(original.empty()) << name;
        std::string file_name = "m"; // (operator+ trips a GCC 12 -Wrestrict false positive)
        file_name += std::to_string(it);
        file_name += ".vdb";
        const std::string path = dir.file(file_name);
        std::ofstream(path, std::ios::binary) << mutate(original, rng);
        const auto t0 = std::chrono::steady_clock::now();
        const int status = import_in_child(path);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (sec > 1.0) // Corrupt sizes make OpenVDB allocate up to the cap before it fails.
            std::printf("iteration %d (%s): %.2f s\n", it, name, sec);
        const bool failed = !WIFEXITED(status) || WEXITSTATUS(status) != 0;
        if (failed && std::getenv("VX_VDB_FUZZ_KEEP")) // A folder to copy failing inputs to.
            std::filesystem::copy_file(path, std::string(std::getenv("VX_VDB_FUZZ_KEEP")) + "/" + file_name);
        std::filesystem::remove(path);
        if (failed) {
            ++crashes;
            ADD_FAILURE() << "iteration " << it << " (" << name << "): "
                          << (WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                                  : "exit " + std::to_string(WEXITSTATUS(status)))
                          << " (set VX_VDB_FUZZ_KEEP=<dir> to keep the input)";
            if (crashes >= 5)
                break;
        }
    }
}

} // namespace
} // namespace vx::vdb
