#include "world/vdb/vdb_common.h"

#include <algorithm>
#include <cerrno>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <random>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include <tbb/task_arena.h>

namespace vx::vdb::detail {

Error make_error(std::string_view context, std::string_view what) {
    // A damaged file can put garbage in OpenVDB's messages (a "KeyError" naming a type of
    // hundreds of megabytes was seen): control bytes become spaces, runs of spaces one, and
    // the message is cut at kMaxWhat characters, so the error stays one readable line.
    constexpr size_t kMaxWhat = 240;
    std::string msg(context);
    if (!what.empty())
        msg += ": ";
    const size_t start = msg.size();
    for (size_t i = 0; i < what.size(); ++i) {
        const char c = what[i];
        if (c == '\x1b') { // Skip ANSI colour sequences ("\x1b[31m").
            while (i < what.size() && what[i] != 'm')
                ++i;
            continue;
        }
        const bool space = (unsigned char)c < 0x20 || c == ' ' || c == '\x7f';
        if (space && (msg.size() == start || msg.back() == ' '))
            continue;
        if (msg.size() - start >= kMaxWhat) {
            msg += "...";
            break;
        }
        msg += space ? ' ' : c;
    }
    while (!msg.empty() && msg.back() == ' ')
        msg.pop_back();
    return Error{msg};
}

Result<std::string> create_temp_beside(const std::string& path) {
    static std::atomic<uint64_t> counter{0};
    thread_local std::mt19937_64 rng(std::random_device{}() ^ (uint64_t(::getpid()) << 32) ^ counter.fetch_add(1));
    int err = 0;
    for (int attempt = 0; attempt < 64; ++attempt) {
        char suffix[24];
        std::snprintf(suffix, sizeof suffix, ".tmp-%012llx", (unsigned long long)(rng() & 0xFFFFFFFFFFFFull));
        std::string name = path + suffix;
        const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return name;
        }
        err = errno;
        if (err != EEXIST)
            break;
    }
    return make_error("cannot create a temporary file beside '" + path + "'", std::strerror(err));
}

Status replace_file(const std::string& from, const std::string& to) {
    std::error_code ec;
    std::filesystem::rename(from, to, ec);
    if (ec) {
        const std::string why = ec.message(); // Before remove() reuses ec.
        std::filesystem::remove(from, ec);
        return make_error("cannot rename '" + from + "' to '" + to + "'", why);
    }
    return {};
}

void run_in_calling_thread(const std::function<void()>& f) {
    // One slot, reserved for this thread: the arena never asks TBB for workers.
    tbb::task_arena arena(1, 1);
    arena.execute(f);
}

double uniform_voxel(const glm::dvec3& vs) {
    const double lo = std::min({vs.x, vs.y, vs.z}), hi = std::max({vs.x, vs.y, vs.z});
    return lo > 0 && hi - lo <= 1e-6 * hi ? vs.x : 0.0;
}

std::string format_length(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.6g", v);
    return s;
}

Status check_volume_options(const VolumeImportOptions& o) {
    if (o.voxels_per_block != 0 && o.block_size != 0)
        return Error{"give block_size (world units) or voxels_per_block, not both"};
    if (o.voxels_per_block < 0 || o.voxels_per_block > 64)
        return Error{"voxels_per_block " + std::to_string(o.voxels_per_block) + " is outside 1..64"};
    if (!(o.block_size >= 0) || !std::isfinite(o.block_size))
        return Error{"block_size " + format_length(o.block_size) +
                     " is not a positive, finite length in the file's world units"};
    if (o.samples_per_axis < 1 || o.samples_per_axis > 16)
        return Error{"samples_per_axis " + std::to_string(o.samples_per_axis) + " is outside 1..16"};
    if (o.block == world::kAir)
        return Error{"block is 0 (air); choose a solid block id"};
    for (const DensityBlock& d : o.density_blocks)
        if (d.block == world::kAir)
            return Error{"density_blocks maps to air (0); use ids > 0"};
    return {};
}

} // namespace vx::vdb::detail

namespace vx::vdb {

const char* to_string(VolumeMode mode) {
    switch (mode) {
    case VolumeMode::Auto: return "auto";
    case VolumeMode::LevelSet: return "levelset";
    case VolumeMode::Fog: return "fog";
    }
    return "?";
}

const char* to_string(VolumeSampling sampling) {
    switch (sampling) {
    case VolumeSampling::Adaptive: return "adaptive";
    case VolumeSampling::CentreOnly: return "centre";
    case VolumeSampling::VoxelMajority: return "voxels";
    case VolumeSampling::Supersample: return "supersample";
    }
    return "?";
}

} // namespace vx::vdb
