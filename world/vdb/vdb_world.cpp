#include "world/vdb/vdb_world.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <unordered_set>
#include <vector>

#include <openvdb/openvdb.h>

#include "world/vdb/vdb_common.h"

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
constexpr const char* kFormat = "vx-world";
constexpr int kFormatVersion = 1;

openvdb::Coord to_coord(BlockPos p) { return openvdb::Coord(int32_t(p.x), int32_t(p.y), int32_t(p.z)); }

bool in_vdb_range(BlockPos p) {
    return std::abs(p.x) <= kVdbCoordLimit && std::abs(p.y) <= kVdbCoordLimit && std::abs(p.z) <= kVdbCoordLimit;
}

BlockBox intersect(const BlockBox& a, const BlockBox& b) { return {glm::max(a.min, b.min), glm::min(a.max, b.max)}; }

BlockBox chunk_box(ChunkCoord c) { return {world::chunk_origin(c), world::chunk_origin(c) + BlockPos(kChunkSize - 1)}; }

std::string block_key(BlockId id, const char* field) {
    return "vx_block_" + std::to_string(id) + "_" + field;
}

// One 8³ leaf slot of a chunk, clipped to `box` (chunk-local dense ids in, tree out). A slot fully
// inside the box holding one non-air id becomes an active tile; otherwise non-air blocks become
// active voxels of a new leaf.
void write_slot(openvdb::Int32Tree& tree, const std::vector<BlockId>& ids, BlockPos chunk_org, glm::ivec3 slot,
                const BlockBox& box) {
    const BlockPos slot_org = chunk_org + BlockPos(slot * kLeafDim);
    int solid = 0;
    bool uniform = true;
    const BlockId first = ids[world::local_index(slot * kLeafDim)];
    for (int z = 0; z < kLeafDim; ++z)
        for (int y = 0; y < kLeafDim; ++y)
            for (int x = 0; x < kLeafDim; ++x) {
                const glm::ivec3 l = slot * kLeafDim + glm::ivec3(x, y, z);
                const BlockId id = ids[world::local_index(l)];
                uniform = uniform && id == first;
                solid += (id != world::kAir && box.contains(chunk_org + BlockPos(l))) ? 1 : 0;
            }
    if (solid == 0)
        return;
    if (uniform && solid == int(LeafT::SIZE)) {
        tree.addTile(1, to_coord(slot_org), int32_t(first), true);
        return;
    }
    auto leaf = std::make_unique<LeafT>(to_coord(slot_org), 0, false);
    for (int z = 0; z < kLeafDim; ++z)
        for (int y = 0; y < kLeafDim; ++y)
            for (int x = 0; x < kLeafDim; ++x) {
                const glm::ivec3 l = slot * kLeafDim + glm::ivec3(x, y, z);
                const BlockId id = ids[world::local_index(l)];
                if (id != world::kAir && box.contains(chunk_org + BlockPos(l)))
                    leaf->setValueOn(LeafT::coordToOffset(openvdb::Coord(x, y, z)), int32_t(id));
            }
    tree.addLeaf(leaf.release());
}

// Adds one chunk, clipped to `box`. Uniform chunks fully inside become tiles.
void write_chunk(openvdb::Int32Tree& tree, ChunkCoord c, const Chunk& chunk, const BlockBox& box,
                 std::vector<BlockId>& scratch) {
    const BlockBox cb = chunk_box(c);
    const BlockBox clip = intersect(cb, box);
    if (chunk.is_uniform() && clip.min == cb.min && clip.max == cb.max) {
        // sparseFill makes tiles at the largest level the (node-aligned) box covers: 64 tiles of 8³.
        tree.sparseFill(openvdb::CoordBBox(to_coord(cb.min), to_coord(cb.max)), int32_t(chunk.uniform_id()), true);
        return;
    }
    chunk.to_dense(scratch);
    for (int z = 0; z < kSlotsPerAxis; ++z)
        for (int y = 0; y < kSlotsPerAxis; ++y)
            for (int x = 0; x < kSlotsPerAxis; ++x)
                write_slot(tree, scratch, cb.min, glm::ivec3(x, y, z), clip);
}

void write_registry(openvdb::GridBase& grid, const world::BlockRegistry& registry) {
    grid.insertMeta("vx_block_table_size", openvdb::Int32Metadata(int32_t(registry.size())));
    for (size_t i = 1; i < registry.size(); ++i) {
        const BlockId id = BlockId(i);
        if (!registry.contains(id))
            continue;
        const world::BlockInfo b = registry.info(id);
        grid.insertMeta(block_key(id, "name"), openvdb::StringMetadata(b.name));
        grid.insertMeta(block_key(id, "albedo"), openvdb::Vec3SMetadata(openvdb::Vec3s(b.albedo.x, b.albedo.y, b.albedo.z)));
        grid.insertMeta(block_key(id, "reflectivity"), openvdb::FloatMetadata(b.reflectivity));
        grid.insertMeta(block_key(id, "emission"),
                        openvdb::Vec3SMetadata(openvdb::Vec3s(b.emission.x, b.emission.y, b.emission.z)));
        grid.insertMeta(block_key(id, "opaque"), openvdb::BoolMetadata(b.opaque));
    }
}

// Calls its argument for every chunk to export; an error stops the export.
using ChunkVisitor = std::function<Status(const std::function<Status(ChunkCoord, const Chunk&)>&)>;

// Builds the "blocks" grid from the chunks `visit` hands out (one at a time: nothing but the tree
// and the chunk in hand is held); fails on blocks beyond OpenVDB's index range.
Result<openvdb::Int32Grid::Ptr> build_grid(const ChunkVisitor& visit, const world::BlockRegistry& registry,
                                           const VdbExportOptions& options) {
    const BlockBox all{BlockPos(INT64_MIN), BlockPos(INT64_MAX)};
    const BlockBox box = options.box ? *options.box : all;
    auto grid = openvdb::Int32Grid::create(0);
    std::vector<BlockId> scratch(kChunkVolume);
    Status visited = visit([&](ChunkCoord c, const Chunk& chunk) -> Status {
        const BlockBox clip = intersect(chunk_box(c), box);
        if (clip.empty() || chunk.is_empty())
            return {};
        if (!in_vdb_range(clip.min) || !in_vdb_range(clip.max)) {
            char msg[160];
            std::snprintf(msg, sizeof msg, "chunk (%d, %d, %d) lies beyond OpenVDB's 32-bit index range (|block| <= %lld)",
                          c.x, c.y, c.z, (long long)kVdbCoordLimit);
            return Error{msg};
        }
        write_chunk(grid->tree(), c, chunk, box, scratch);
        return {};
    });
    if (!visited)
        return Error{visited.error()};
    grid->tree().prune(); // Merges equal tiles into larger ones; exact (tolerance 0).
    grid->setName(kGridName);
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    // Voxel (i, j, k) covers world [i, i + 1): its centre, the index point, sits at i + 0.5.
    auto xform = openvdb::math::Transform::createLinearTransform(1.0);
    xform->postTranslate(openvdb::Vec3d(0.5));
    grid->setTransform(xform);
    grid->insertMeta("vx_format", openvdb::StringMetadata(kFormat));
    grid->insertMeta("vx_format_version", openvdb::Int32Metadata(kFormatVersion));
    grid->insertMeta("vx_chunk_size", openvdb::Int32Metadata(kChunkSize));
    if (options.box && !options.box->empty() && in_vdb_range(options.box->min) && in_vdb_range(options.box->max)) {
        const BlockPos lo = options.box->min, hi = options.box->max;
        grid->insertMeta("vx_box_min", openvdb::Vec3IMetadata(openvdb::Vec3i(int(lo.x), int(lo.y), int(lo.z))));
        grid->insertMeta("vx_box_max", openvdb::Vec3IMetadata(openvdb::Vec3i(int(hi.x), int(hi.y), int(hi.z))));
    }
    write_registry(*grid, registry);
    return grid;
}

// ---- import ----

template <class T> std::optional<T> get_meta(const openvdb::GridBase& g, const std::string& key) {
    auto m = g.getMetadata<openvdb::TypedMetadata<T>>(key);
    if (!m)
        return std::nullopt;
    return m->value();
}

glm::vec3 to_glm(const openvdb::Vec3s& v) { return glm::vec3(v.x(), v.y(), v.z()); }

Result<world::BlockRegistry> read_registry(const openvdb::GridBase& g) {
    const auto table = get_meta<int32_t>(g, "vx_block_table_size");
    if (!table)
        return world::BlockRegistry::default_registry();
    if (*table < 1 || *table > 0x10000)
        return Error{"metadata vx_block_table_size = " + std::to_string(*table) + " is out of range 1..65536"};
    world::BlockRegistry r;
    for (int i = 1; i < *table; ++i) {
        const BlockId id = BlockId(i);
        const auto name = get_meta<std::string>(g, block_key(id, "name"));
        if (!name)
            continue;
        world::BlockInfo b;
        b.name = *name;
        if (auto v = get_meta<openvdb::Vec3s>(g, block_key(id, "albedo")))
            b.albedo = to_glm(*v);
        if (auto v = get_meta<float>(g, block_key(id, "reflectivity")))
            b.reflectivity = *v;
        if (auto v = get_meta<openvdb::Vec3s>(g, block_key(id, "emission")))
            b.emission = to_glm(*v);
        if (auto v = get_meta<bool>(g, block_key(id, "opaque")))
            b.opaque = *v;
        if (Status s = r.set(id, std::move(b)); !s)
            return Error{"block " + std::to_string(i) + " in the file's registry: " + s.error()};
    }
    return r;
}

struct ChunkSet {
    std::unordered_set<ChunkCoord, world::ChunkCoordHash> chunks;
    bool too_many = false;
    bool out_of_range = false; // Content beyond +-kVdbCoordLimit.
};

// Adds the chunks overlapping the index box [lo, hi] clipped to `box`; refuses more than `cap`.
void add_chunks(ChunkSet& set, const openvdb::CoordBBox& b, const BlockBox& box, uint64_t cap) {
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
    if (n.x * n.y * n.z > cap || set.chunks.size() + n.x * n.y * n.z > cap) {
        set.too_many = true;
        return;
    }
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x)
                set.chunks.insert(ChunkCoord(x, y, z));
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
        add_chunks(set, b, box, cap);
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
        // Partial read: only leaf buffers overlapping the box are loaded. World space is index
        // space + 0.5 (see the header); a one-block margin keeps clipping conservative, and
        // grid_to_world clips exactly.
        const glm::dvec3 lo = glm::dvec3(glm::max(options.box->min, BlockPos(-kVdbCoordLimit))) - 1.0;
        const glm::dvec3 hi = glm::dvec3(glm::min(options.box->max, BlockPos(kVdbCoordLimit))) + 2.0;
        base = file.readGrid(kGridName, openvdb::BBoxd(openvdb::Vec3d(lo.x, lo.y, lo.z), openvdb::Vec3d(hi.x, hi.y, hi.z)));
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

static Status export_vdb_impl(const ChunkVisitor& visit, const world::BlockRegistry& registry,
                              const std::string& path, const VdbExportOptions& options) {
    Result<std::string> created = detail::create_temp_beside(path);
    if (!created)
        return Error{"cannot export to '" + path + "': " + created.error()};
    const std::string tmp = *created;
    try {
        openvdb::initialize();
        Result<openvdb::Int32Grid::Ptr> grid = build_grid(visit, registry, options);
        if (!grid) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return Error{"cannot export to '" + path + "': " + grid.error()};
        }
        openvdb::io::File file(tmp);
        // ZIP rather than Blosc: zlib is part of every OpenVDB build, Blosc is optional.
        file.setCompression(options.compression == VdbCompression::Zip
                                ? openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK
                                : openvdb::io::COMPRESS_ACTIVE_MASK);
        openvdb::MetaMap meta;
        meta.insertMeta("creator", openvdb::StringMetadata("vx"));
        file.write(openvdb::GridCPtrVec{*grid}, meta);
        file.close();
    } catch (const std::exception& e) { // openvdb::Exception derives from std::exception.
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        return detail::make_error("cannot write '" + path + "'", e.what());
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        return detail::make_error("cannot write '" + path + "'", "unknown error");
    }
    return detail::replace_file(tmp, path);
}

static Result<world::World> import_world_vdb_impl(const std::string& path, const VdbWorldImportOptions& options) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return Error{"cannot read '" + path + "': no such file"};
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

Status export_vdb(const world::World& w, const std::string& path, const VdbExportOptions& options) {
    const ChunkVisitor visit = [&](const std::function<Status(ChunkCoord, const Chunk&)>& fn) -> Status {
        Status result;
        w.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
            if (result)
                result = fn(c, chunk);
        });
        return result;
    };
    return detail::serial<Status>([&] { return export_vdb_impl(visit, w.registry(), path, options); });
}

Status export_store_vdb(world::ChunkStore& store, const world::BlockRegistry& registry, const std::string& path,
                        const VdbExportOptions& options) {
    const ChunkVisitor visit = [&](const std::function<Status(ChunkCoord, const Chunk&)>& fn) -> Status {
        // The coordinates first (12 bytes each): for_each_coord's callback may not call the store.
        Result<std::vector<ChunkCoord>> coords = store.list_coords();
        if (!coords)
            return Error{coords.error()};
        for (const ChunkCoord c : *coords) {
            if (options.box && intersect(chunk_box(c), *options.box).empty())
                continue;
            Result<world::ChunkLoad> load = store.load(c);
            if (!load)
                return Error{load.error()};
            if (load->state == world::LoadState::Corrupt) {
                char where[96];
                std::snprintf(where, sizeof where, "chunk (%d, %d, %d) is damaged: ", c.x, c.y, c.z);
                return Error{where + load->problem};
            }
            if (load->state == world::LoadState::Present)
                if (Status s = fn(c, *load->chunk); !s)
                    return s;
        }
        return {};
    };
    return detail::serial<Status>([&] { return export_vdb_impl(visit, registry, path, options); });
}

Result<world::World> import_world_vdb(const std::string& path, const VdbWorldImportOptions& options) {
    return detail::serial<Result<world::World>>([&] { return import_world_vdb_impl(path, options); });
}

} // namespace vx::vdb
