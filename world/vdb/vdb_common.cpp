#include "world/vdb/vdb_common.h"

#include <filesystem>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <tbb/task_arena.h>

namespace vx::vdb::detail {

std::string unreadable_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec))
        return {};
    return "cannot read '" + path + "': " + (std::filesystem::exists(path, ec) ? "not a file" : "no such file");
}

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
