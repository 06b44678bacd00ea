#include "world/vdb/vdb_volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

#include <openvdb/openvdb.h>

#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_lattice.h"
#include "world/vdb/vdb_neighbourhood.h"

namespace vx::vdb {
namespace {

using world::BlockId;
using world::BlockPos;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;

std::string quoted_name(const openvdb::GridBase& g, int index) {
    return g.getName().empty() ? "#" + std::to_string(index) + " (unnamed)" : "'" + g.getName() + "'";
}

// Reads every grid of `path`: with trees when `trees`, else metadata only.
Result<openvdb::GridPtrVecPtr> read_grids(const std::string& path, bool trees) {
    if (std::string why = detail::unreadable_file(path); !why.empty())
        return Error{why};
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open(false); // No delayed loading: every read error surfaces inside the caller's try.
    openvdb::GridPtrVecPtr grids = trees ? file.getGrids() : file.readAllGridMetadata();
    file.close();
    if (!grids || grids->empty())
        return Error{"'" + path + "' holds no grids"};
    for (const auto& g : *grids)
        if (!g)
            return Error{"'" + path + "' holds a grid that could not be read"};
    return grids;
}

// Reads grid `index` with its tree: alone when its name is unique in the file (OpenVDB reads by
// name), else together with all the others.
Result<openvdb::GridBase::Ptr> read_one_grid(const std::string& path, const openvdb::GridPtrVec& meta, int index) {
    const std::string& name = meta[size_t(index)]->getName();
    const auto same = std::count_if(meta.begin(), meta.end(), [&](const auto& g) { return g->getName() == name; });
    if (same == 1 && !name.empty()) {
        openvdb::io::File file(path);
        file.open(false);
        openvdb::GridBase::Ptr g = file.readGrid(name);
        file.close();
        if (!g)
            return Error{"cannot read grid '" + name + "' of '" + path + "'"};
        return g;
    }
    Result<openvdb::GridPtrVecPtr> all = read_grids(path, true);
    if (!all)
        return Error{all.error()};
    if ((*all)->size() != meta.size())
        return Error{"'" + path + "' changed while being read"};
    return (**all)[size_t(index)];
}

bool is_scalar(const openvdb::GridBase& g) {
    return g.isType<openvdb::FloatGrid>() || g.isType<openvdb::DoubleGrid>();
}

std::string grid_names(const openvdb::GridPtrVec& grids) {
    std::string s;
    for (size_t i = 0; i < grids.size(); ++i)
        s += (i ? ", " : "") + std::to_string(i) + ":" + quoted_name(*grids[i], int(i)) + " " + grids[i]->valueType();
    return s;
}

// Why a grid of another value type cannot become blocks.
Error refuse_type(const openvdb::GridBase& g, int index) {
    const std::string t = g.valueType(), name = quoted_name(g, index);
    if (t.rfind("ptdataidx", 0) == 0)
        return Error{"grid " + name + " is a point-data grid (particles), not a volume; it cannot become blocks"};
    if (t.rfind("vec3", 0) == 0)
        return Error{"grid " + name + " holds " + t +
                     " vectors (a colour or velocity field), not a scalar volume; select a float or double grid"};
    if (t == "int32" && g.getName() == "blocks")
        return Error{"grid 'blocks' holds block ids; read it with import_world_vdb"};
    return Error{"grid " + name + " holds " + t + " values; only float and double grids can become blocks"};
}

Result<int> select_grid(const openvdb::GridPtrVec& grids, const VolumeImportOptions& o) {
    const int n = int(grids.size());
    if (o.grid_index >= 0) {
        if (o.grid_index >= n)
            return Error{"grid_index " + std::to_string(o.grid_index) + " is out of range (the file has " +
                         std::to_string(n) + " grids: " + grid_names(grids) + ")"};
        return o.grid_index;
    }
    if (!o.grid_name.empty()) {
        std::vector<int> hits;
        for (int i = 0; i < n; ++i)
            if (grids[size_t(i)]->getName() == o.grid_name)
                hits.push_back(i);
        if (hits.empty())
            return Error{"no grid named '" + o.grid_name + "' (grids: " + grid_names(grids) + ")"};
        if (hits.size() > 1)
            return Error{std::to_string(hits.size()) + " grids are named '" + o.grid_name +
                         "'; choose one with grid_index (grids: " + grid_names(grids) + ")"};
        return hits[0];
    }
    for (int i = 0; i < n; ++i)
        if (is_scalar(*grids[size_t(i)]))
            return i;
    if (n == 1)
        return refuse_type(*grids[0], 0);
    return Error{"no float or double grid to import (grids: " + grid_names(grids) + ")"};
}

template <class GridT> class VolumeImporter {
public:
    VolumeImporter(const GridT& grid, int index, const VolumeImportOptions& o)
        : m_grid(grid), m_index(index), m_o(o), m_acc(grid.getConstAccessor()) {}

    Result<VolumeImport> run();

private:
    using ValueT = typename GridT::ValueType;

    Status analyse();
    Status map_blocks(const openvdb::CoordBBox& bbox);
    bool solid(const glm::i64vec3& src, float& mean);
    double sample(const glm::dvec3& p);
    void fetch_hood(const glm::i64vec3& src);
    bool supersample(const glm::i64vec3& src, bool refine);
    int count_inside(const glm::i64vec3& src, int s) const;
    double member_mean(const glm::i64vec3& src) const;
    bool inside(double v) const { return m_level_set ? v < 0 : v >= m_threshold; }
    bool voxel_majority(const glm::i64vec3& src, float& mean);
    glm::dvec3 centre(const glm::i64vec3& src) const { return m_lattice.index_of(glm::dvec3(src) + 0.5); }
    void mark_active_chunks();
    void add_chunks(openvdb::CoordBBox b);
    bool fill_chunk(ChunkCoord c, bool active, std::vector<BlockId>& ids);
    BlockId block_for(float mean) const;
    std::string name() const { return quoted_name(m_grid, m_index); }

    const GridT& m_grid;
    int m_index;
    const VolumeImportOptions& m_o;
    typename GridT::ConstAccessor m_acc;
    detail::BlockLattice m_lattice;
    double m_block_size = 1;                // World units.
    bool m_level_set = false;
    double m_threshold = 0, m_max = 0;
    double m_distance_unit = 1;             // Level set: world units per index unit, at most (largest voxel edge).
    int m_box_samples = 2;                  // VoxelMajority: samples per block axis.
    glm::i64vec3 m_src_lo{0}, m_src_hi{-1}; // Source block range (inclusive).
    std::unordered_set<ChunkCoord, world::ChunkCoordHash> m_active;
    detail::Neighbourhood m_hood;
    uint64_t m_supersampled = 0, m_solid = 0;
};

// Resolves the block size and builds the lattice from the grid's transform; the source block
// range is every block the active voxels' cells ([min - 1/2, max + 1/2] in index space) reach.
template <class GridT> Status VolumeImporter<GridT>::map_blocks(const openvdb::CoordBBox& bbox) {
    const openvdb::math::Transform& xf = m_grid.transform();
    if (!xf.isLinear())
        return Error{"grid " + name() + " has a non-linear " + xf.mapType() +
                     " transform (a frustum: voxels grow with depth), which blocks of one size cannot honour; "
                     "resample it to a linear transform first"};
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0.0));
    glm::dmat3 m;
    for (int k = 0; k < 3; ++k) {
        openvdb::Vec3d e(0.0);
        e[k] = 1.0;
        const openvdb::Vec3d w = xf.indexToWorld(e) - o;
        m[k] = glm::dvec3(w[0], w[1], w[2]);
    }
    const glm::dvec3 vs(glm::length(m[0]), glm::length(m[1]), glm::length(m[2]));
    const openvdb::Vec3d ovs = xf.voxelSize();
    const double uniform = detail::uniform_voxel(glm::dvec3(ovs[0], ovs[1], ovs[2]));
    const std::string sizes = detail::format_length(vs.x) + " x " + detail::format_length(vs.y) + " x " + detail::format_length(vs.z);
    if (m_o.voxels_per_block > 0 || m_o.block_size == 0) {
        if (uniform == 0)
            return Error{"grid " + name() + " has non-cubic voxels (" + sizes + " world units), so " +
                         (m_o.voxels_per_block > 0 ? "voxels_per_block" : "the default block size") +
                         " is ambiguous; give block_size in world units"};
        // The same product a caller forms from list_grids' voxel_size, so both spellings agree exactly.
        m_block_size = m_o.voxels_per_block > 0 ? double(m_o.voxels_per_block) * ovs[0] : ovs[0];
    } else {
        m_block_size = m_o.block_size;
    }
    const double finest = std::min({vs.x, vs.y, vs.z});
    if (m_block_size > 64 * finest * (1 + 1e-9))
        return Error{"block_size " + detail::format_length(m_block_size) + " is " + detail::format_length(m_block_size / finest) +
                     " voxels of grid " + name() + " (voxel " + sizes + "), more than 64; lower block_size"};
    Result<detail::BlockLattice> lattice = detail::BlockLattice::create(m, glm::dvec3(o[0], o[1], o[2]), m_block_size);
    if (!lattice)
        return Error{"grid " + name() + ": " + lattice.error()};
    m_lattice = *lattice;
    m_distance_unit = std::max({vs.x, vs.y, vs.z});
    // Two samples per voxel spacing make the box filter exact for whole voxels per block on a
    // grid aligned with the blocks (each voxel cell is covered by whole sample pairs or halves).
    m_box_samples = std::clamp(int(std::ceil(2 * m_block_size / finest - 1e-9)), 2, 32);
    const glm::dvec3 lo(bbox.min().x() - 0.5, bbox.min().y() - 0.5, bbox.min().z() - 0.5);
    const glm::dvec3 hi(bbox.max().x() + 0.5, bbox.max().y() + 0.5, bbox.max().z() + 0.5);
    m_lattice.blocks_meeting(lo, hi, m_src_lo, m_src_hi);
    return {};
}

template <class GridT> Status VolumeImporter<GridT>::analyse() {
    openvdb::CoordBBox bbox;
    if (!m_grid.tree().evalActiveVoxelBoundingBox(bbox) || bbox.empty())
        return Error{"grid " + name() + " is empty (no active voxels)"};
    for (int a = 0; a < 3; ++a)
        if (std::abs(int64_t(bbox.min()[a])) > kVdbCoordLimit || std::abs(int64_t(bbox.max()[a])) > kVdbCoordLimit)
            return Error{"grid " + name() + " has voxels beyond index +-" + std::to_string(kVdbCoordLimit) +
                         ", too close to OpenVDB's 32-bit limit"};
    if (Status s = map_blocks(bbox); !s)
        return s;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (auto it = m_grid.tree().cbeginValueOn(); it; ++it) {
        const double v = double(*it);
        if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    if (!std::isfinite(lo))
        return Error{"grid " + name() + " holds no finite values"};
    m_max = hi;
    const double bg = double(m_grid.background());
    const openvdb::GridClass cls = m_grid.getGridClass();
    m_level_set = m_o.mode == VolumeMode::LevelSet ||
                  (m_o.mode == VolumeMode::Auto &&
                   (cls == openvdb::GRID_LEVEL_SET || (cls != openvdb::GRID_FOG_VOLUME && bg > 0 && lo < 0)));
    if (m_level_set) {
        if (!(bg > 0))
            return Error{"level set " + name() + " has background " + std::to_string(bg) +
                         " (not > 0, so outside would be solid); import it with mode fog"};
    } else {
        if (!(hi > 0))
            return Error{"fog grid " + name() + " has no positive density"};
        if (!(m_o.threshold > 0.f && m_o.threshold <= 1.f))
            return Error{"threshold " + std::to_string(m_o.threshold) + " is outside (0, 1]"};
        m_threshold = double(m_o.threshold) * hi;
        if (bg >= m_threshold)
            return Error{"fog grid " + name() + " has background " + std::to_string(bg) +
                         " at or above the density threshold " + std::to_string(m_threshold) + "; raise threshold"};
    }
    const glm::u64vec3 n = glm::u64vec3(m_src_hi - m_src_lo + glm::i64vec3(1));
    const long double count = (long double)n.x * n.y * n.z;
    if (count > (long double)m_o.max_blocks)
        return Error{"grid " + name() + " would be " + std::to_string(n.x) + "x" + std::to_string(n.y) + "x" +
                     std::to_string(n.z) + " blocks at block_size " + detail::format_length(m_block_size) +
                     ", more than max_blocks " + std::to_string(m_o.max_blocks) + "; raise block_size or max_blocks"};
    // Offsets near the world's edge could overflow; the world spans [-2^36, 2^36) (coords.h).
    constexpr int64_t kMaxOffset = int64_t(1) << 40;
    const glm::i64vec3 lim(kMaxOffset);
    if (glm::any(glm::greaterThan(m_o.offset, lim)) || glm::any(glm::lessThan(m_o.offset, -lim)) ||
        !world::in_world(m_src_lo + m_o.offset) || !world::in_world(m_src_hi + m_o.offset))
        return Error{"offset puts blocks beyond the world's range [-2^36, 2^36); change offset"};
    return {};
}

// Trilinear value at continuous index position p, read through the accessor (inactive voxels
// give their stored value: -background inside a narrow-band level set).
template <class GridT> double VolumeImporter<GridT>::sample(const glm::dvec3& p) {
    const glm::dvec3 fl = glm::floor(p);
    const glm::dvec3 f = p - fl;
    const openvdb::Coord i(int32_t(fl.x), int32_t(fl.y), int32_t(fl.z));
    if (f == glm::dvec3(0.0))
        return double(m_acc.getValue(i));
    double c[2][2];
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            c[z][y] = double(m_acc.getValue(i.offsetBy(0, y, z))) * (1 - f.x) +
                      double(m_acc.getValue(i.offsetBy(1, y, z))) * f.x;
    const double c0 = c[0][0] * (1 - f.y) + c[0][1] * f.y, c1 = c[1][0] * (1 - f.y) + c[1][1] * f.y;
    return c0 * (1 - f.z) + c1 * f.z;
}

// Samples on an s³ grid spread evenly over block src's cell that fall inside (m_hood must hold
// the cell).
template <class GridT> int VolumeImporter<GridT>::count_inside(const glm::i64vec3& src, int s) const {
    const glm::dvec3 b(src);
    int votes = 0;
    for (int z = 0; z < s; ++z)
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                const glm::dvec3 p = m_lattice.index_of(b + (glm::dvec3(x, y, z) + 0.5) / double(s));
                votes += inside(m_hood.sample(p)) ? 1 : 0;
            }
    return votes;
}

// Mean value of the voxels whose centres lie in block src's cell (m_hood must hold the cell);
// the centre sample when the block is smaller than the voxel spacing and holds none.
template <class GridT> double VolumeImporter<GridT>::member_mean(const glm::i64vec3& src) const {
    double sum = 0;
    int members = 0;
    for (int z = 0; z < m_hood.dim.z; ++z)
        for (int y = 0; y < m_hood.dim.y; ++y)
            for (int x = 0; x < m_hood.dim.x; ++x) {
                const glm::dvec3 q(m_hood.lo + glm::ivec3(x, y, z));
                if (glm::i64vec3(glm::floor(m_lattice.block_of(q))) != src)
                    continue;
                ++members;
                sum += std::isfinite(m_hood.at(x, y, z)) ? m_hood.at(x, y, z) : 0.0;
            }
    return members ? sum / members : m_hood.sample(centre(src));
}

// Majority of samples_per_axis³ samples on a regular grid inside the block. Blocks whose whole
// neighbourhood lies on one side of the threshold skip sampling (trilinear values lie between
// their corners' values, so that answer is exact). With `refine`, a solid fraction within 0.075
// of one half is redone at twice the rate per axis: close votes are where a coarse estimate
// flips.
// Fetches the voxels under block src's cell into m_hood. Samples lie strictly inside the cell,
// so floor(p) + 1 <= ceil(hi) for every trilinear corner and every nearest voxel.
template <class GridT> void VolumeImporter<GridT>::fetch_hood(const glm::i64vec3& src) {
    glm::dvec3 lo, hi;
    m_lattice.cell_bounds(src, lo, hi);
    const glm::dvec3 first = glm::floor(lo), last = glm::ceil(hi);
    m_hood.fetch(glm::ivec3(first), glm::ivec3(last - first) + 1,
                 [&](int x, int y, int z) { return double(m_acc.getValue(openvdb::Coord(x, y, z))); });
}

template <class GridT> bool VolumeImporter<GridT>::supersample(const glm::i64vec3& src, bool refine) {
    fetch_hood(src);
    if (inside(m_hood.min) == inside(m_hood.max))
        return inside(m_hood.min);
    ++m_supersampled;
    int s = m_o.samples_per_axis;
    int votes = count_inside(src, s);
    if (refine && s < 16 && std::abs(2 * votes - s * s * s) * 20 < 3 * s * s * s) {
        s = std::min(2 * s, 16);
        votes = count_inside(src, s);
    }
    if (2 * votes == s * s * s) // A tie (even sample counts): the centre decides.
        return inside(sample(centre(src)));
    return 2 * votes > s * s * s;
}

// More than half of the block's cell inside with box reconstruction (each voxel's value fills
// its cell, no interpolation), estimated from m_box_samples³ points each taking its nearest
// voxel; exact for whole voxels per block on block-aligned grids. A tie is air. `mean` gets the
// box-filtered mean relative to the grid's max.
template <class GridT> bool VolumeImporter<GridT>::voxel_majority(const glm::i64vec3& src, float& mean) {
    fetch_hood(src);
    const int n = m_box_samples;
    const glm::dvec3 b(src);
    int dense = 0;
    double sum = 0;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double v = m_hood.nearest(m_lattice.index_of(b + (glm::dvec3(x, y, z) + 0.5) / double(n)));
                dense += inside(v) ? 1 : 0;
                sum += std::isfinite(v) ? v : 0.0;
            }
    mean = float(sum / (n * n * n) / m_max);
    return 2 * dense > n * n * n;
}

template <class GridT> bool VolumeImporter<GridT>::solid(const glm::i64vec3& src, float& mean) {
    mean = 0.f;
    switch (m_o.sampling) {
    case VolumeSampling::CentreOnly: {
        const double v = sample(centre(src));
        mean = float(v / m_max);
        return inside(v);
    }
    case VolumeSampling::VoxelMajority:
        return voxel_majority(src, mean);
    case VolumeSampling::Supersample: {
        const bool in = supersample(src, false);
        if (!m_level_set && !m_o.density_blocks.empty())
            mean = float(member_mean(src) / m_max);
        return in;
    }
    case VolumeSampling::Adaptive:
        break;
    }
    if (!m_level_set) {
        const bool in = supersample(src, true);
        if (!m_o.density_blocks.empty())
            mean = float(member_mean(src) / m_max);
        return in;
    }
    // Signed distances are in world units; in index units (divided by the largest voxel edge,
    // which never overstates the distance) a zero crossing inside the cell lies within its half
    // diagonal of the centre (distance fields are 1-Lipschitz); one voxel of slack covers
    // interpolation and narrow-band clamping.
    const double phi = sample(centre(src)) / m_distance_unit;
    const double near = m_lattice.half_diagonal() + 1.0;
    if (std::abs(phi) < near)
        return supersample(src, true);
    return phi < 0;
}

// Chunks (destination coordinates) whose blocks touch a leaf or an active tile, dilated by one
// voxel for the trilinear footprint. Other chunks are uniform: all one sign (level set) or all
// background (fog).
template <class GridT> void VolumeImporter<GridT>::add_chunks(openvdb::CoordBBox b) {
    b.expand(1);
    glm::i64vec3 lo, hi;
    m_lattice.blocks_meeting(glm::dvec3(b.min().x(), b.min().y(), b.min().z()),
                             glm::dvec3(b.max().x(), b.max().y(), b.max().z()), lo, hi);
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(lo[a], m_src_lo[a]) + m_o.offset[a];
        hi[a] = std::min(hi[a], m_src_hi[a]) + m_o.offset[a];
        if (lo[a] > hi[a])
            return;
    }
    const ChunkCoord clo = world::chunk_of(lo), chi = world::chunk_of(hi);
    // 64-bit counters: the world's last chunk is INT32_MAX, where ++ on an int never passes it.
    for (int64_t z = clo.z; z <= chi.z; ++z)
        for (int64_t y = clo.y; y <= chi.y; ++y)
            for (int64_t x = clo.x; x <= chi.x; ++x)
                m_active.insert(ChunkCoord(int32_t(x), int32_t(y), int32_t(z)));
}

template <class GridT> void VolumeImporter<GridT>::mark_active_chunks() {
    for (auto it = m_grid.tree().cbeginLeaf(); it; ++it)
        add_chunks(it->getNodeBoundingBox());
    auto tiles = m_grid.tree().cbeginValueOn();
    tiles.setMaxDepth(GridT::TreeType::ValueOnCIter::LEAF_DEPTH - 1); // Tiles only.
    for (; tiles; ++tiles) {
        openvdb::CoordBBox b;
        tiles.getBoundingBox(b);
        add_chunks(b);
    }
}

template <class GridT> BlockId VolumeImporter<GridT>::block_for(float mean) const {
    if (m_level_set || m_o.density_blocks.empty())
        return m_o.block;
    const DensityBlock* best = nullptr;
    for (const DensityBlock& d : m_o.density_blocks)
        if (d.min_density <= mean && (!best || d.min_density > best->min_density))
            best = &d;
    if (!best) // Solid but below every entry: the lowest entry.
        for (const DensityBlock& d : m_o.density_blocks)
            if (!best || d.min_density < best->min_density)
                best = &d;
    return best->block;
}

// Classifies the blocks of one destination chunk; returns false when it holds no solid block.
template <class GridT> bool VolumeImporter<GridT>::fill_chunk(ChunkCoord c, bool active, std::vector<BlockId>& ids) {
    const BlockPos org = world::chunk_origin(c);
    bool uniform_inside = false;
    if (!active) {
        if (!m_level_set)
            return false;
        uniform_inside = sample(m_lattice.index_of(glm::dvec3(org - m_o.offset) + 0.5 * kChunkSize)) < 0;
        if (!uniform_inside)
            return false;
    }
    bool any = false;
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < kChunkSize; ++y)
            for (int x = 0; x < kChunkSize; ++x) {
                const glm::i64vec3 src = org + BlockPos(x, y, z) - m_o.offset;
                BlockId id = world::kAir;
                if (glm::all(glm::greaterThanEqual(src, m_src_lo)) && glm::all(glm::lessThanEqual(src, m_src_hi))) {
                    float mean = 0.f;
                    if (uniform_inside || solid(src, mean))
                        id = block_for(mean);
                }
                ids[size_t(world::local_index(x, y, z))] = id;
                if (id != world::kAir) {
                    any = true;
                    ++m_solid;
                }
            }
    return any;
}

template <class GridT> Result<VolumeImport> VolumeImporter<GridT>::run() {
    if (Status s = analyse(); !s)
        return Error{s.error()};
    mark_active_chunks();
    VolumeImport out;
    const ChunkCoord clo = world::chunk_of(m_src_lo + m_o.offset), chi = world::chunk_of(m_src_hi + m_o.offset);
    std::vector<BlockId> ids(kChunkVolume);
    for (int64_t z = clo.z; z <= chi.z; ++z) // 64-bit: see add_chunks.
        for (int64_t y = clo.y; y <= chi.y; ++y)
            for (int64_t x = clo.x; x <= chi.x; ++x) {
                const ChunkCoord c{int32_t(x), int32_t(y), int32_t(z)};
                if (fill_chunk(c, m_active.count(c) != 0, ids))
                    out.world.put_chunk(c, world::Chunk::from_dense(ids));
            }
    VolumeImportSummary& s = out.summary;
    s.grid_index = m_index;
    s.grid_name = m_grid.getName();
    s.mode = m_level_set ? VolumeMode::LevelSet : VolumeMode::Fog;
    const openvdb::Vec3d vs = m_grid.voxelSize();
    s.voxel_size = glm::dvec3(vs[0], vs[1], vs[2]);
    s.block_size = m_block_size;
    s.threshold_absolute = m_threshold;
    s.max_value = m_max;
    s.solid_blocks = m_solid;
    s.supersampled_blocks = m_supersampled;
    s.blocks = BlockBox{m_src_lo + m_o.offset, m_src_hi + m_o.offset};
    return out;
}

Result<VolumeImport> import_grid(const openvdb::GridBase::Ptr& g, int index, const VolumeImportOptions& o) {
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
        return VolumeImporter<openvdb::FloatGrid>(*f, index, o).run();
    if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(g))
        return VolumeImporter<openvdb::DoubleGrid>(*d, index, o).run();
    return refuse_type(*g, index);
}

GridInfo describe(const openvdb::GridBase& g, int index) {
    GridInfo info;
    info.index = index;
    info.name = g.getName();
    info.value_type = g.valueType();
    info.grid_class = openvdb::GridBase::gridClassToString(g.getGridClass());
    const openvdb::Vec3d vs = g.voxelSize();
    info.voxel_size = glm::dvec3(vs[0], vs[1], vs[2]);
    info.transform = g.transform().mapType();
    info.active_voxels = g.activeVoxelCount();
    const openvdb::CoordBBox b = g.evalActiveVoxelBoundingBox();
    info.empty = info.active_voxels == 0 || b.empty();
    if (!info.empty) {
        info.bbox_min = glm::ivec3(b.min().x(), b.min().y(), b.min().z());
        info.bbox_max = glm::ivec3(b.max().x(), b.max().y(), b.max().z());
    }
    info.saved_as_half = g.saveFloatAsHalf();
    return info;
}

} // namespace

static Result<std::vector<GridInfo>> list_grids_impl(const std::string& path) {
    try {
        Result<openvdb::GridPtrVecPtr> grids = read_grids(path, true);
        if (!grids)
            return Error{grids.error()};
        std::vector<GridInfo> out;
        for (size_t i = 0; i < (*grids)->size(); ++i)
            out.push_back(describe(*(**grids)[i], int(i)));
        return out;
    } catch (const std::exception& e) { // openvdb::Exception derives from std::exception.
        return detail::make_error("cannot read '" + path + "'", e.what());
    } catch (...) {
        return detail::make_error("cannot read '" + path + "'", "unknown error");
    }
}

static Result<VolumeImport> import_volume_impl(const std::string& path, const VolumeImportOptions& options) {
    if (Status s = detail::check_volume_options(options); !s)
        return Error{s.error()};
    try {
        Result<openvdb::GridPtrVecPtr> meta = read_grids(path, false);
        if (!meta)
            return Error{meta.error()};
        Result<int> index = select_grid(**meta, options);
        if (!index)
            return Error{"cannot import '" + path + "': " + index.error()};
        Result<openvdb::GridBase::Ptr> grid = read_one_grid(path, **meta, *index);
        if (!grid)
            return Error{grid.error()};
        Result<VolumeImport> r = import_grid(*grid, *index, options);
        if (!r)
            return Error{"cannot import '" + path + "': " + r.error()};
        return r;
    } catch (const std::exception& e) {
        return detail::make_error("cannot read '" + path + "'", e.what());
    } catch (...) {
        return detail::make_error("cannot read '" + path + "'", "unknown error");
    }
}

Result<std::vector<GridInfo>> list_grids(const std::string& path) {
    return detail::serial<Result<std::vector<GridInfo>>>([&] { return list_grids_impl(path); });
}

Result<VolumeImport> import_volume(const std::string& path, const VolumeImportOptions& options) {
    return detail::serial<Result<VolumeImport>>([&] { return import_volume_impl(path, options); });
}

} // namespace vx::vdb
