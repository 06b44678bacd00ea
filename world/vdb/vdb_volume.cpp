#include "world/vdb/vdb_volume.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <unordered_set>

#include <openvdb/openvdb.h>

#include "world/vdb/vdb_common.h"

namespace vx::vdb {
namespace {

using world::BlockId;
using world::BlockPos;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;

int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

std::string quoted_name(const openvdb::GridBase& g, int index) {
    return g.getName().empty() ? "#" + std::to_string(index) + " (unnamed)" : "'" + g.getName() + "'";
}

// Reads every grid of `path`: with trees when `trees`, else metadata only.
Result<openvdb::GridPtrVecPtr> read_grids(const std::string& path, bool trees) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return Error{"cannot read '" + path + "': no such file"};
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

// (B + 2)³ voxel values around one block, fetched once so that many trilinear samples read local
// memory instead of walking the tree.
struct Neighbourhood {
    openvdb::Coord lo; // Index of values[0].
    int dim = 0;
    std::vector<double> values;
    double min = 0, max = 0;

    double at(int x, int y, int z) const { return values[size_t(x + dim * (y + dim * z))]; }

    template <class Acc> void fetch(Acc& acc, openvdb::Coord origin, int size) {
        lo = origin;
        dim = size;
        values.resize(size_t(dim) * dim * dim);
        min = std::numeric_limits<double>::infinity();
        max = -min;
        size_t i = 0;
        for (int z = 0; z < dim; ++z)
            for (int y = 0; y < dim; ++y)
                for (int x = 0; x < dim; ++x) {
                    const double v = double(acc.getValue(lo.offsetBy(x, y, z)));
                    values[i++] = v;
                    min = std::min(min, v);
                    max = std::max(max, v);
                }
    }
    // Mean of the inner voxels (the block itself, without the one-voxel margin).
    double inner_mean() const {
        double sum = 0;
        for (int z = 1; z < dim - 1; ++z)
            for (int y = 1; y < dim - 1; ++y)
                for (int x = 1; x < dim - 1; ++x)
                    sum += std::isfinite(at(x, y, z)) ? at(x, y, z) : 0.0;
        return sum / double((dim - 2) * (dim - 2) * (dim - 2));
    }
    // Trilinear value at continuous index position p (p - lo must lie in [0, dim - 1]).
    double sample(const glm::dvec3& p) const {
        const glm::dvec3 q = p - glm::dvec3(lo.x(), lo.y(), lo.z());
        const glm::ivec3 i = glm::clamp(glm::ivec3(glm::floor(q)), glm::ivec3(0), glm::ivec3(dim - 2));
        const glm::dvec3 f = q - glm::dvec3(i);
        double c[2][2];
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 2; ++y)
                c[z][y] = at(i.x, i.y + y, i.z + z) * (1 - f.x) + at(i.x + 1, i.y + y, i.z + z) * f.x;
        const double c0 = c[0][0] * (1 - f.y) + c[0][1] * f.y, c1 = c[1][0] * (1 - f.y) + c[1][1] * f.y;
        return c0 * (1 - f.z) + c1 * f.z;
    }
};

template <class GridT> class VolumeImporter {
public:
    VolumeImporter(const GridT& grid, int index, const VolumeImportOptions& o)
        : m_grid(grid), m_index(index), m_o(o), m_acc(grid.getConstAccessor()), m_b(o.block_size) {}

    Result<VolumeImport> run();

private:
    using ValueT = typename GridT::ValueType;

    Status analyse();
    bool solid(const glm::i64vec3& src, float& mean);
    double sample(const glm::dvec3& p);
    bool supersample(const glm::i64vec3& src, bool refine);
    int count_inside(const glm::i64vec3& org, int s) const;
    bool inside(double v) const { return m_level_set ? v < 0 : v >= m_threshold; }
    bool voxel_majority(const glm::i64vec3& src, float& mean);
    void mark_active_chunks();
    void add_chunks(openvdb::CoordBBox b);
    bool fill_chunk(ChunkCoord c, bool active, std::vector<BlockId>& ids);
    BlockId block_for(float mean) const;
    std::string name() const { return quoted_name(m_grid, m_index); }

    const GridT& m_grid;
    int m_index;
    const VolumeImportOptions& m_o;
    typename GridT::ConstAccessor m_acc;
    int m_b;
    bool m_level_set = false;
    double m_threshold = 0, m_max = 0, m_voxel = 1;
    glm::i64vec3 m_src_lo{0}, m_src_hi{-1}; // Source block range (inclusive).
    std::unordered_set<ChunkCoord, world::ChunkCoordHash> m_active;
    Neighbourhood m_hood;
    uint64_t m_supersampled = 0, m_solid = 0;
};

template <class GridT> Status VolumeImporter<GridT>::analyse() {
    openvdb::CoordBBox bbox;
    if (!m_grid.tree().evalActiveVoxelBoundingBox(bbox) || bbox.empty())
        return Error{"grid " + name() + " is empty (no active voxels)"};
    for (int a = 0; a < 3; ++a)
        if (std::abs(int64_t(bbox.min()[a])) > kVdbCoordLimit || std::abs(int64_t(bbox.max()[a])) > kVdbCoordLimit)
            return Error{"grid " + name() + " has voxels beyond index +-" + std::to_string(kVdbCoordLimit) +
                         ", too close to OpenVDB's 32-bit limit"};
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
    const openvdb::Vec3d vs = m_grid.voxelSize();
    m_voxel = std::isfinite(vs[0]) && vs[0] > 0 ? vs[0] : 1.0;
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
    const glm::i64vec3 vlo(bbox.min().x(), bbox.min().y(), bbox.min().z());
    const glm::i64vec3 vhi(bbox.max().x(), bbox.max().y(), bbox.max().z());
    for (int a = 0; a < 3; ++a) {
        m_src_lo[a] = floor_div(vlo[a], m_b);
        m_src_hi[a] = floor_div(vhi[a], m_b);
    }
    const glm::u64vec3 n = glm::u64vec3(m_src_hi - m_src_lo + glm::i64vec3(1));
    const long double count = (long double)n.x * n.y * n.z;
    if (count > (long double)m_o.max_blocks)
        return Error{"grid " + name() + " would be " + std::to_string(n.x) + "x" + std::to_string(n.y) + "x" +
                     std::to_string(n.z) + " blocks at block_size " + std::to_string(m_b) + ", more than max_blocks " +
                     std::to_string(m_o.max_blocks) + "; raise block_size or max_blocks"};
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

// Samples on an s³ grid inside the block at `org` that fall inside (m_hood must hold the block).
template <class GridT> int VolumeImporter<GridT>::count_inside(const glm::i64vec3& org, int s) const {
    const double step = double(m_b) / s;
    int votes = 0;
    for (int z = 0; z < s; ++z)
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                const glm::dvec3 p = glm::dvec3(org) - 0.5 + (glm::dvec3(x, y, z) + 0.5) * step;
                votes += inside(m_hood.sample(p)) ? 1 : 0;
            }
    return votes;
}

// Majority of samples_per_axis³ samples on a regular grid inside the block. Blocks whose whole
// neighbourhood lies on one side of the threshold skip sampling (trilinear values lie between
// their corners' values, so that answer is exact). With `refine`, a solid fraction within 0.075
// of one half is redone at twice the rate per axis: close votes are where a coarse estimate
// flips.
template <class GridT> bool VolumeImporter<GridT>::supersample(const glm::i64vec3& src, bool refine) {
    const glm::i64vec3 org = src * int64_t(m_b);
    m_hood.fetch(m_acc, openvdb::Coord(int32_t(org.x - 1), int32_t(org.y - 1), int32_t(org.z - 1)), m_b + 2);
    if (inside(m_hood.min) == inside(m_hood.max))
        return inside(m_hood.min);
    ++m_supersampled;
    int s = m_o.samples_per_axis;
    int votes = count_inside(org, s);
    if (refine && s < 16 && std::abs(2 * votes - s * s * s) * 20 < 3 * s * s * s) {
        s = std::min(2 * s, 16);
        votes = count_inside(org, s);
    }
    if (2 * votes == s * s * s) // A tie (even sample counts): the centre decides.
        return inside(sample(glm::dvec3(org) + 0.5 * (m_b - 1)));
    return 2 * votes > s * s * s;
}

// More than half of the block's voxels inside (box reconstruction: no interpolation). `mean`
// gets the block's mean value relative to the grid's max.
template <class GridT> bool VolumeImporter<GridT>::voxel_majority(const glm::i64vec3& src, float& mean) {
    const glm::i64vec3 org = src * int64_t(m_b);
    const openvdb::Coord o(int32_t(org.x), int32_t(org.y), int32_t(org.z));
    int dense = 0;
    double sum = 0;
    for (int z = 0; z < m_b; ++z)
        for (int y = 0; y < m_b; ++y)
            for (int x = 0; x < m_b; ++x) {
                const double v = double(m_acc.getValue(o.offsetBy(x, y, z)));
                dense += inside(v) ? 1 : 0;
                sum += std::isfinite(v) ? v : 0.0;
            }
    const int volume = m_b * m_b * m_b;
    mean = float(sum / volume / m_max);
    return 2 * dense > volume;
}

template <class GridT> bool VolumeImporter<GridT>::solid(const glm::i64vec3& src, float& mean) {
    const glm::dvec3 centre = glm::dvec3(src * int64_t(m_b)) + 0.5 * (m_b - 1);
    mean = 0.f;
    switch (m_o.sampling) {
    case VolumeSampling::CentreOnly: {
        const double v = sample(centre);
        mean = float(v / m_max);
        return inside(v);
    }
    case VolumeSampling::VoxelMajority:
        return voxel_majority(src, mean);
    case VolumeSampling::Supersample: {
        const bool in = supersample(src, false);
        mean = float(m_hood.inner_mean() / m_max);
        return in;
    }
    case VolumeSampling::Adaptive:
        break;
    }
    if (!m_level_set) {
        const bool in = supersample(src, true);
        mean = float(m_hood.inner_mean() / m_max);
        return in;
    }
    // Signed distances are in world units; a zero crossing inside the block lies within half a
    // block diagonal of its centre (distance fields are 1-Lipschitz); one voxel of slack covers
    // interpolation and narrow-band clamping.
    const double phi = sample(centre) / m_voxel;
    const double near = 0.5 * std::sqrt(3.0) * m_b + 1.0;
    if (std::abs(phi) < near)
        return supersample(src, true);
    return phi < 0;
}

// Chunks (destination coordinates) whose blocks touch a leaf or an active tile, dilated by one
// voxel for the supersampling footprint. Other chunks are uniform: all one sign (level set) or
// all background (fog).
template <class GridT> void VolumeImporter<GridT>::add_chunks(openvdb::CoordBBox b) {
    b.expand(1);
    glm::i64vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(floor_div(b.min()[a], m_b), m_src_lo[a]) + m_o.offset[a];
        hi[a] = std::min(floor_div(b.max()[a], m_b), m_src_hi[a]) + m_o.offset[a];
        if (lo[a] > hi[a])
            return;
    }
    const ChunkCoord clo = world::chunk_of(lo), chi = world::chunk_of(hi);
    for (int z = clo.z; z <= chi.z; ++z)
        for (int y = clo.y; y <= chi.y; ++y)
            for (int x = clo.x; x <= chi.x; ++x)
                m_active.insert(ChunkCoord(x, y, z));
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
        const glm::dvec3 centre = (glm::dvec3(org - m_o.offset) + 0.5 * kChunkSize) * double(m_b) - 0.5;
        uniform_inside = sample(centre) < 0;
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
    for (int z = clo.z; z <= chi.z; ++z)
        for (int y = clo.y; y <= chi.y; ++y)
            for (int x = clo.x; x <= chi.x; ++x) {
                const ChunkCoord c(x, y, z);
                if (fill_chunk(c, m_active.count(c) != 0, ids))
                    out.world.put_chunk(c, world::Chunk::from_dense(ids));
            }
    VolumeImportSummary& s = out.summary;
    s.grid_index = m_index;
    s.grid_name = m_grid.getName();
    s.mode = m_level_set ? VolumeMode::LevelSet : VolumeMode::Fog;
    const openvdb::Vec3d vs = m_grid.voxelSize();
    s.voxel_size = glm::dvec3(vs[0], vs[1], vs[2]);
    s.block_size = m_b;
    s.threshold_absolute = m_threshold;
    s.max_value = m_max;
    s.solid_blocks = m_solid;
    s.supersampled_blocks = m_supersampled;
    s.blocks = BlockBox{m_src_lo + m_o.offset, m_src_hi + m_o.offset};
    return out;
}

Status check_options(const VolumeImportOptions& o) {
    if (o.block_size < 1 || o.block_size > 64)
        return Error{"block_size " + std::to_string(o.block_size) + " is outside 1..64"};
    if (o.samples_per_axis < 1 || o.samples_per_axis > 16)
        return Error{"samples_per_axis " + std::to_string(o.samples_per_axis) + " is outside 1..16"};
    if (o.block == world::kAir)
        return Error{"block is 0 (air); choose a solid block id"};
    for (const DensityBlock& d : o.density_blocks)
        if (d.block == world::kAir)
            return Error{"density_blocks maps to air (0); use ids > 0"};
    return {};
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
    if (Status s = check_options(options); !s)
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

Result<std::vector<GridInfo>> list_grids(const std::string& path) {
    return detail::serial<Result<std::vector<GridInfo>>>([&] { return list_grids_impl(path); });
}

Result<VolumeImport> import_volume(const std::string& path, const VolumeImportOptions& options) {
    return detail::serial<Result<VolumeImport>>([&] { return import_volume_impl(path, options); });
}

} // namespace vx::vdb
