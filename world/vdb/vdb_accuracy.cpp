#include "world/vdb/vdb_accuracy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <unordered_set>

namespace vx::vdb {
namespace {

using world::BlockId;
using world::BlockPos;
using world::ChunkCoord;

constexpr int kReferenceSamples = 8; // Per axis: 512 samples per block.
constexpr int kMaxSearch = 8;        // Blocks; surface distances beyond are reported as 8.

struct Comparison {
    uint64_t both = 0, either = 0, solid = 0, reference = 0;
    std::vector<BlockPos> mismatches;
};

Comparison compare(const world::World& a, const world::World& ref) {
    std::unordered_set<ChunkCoord, world::ChunkCoordHash> chunks;
    a.for_each_chunk([&](ChunkCoord c, const world::Chunk&) { chunks.insert(c); });
    ref.for_each_chunk([&](ChunkCoord c, const world::Chunk&) { chunks.insert(c); });
    Comparison out;
    const world::Chunk air;
    for (const ChunkCoord& c : chunks) {
        const world::Chunk* ca = a.find_chunk(c);
        const world::Chunk* cr = ref.find_chunk(c);
        const world::Chunk& x = ca ? *ca : air;
        const world::Chunk& y = cr ? *cr : air;
        for (int i = 0; i < world::kChunkVolume; ++i) {
            const bool sa = x.get(i) != world::kAir, sr = y.get(i) != world::kAir;
            out.solid += sa;
            out.reference += sr;
            out.both += sa && sr;
            out.either += sa || sr;
            if (sa != sr) {
                const int lx = i & 31, ly = (i >> 5) & 31, lz = i >> 10;
                out.mismatches.push_back(world::chunk_origin(c) + BlockPos(lx, ly, lz));
            }
        }
    }
    return out;
}

// Distance from block p's centre to the reference surface: to the nearest face between p's
// reference class and the other one, searched in growing cubes.
double surface_distance(const world::World& ref, BlockPos p) {
    const bool inside = ref.get_block(p) != world::kAir;
    double best = kMaxSearch;
    for (int r = 1; r <= kMaxSearch && r - 0.5 < best; ++r)
        for (int z = -r; z <= r; ++z)
            for (int y = -r; y <= r; ++y)
                for (int x = -r; x <= r; ++x) {
                    if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != r)
                        continue; // Shell only.
                    if ((ref.get_block(p + BlockPos(x, y, z)) != world::kAir) == inside)
                        continue;
                    // The other class starts at the block's near face, half a block before its centre.
                    const double d = std::sqrt(double(x * x + y * y + z * z)) - 0.5;
                    best = std::min(best, d);
                }
    return best;
}

AccuracyRow make_row(const VolumeImport& imp, const world::World& ref, VolumeSampling sampling, double seconds) {
    Comparison c = compare(imp.world, ref);
    AccuracyRow row;
    row.grid_name = imp.summary.grid_name;
    row.mode = imp.summary.mode;
    row.block_size = imp.summary.block_size;
    const glm::dvec3& vs = imp.summary.voxel_size;
    row.voxels_per_block = imp.summary.block_size / std::min({vs.x, vs.y, vs.z});
    row.sampling = sampling;
    row.solid = c.solid;
    row.reference_solid = c.reference;
    row.mismatched = c.mismatches.size();
    row.iou = c.either ? double(c.both) / double(c.either) : 1.0;
    row.import_seconds = seconds;
    row.supersampled = imp.summary.supersampled_blocks;
    double sum = 0;
    for (const BlockPos& p : c.mismatches) {
        const double d = surface_distance(ref, p);
        sum += d;
        row.max_surface_distance = std::max(row.max_surface_distance, d);
    }
    row.mean_surface_distance = c.mismatches.empty() ? 0.0 : sum / double(c.mismatches.size());
    return row;
}

Result<VolumeImport> timed_import(const std::string& path, const VolumeImportOptions& o, double& seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<VolumeImport> r = import_volume(path, o);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

// Exact-shape classification of block b (cell s * [b, b + 1) in world units).
bool truth_solid(const AnalyticVolume& shape, double s, BlockPos b) {
    const glm::dvec3 lo = glm::dvec3(b) * s;
    const double half_diagonal = 0.5 * std::sqrt(3.0) * s;
    const double d = analytic_distance(shape, lo + 0.5 * s);
    if (std::abs(d) > half_diagonal)
        return d < 0;
    int in = 0;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                in += analytic_distance(shape, lo + (glm::dvec3(x, y, z) + 0.5) * (s / 8)) < 0;
    return 2 * in == 512 ? d < 0 : 2 * in > 512; // A tie goes to the centre, as in the importer.
}

} // namespace

AnalyticComparison compare_to_analytic(const world::World& w, const AnalyticVolume& shape, double s, BlockPos offset) {
    AnalyticComparison c;
    glm::dvec3 amin, amax;
    analytic_bounds(shape, amin, amax);
    const BlockPos lo(glm::floor(amin / s)), hi(glm::floor(amax / s));
    glm::i64vec3 smin(std::numeric_limits<int64_t>::max()), smax(std::numeric_limits<int64_t>::min());
    w.for_each_chunk([&](ChunkCoord cc, const world::Chunk& chunk) {
        for (int i = 0; i < world::kChunkVolume; ++i) {
            if (chunk.get(i) == world::kAir)
                continue;
            const BlockPos b = world::chunk_origin(cc) + BlockPos(i & 31, (i >> 5) & 31, i >> 10) - offset;
            ++c.solid;
            smin = glm::min(smin, b);
            smax = glm::max(smax, b);
            if (glm::any(glm::lessThan(b, lo)) || glm::any(glm::greaterThan(b, hi)))
                ++c.either; // Solid outside the shape's bounds: a mismatch.
        }
    });
    for (int64_t z = lo.z; z <= hi.z; ++z)
        for (int64_t y = lo.y; y <= hi.y; ++y)
            for (int64_t x = lo.x; x <= hi.x; ++x) {
                const BlockPos b(x, y, z);
                const bool t = truth_solid(shape, s, b), got = w.get_block(b + offset) != world::kAir;
                c.truth_solid += t;
                c.both += t && got;
                c.either += t || got;
            }
    c.iou = c.either ? double(c.both) / double(c.either) : 1.0;
    c.volume_error = double(c.solid) * s * s * s / analytic_volume(shape) - 1.0;
    if (c.solid) {
        c.solid_min = glm::dvec3(smin) * s;
        c.solid_max = glm::dvec3(smax + BlockPos(1)) * s;
        for (int a = 0; a < 3; ++a)
            c.bounds_error = std::max({c.bounds_error, std::abs(c.solid_min[a] - amin[a]) / s,
                                       std::abs(c.solid_max[a] - amax[a]) / s});
    }
    return c;
}

Result<std::vector<AccuracyRow>> measure_vdb_accuracy(const std::string& path, std::span<const int> block_sizes,
                                                      const VolumeImportOptions& base, const AnalyticVolume* truth) {
    std::vector<AccuracyRow> rows;
    for (int b : block_sizes) {
        VolumeImportOptions o = base;
        if (base.block_size > 0)
            o.block_size = b * base.block_size;
        else
            o.voxels_per_block = b;
        o.sampling = VolumeSampling::Supersample;
        o.samples_per_axis = kReferenceSamples;
        double seconds = 0;
        Result<VolumeImport> ref = timed_import(path, o, seconds);
        if (!ref)
            return Error{ref.error()};
        for (VolumeSampling s : {VolumeSampling::Adaptive, VolumeSampling::VoxelMajority, VolumeSampling::CentreOnly}) {
            o.sampling = s;
            o.samples_per_axis = base.samples_per_axis;
            Result<VolumeImport> imp = timed_import(path, o, seconds);
            if (!imp)
                return Error{imp.error()};
            rows.push_back(make_row(*imp, ref->world, s, seconds));
            if (truth) {
                const AnalyticComparison c = compare_to_analytic(imp->world, *truth, imp->summary.block_size, o.offset);
                rows.back().truth_iou = c.iou;
                rows.back().volume_error = c.volume_error;
                rows.back().bounds_error = c.bounds_error;
            }
        }
    }
    return rows;
}

Result<WorldRoundTripStats> measure_world_roundtrip(const world::World& w, const std::string& path,
                                                    const VdbExportOptions& options) {
    WorldRoundTripStats st;
    st.chunks = w.chunk_count();
    auto t0 = std::chrono::steady_clock::now();
    if (Status s = export_vdb(w, path, options); !s)
        return Error{s.error()};
    auto t1 = std::chrono::steady_clock::now();
    Result<world::World> back = import_world_vdb(path);
    auto t2 = std::chrono::steady_clock::now();
    if (!back)
        return Error{back.error()};
    std::error_code ec;
    st.file_bytes = std::filesystem::file_size(path, ec);
    st.export_seconds = std::chrono::duration<double>(t1 - t0).count();
    st.import_seconds = std::chrono::duration<double>(t2 - t1).count();
    const Comparison c = compare(*back, w);
    // Solid/air agreement is not enough: compare ids too.
    bool same = c.mismatches.empty();
    w.for_each_chunk([&](ChunkCoord cc, const world::Chunk& chunk) {
        const world::Chunk* o = back->find_chunk(cc);
        for (int i = 0; same && i < world::kChunkVolume; ++i)
            same = chunk.get(i) == (o ? o->get(i) : world::kAir);
    });
    st.exact = same;
    return st;
}

std::string format_accuracy_table(std::span<const AccuracyRow> rows) {
    std::string out = "grid                 mode         B  sampling         solid   reference  mismatch       IoU  "
                      "dist_max  dist_mean  supersampled  import_s  truth_IoU  vol_err  bound_err\n";
    char line[320];
    for (const AccuracyRow& r : rows) {
        std::snprintf(line, sizeof line,
                      "%-20.20s %-8s %5.3g  %-9s %12llu %11llu %9llu %9.5f %9.2f %10.2f %13llu %9.3f",
                      r.grid_name.c_str(), to_string(r.mode), r.voxels_per_block, to_string(r.sampling),
                      (unsigned long long)r.solid, (unsigned long long)r.reference_solid,
                      (unsigned long long)r.mismatched, r.iou, r.max_surface_distance, r.mean_surface_distance,
                      (unsigned long long)r.supersampled, r.import_seconds);
        out += line;
        if (r.truth_iou >= 0) {
            std::snprintf(line, sizeof line, "  %9.5f %+7.3f%% %10.2f", r.truth_iou, 100 * r.volume_error, r.bounds_error);
            out += line;
        }
        out += "\n";
    }
    return out;
}

} // namespace vx::vdb
