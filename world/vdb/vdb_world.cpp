#include "world/vdb/vdb_world.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <openvdb/openvdb.h>

#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_meta.h"

namespace vx::vdb {
namespace {

using world::BlockId;
using world::BlockPos;
using world::Chunk;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;
using LeafT = openvdb::Int32Tree::LeafNodeType;

constexpr int kLeafDim = int(LeafT::DIM); // 8: OpenVDB leaf nodes are 8³ voxels.
constexpr int kSlotsPerAxis = kChunkSize / kLeafDim;
static_assert(kChunkSize % kLeafDim == 0, "a chunk must hold whole leaf nodes");

constexpr const char* kGridName = "blocks";
constexpr int kFormatVersion = 1;

openvdb::Coord to_coord(BlockPos p) { return openvdb::Coord(int32_t(p.x), int32_t(p.y), int32_t(p.z)); }

bool in_vdb_range(BlockPos p) {
    return std::abs(p.x) <= kVdbCoordLimit && std::abs(p.y) <= kVdbCoordLimit && std::abs(p.z) <= kVdbCoordLimit;
}

BlockBox intersect(const BlockBox& a, const BlockBox& b) { return {glm::max(a.min, b.min), glm::min(a.max, b.max)}; }

// ---- import ----

template <class T> std::optional<T> get_meta(const openvdb::GridBase& g, const std::string& key) {
    auto m = g.getMetadata<openvdb::TypedMetadata<T>>(key);
    if (!m)
        return std::nullopt;
    return m->value();
}

// The grid's vx_* metadata as raw items (Metadata::write gives the value's size, then its bytes),
// read by the same code as the streaming reader's.
Result<world::BlockRegistry> read_registry(const openvdb::GridBase& g) {
    detail::VdbMetaMap meta;
    for (auto it = g.beginMeta(); it != g.endMeta(); ++it) {
        if (it->first.compare(0, 3, "vx_") != 0 || !it->second)
            continue;
        std::ostringstream os;
        it->second->write(os);
        const std::string bytes = os.str();
        meta[it->first] = {it->second->typeName(), bytes.size() >= 4 ? bytes.substr(4) : std::string()};
    }
    return detail::registry_from_meta(meta);
}

struct ChunkSet {
    std::unordered_set<ChunkCoord, world::ChunkCoordHash> chunks; // Read voxel by voxel.
    // Chunks wholly inside one active tile (and the box): all of them the tile's value. Tiles
    // (128³ and 4096³ regions; the exporter writes one for every region of one block) are
    // disjoint from leaves and from each other, so such a chunk holds nothing else. Reading them
    // voxel by voxel cost minutes of CPU for one 3 KB file.
    std::unordered_map<ChunkCoord, int32_t, world::ChunkCoordHash> uniform;
    bool too_many = false;
    bool out_of_range = false; // Content beyond +-kVdbCoordLimit.
    size_t size() const { return chunks.size() + uniform.size(); }
};

// Adds the chunks overlapping the index box [lo, hi] clipped to `box`; refuses more than `cap`.
// `tile`: the box is an active tile of this value (chunks wholly inside it are uniform).
void add_chunks(ChunkSet& set, const openvdb::CoordBBox& b, const BlockBox& box, uint64_t cap,
                std::optional<int32_t> tile = std::nullopt) {
    const BlockPos bmin(b.min().x(), b.min().y(), b.min().z()), bmax(b.max().x(), b.max().y(), b.max().z());
    if (!in_vdb_range(bmin) || !in_vdb_range(bmax)) {
        set.out_of_range = true;
        return;
    }
    const BlockBox clip = intersect({bmin, bmax}, box);
    if (clip.empty())
        return;
    const ChunkCoord lo = world::chunk_of(clip.min), hi = world::chunk_of(clip.max);
    const glm::u64vec3 n = glm::u64vec3(glm::i64vec3(hi) - glm::i64vec3(lo) + glm::i64vec3(1));
    if (n.x * n.y * n.z > cap || set.size() + n.x * n.y * n.z > cap) {
        set.too_many = true;
        return;
    }
    // 64-bit counters: the world's last chunk is INT32_MAX, where ++ on an int never passes it.
    for (int64_t z = lo.z; z <= hi.z; ++z)
        for (int64_t y = lo.y; y <= hi.y; ++y)
            for (int64_t x = lo.x; x <= hi.x; ++x) {
                const ChunkCoord c{int32_t(x), int32_t(y), int32_t(z)};
                const BlockPos org = world::chunk_origin(c);
                if (tile && clip.contains(org) && clip.contains(org + BlockPos(kChunkSize - 1)))
                    set.uniform.emplace(c, *tile);
                else
                    set.chunks.insert(c);
            }
}

ChunkSet touched_chunks(const openvdb::Int32Tree& tree, const BlockBox& box, uint64_t cap) {
    ChunkSet set;
    for (auto it = tree.cbeginLeaf(); it && !set.too_many && !set.out_of_range; ++it)
        add_chunks(set, it->getNodeBoundingBox(), box, cap);
    auto tiles = tree.cbeginValueOn();
    tiles.setMaxDepth(openvdb::Int32Tree::ValueOnCIter::LEAF_DEPTH - 1); // Tiles only, not voxels.
    for (; tiles && !set.too_many && !set.out_of_range; ++tiles) {
        openvdb::CoordBBox b;
        tiles.getBoundingBox(b);
        add_chunks(set, b, box, cap, tiles.getValue());
    }
    return set;
}

// Reads one chunk's ids from the tree (inactive = air); fails on values that are not block ids.
Status read_chunk(openvdb::Int32Grid::ConstAccessor& acc, ChunkCoord c, const BlockBox& box, std::vector<BlockId>& ids) {
    const BlockPos org = world::chunk_origin(c);
    for (int sz = 0; sz < kSlotsPerAxis; ++sz)
        for (int sy = 0; sy < kSlotsPerAxis; ++sy)
            for (int sx = 0; sx < kSlotsPerAxis; ++sx) {
                const glm::ivec3 slot = glm::ivec3(sx, sy, sz) * kLeafDim;
                const openvdb::Coord so = to_coord(org + BlockPos(slot));
                const LeafT* leaf = acc.probeConstLeaf(so);
                const bool tile_on = leaf ? false : acc.isValueOn(so);
                const int32_t tile_value = leaf ? 0 : acc.getValue(so);
                for (int z = 0; z < kLeafDim; ++z)
                    for (int y = 0; y < kLeafDim; ++y)
                        for (int x = 0; x < kLeafDim; ++x) {
                            const glm::ivec3 l = slot + glm::ivec3(x, y, z);
                            int32_t v = tile_on ? tile_value : 0;
                            if (leaf) {
                                const openvdb::Index off = LeafT::coordToOffset(openvdb::Coord(x, y, z));
                                v = leaf->isValueOn(off) ? leaf->getValue(off) : 0;
                            }
                            const BlockPos p = org + BlockPos(l);
                            if (!box.contains(p))
                                v = 0;
                            if (v < 0 || v > 0xFFFF)
                                return Error{"voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                                             std::to_string(p.z) + ") holds " + std::to_string(v) +
                                             ", not a block id (0..65535)"};
                            ids[size_t(world::local_index(l))] = BlockId(v);
                        }
            }
    return {};
}

Result<world::World> grid_to_world(const openvdb::Int32Grid& grid, const VdbWorldImportOptions& options) {
    Result<world::BlockRegistry> registry = read_registry(grid);
    if (!registry)
        return Error{registry.error()};
    const BlockBox all{BlockPos(-kVdbCoordLimit), BlockPos(kVdbCoordLimit)};
    const BlockBox box = options.box ? intersect(*options.box, all) : all;
    world::World w(std::move(*registry));
    if (box.empty())
        return w;
    ChunkSet set = touched_chunks(grid.tree(), box, options.max_chunks);
    if (set.out_of_range)
        return Error{"the grid holds voxels beyond index +-" + std::to_string(kVdbCoordLimit) +
                     ", too close to OpenVDB's 32-bit limit"};
    if (set.too_many)
        return Error{"the grid spans more than " + std::to_string(options.max_chunks) +
                     " chunks; import a smaller box or raise max_chunks"};
    for (const auto& [c, v] : set.uniform) {
        if (v < 0 || v > 0xFFFF) {
            const BlockPos p = world::chunk_origin(c);
            return Error{"voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                         ") holds " + std::to_string(v) + ", not a block id (0..65535)"};
        }
        if (v != 0)
            w.put_chunk(c, Chunk(BlockId(v)));
    }
    auto acc = grid.getConstAccessor();
    std::vector<BlockId> ids(kChunkVolume);
    for (const ChunkCoord& c : set.chunks) {
        if (Status s = read_chunk(acc, c, box, ids); !s)
            return Error{s.error()};
        Chunk chunk = Chunk::from_dense(ids);
        if (!chunk.is_empty())
            w.put_chunk(c, std::move(chunk));
    }
    return w;
}

Result<openvdb::Int32Grid::Ptr> read_blocks_grid(const std::string& path, const VdbWorldImportOptions& options) {
    openvdb::io::File file(path);
    file.open(false); // No delayed loading: every read error surfaces here, inside the try.
    if (!file.hasGrid(kGridName)) {
        file.close();
        return Error{"'" + path + "' has no grid named 'blocks' (not a vx world; use import_volume for other volumes)"};
    }
    openvdb::GridBase::Ptr base;
    if (options.box && !options.box->empty()) {
        // Partial read: only leaf buffers overlapping the box are loaded. Blocks are index
        // coordinates whatever the grid's transform (as the whole import reads them), and OpenVDB
        // clips in world space: the box goes through the grid's own transform (it was taken as
        // unit voxels, so a grid of voxel size 4 lost most of the box). A one-voxel margin keeps
        // the clip conservative; grid_to_world clips exactly.
        // Both ends inside the file's range (a box past it wrapped to another region in 32 bits).
        const BlockPos limit(kVdbCoordLimit);
        const BlockPos lo = glm::clamp(options.box->min, -limit, limit) - BlockPos(1);
        const BlockPos hi = glm::clamp(options.box->max, -limit, limit) + BlockPos(1);
        const openvdb::GridBase::ConstPtr meta = file.readGridMetadata(kGridName);
        const openvdb::BBoxd world_box = meta->transform().indexToWorld(
            openvdb::CoordBBox(openvdb::Coord(int32_t(lo.x), int32_t(lo.y), int32_t(lo.z)),
                               openvdb::Coord(int32_t(hi.x), int32_t(hi.y), int32_t(hi.z))));
        base = file.readGrid(kGridName, world_box);
    } else {
        base = file.readGrid(kGridName);
    }
    file.close();
    auto grid = openvdb::gridPtrCast<openvdb::Int32Grid>(base);
    if (!grid)
        return Error{"grid 'blocks' in '" + path + "' holds " + base->valueType() + " values, not int32 block ids"};
    if (auto version = get_meta<int32_t>(*grid, "vx_format_version"); version && *version > kFormatVersion)
        return Error{"'" + path + "' uses vx-world format version " + std::to_string(*version) + ", newer than " +
                     std::to_string(kFormatVersion)};
    return grid;
}

} // namespace

static Result<world::World> import_world_vdb_impl(const std::string& path, const VdbWorldImportOptions& options) {
    if (std::string why = detail::unreadable_file(path); !why.empty())
        return Error{why};
    try {
        openvdb::initialize();
        Result<openvdb::Int32Grid::Ptr> grid = read_blocks_grid(path, options);
        if (!grid)
            return Error{grid.error()};
        Result<world::World> w = grid_to_world(**grid, options);
        if (!w)
            return Error{"cannot import '" + path + "': " + w.error()};
        return w;
    } catch (const std::exception& e) {
        return detail::make_error("cannot read '" + path + "'", e.what());
    } catch (...) {
        return detail::make_error("cannot read '" + path + "'", "unknown error");
    }
}

Result<world::World> import_world_vdb(const std::string& path, const VdbWorldImportOptions& options) {
    return detail::serial<Result<world::World>>([&] { return import_world_vdb_impl(path, options); });
}

} // namespace vx::vdb
