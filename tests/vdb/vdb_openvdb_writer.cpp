#include "tests/vdb/vdb_openvdb_writer.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <vector>

#include <openvdb/openvdb.h>

namespace vx::vdb::test {
namespace {

using world::BlockId;
using world::BlockPos;
using world::Chunk;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;
using LeafT = openvdb::Int32Tree::LeafNodeType;

constexpr int kLeafDim = int(LeafT::DIM);
constexpr int kSlotsPerAxis = kChunkSize / kLeafDim;
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

// Builds the "blocks" grid of `w` in memory; fails on blocks beyond OpenVDB's index range.
Result<openvdb::Int32Grid::Ptr> build_grid(const world::World& w, const world::BlockRegistry& registry,
                                           const VdbExportOptions& options) {
    const BlockBox all{BlockPos(INT64_MIN), BlockPos(INT64_MAX)};
    const BlockBox box = options.box ? *options.box : all;
    auto grid = openvdb::Int32Grid::create(0);
    std::vector<BlockId> scratch(kChunkVolume);
    Status visited;
    w.for_each_chunk([&](ChunkCoord c, const Chunk& chunk) {
        const BlockBox clip = intersect(chunk_box(c), box);
        if (!visited || clip.empty() || chunk.is_empty())
            return;
        if (!in_vdb_range(clip.min) || !in_vdb_range(clip.max))
            visited = Error{"beyond OpenVDB's 32-bit index range"};
        else
            write_chunk(grid->tree(), c, chunk, box, scratch);
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

// Reads the "blocks" grid and the file metadata of `in` with OpenVDB and writes the grids
// `grids(blocks)` makes to `out` with that metadata (`compression`: OpenVDB's flags; none: its
// default).
template <class MakeGrids>
Status rewrite_blocks_openvdb(const std::string& in, const std::string& out, std::optional<uint32_t> compression,
                              MakeGrids grids) {
    try {
        openvdb::initialize();
        openvdb::io::File file(in);
        file.open(false);
        openvdb::GridBase::Ptr blocks = file.readGrid(kGridName);
        openvdb::MetaMap::Ptr file_meta = file.getMetadata();
        file.close();
        const openvdb::GridCPtrVec written = grids(blocks);
        openvdb::io::File o(out);
        if (compression)
            o.setCompression(*compression);
        o.write(written, *file_meta);
        o.close();
    } catch (const std::exception& e) {
        return Error{std::string("OpenVDB: ") + e.what()};
    }
    return {};
}

} // namespace

Status write_world_openvdb(const world::World& w, const std::string& path, const VdbExportOptions& options,
                           bool blosc) {
    try {
        openvdb::initialize();
        Result<openvdb::Int32Grid::Ptr> grid = build_grid(w, w.registry(), options);
        if (!grid)
            return Error{grid.error()};
        openvdb::io::File file(path);
        file.setCompression(options.compression == VdbCompression::Zip
                                ? openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK
                                : openvdb::io::COMPRESS_ACTIVE_MASK);
        if (blosc)
            file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
        openvdb::MetaMap meta;
        meta.insertMeta("creator", openvdb::StringMetadata("vx"));
        file.write(openvdb::GridCPtrVec{*grid}, meta);
        file.close();
    } catch (const std::exception& e) {
        return Error{std::string("OpenVDB: ") + e.what()};
    }
    return {};
}

Status write_root_tile_openvdb(const std::string& path) {
    try {
        openvdb::initialize();
        auto grid = openvdb::Int32Grid::create(0);
        grid->tree().addTile(3, openvdb::Coord(0), 3, true);
        grid->tree().setValueOn(openvdb::Coord(-1), 5);
        grid->setName(kGridName);
        openvdb::io::File file(path);
        file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
        file.write(openvdb::GridCPtrVec{grid});
        file.close();
    } catch (const std::exception& e) {
        return Error{std::string("OpenVDB: ") + e.what()};
    }
    return {};
}

Status rescale_openvdb(const std::string& in, const std::string& out, double voxel_size) {
    return rewrite_blocks_openvdb(in, out, std::nullopt, [&](const openvdb::GridBase::Ptr& blocks) {
        blocks->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size));
        return openvdb::GridCPtrVec{blocks};
    });
}

Status prepend_instanced_grids_openvdb(const std::string& in, const std::string& out) {
    // ZIP: with OpenVDB's default (Blosc) the streaming reader would refuse the file for that.
    const uint32_t zip = openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    return rewrite_blocks_openvdb(in, out, zip, [](const openvdb::GridBase::Ptr& blocks) {
        openvdb::Int32Grid::Ptr terrain = openvdb::Int32Grid::create(0);
        terrain->setName("terrain");
        terrain->denseFill(openvdb::CoordBBox({0, 0, 0}, {9, 9, 9}), 4, true);
        openvdb::Int32Grid::Ptr copy = openvdb::Int32Grid::create(terrain->treePtr()); // Shares the tree.
        copy->setName("terrain_copy");
        return openvdb::GridCPtrVec{terrain, copy, blocks};
    });
}

std::map<std::string, std::string> grid_meta_openvdb(const std::string& path) {
    std::map<std::string, std::string> out;
    try {
        openvdb::initialize();
        openvdb::io::File file(path);
        file.open(false);
        openvdb::GridBase::Ptr grid = file.readGrid(kGridName);
        file.close();
        for (auto it = grid->beginMeta(); it != grid->endMeta(); ++it)
            out[it->first] = it->second->str();
    } catch (const std::exception&) {
        out.clear();
    }
    return out;
}

} // namespace vx::vdb::test
