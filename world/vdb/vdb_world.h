#pragma once
// Worlds as OpenVDB files: export a World (or a box of it) to a .vdb and import it back losslessly.
//
// File layout (format "vx-world", version 1):
//   - one openvdb::Int32Grid named "blocks": voxel value = block id, background 0 = air; air voxels
//     are inactive, every other block is an active voxel or part of an active tile. A uniform 32³
//     chunk is written as tiles (64 tiles of 8³ at the leaf-parent level; one 128³ tile when all
//     4³ chunks of a leaf-parent node agree, as OpenVDB's prune() merges them), never as voxels.
//   - grid metadata: "vx_format" = "vx-world", "vx_format_version" = 1, "vx_chunk_size" = 32, the
//     block registry as "vx_block_<id>_name" (string), "_albedo" (vec3s, linear RGB),
//     "_reflectivity" (float), "_emission" (vec3s, linear RGB radiance) and "_opaque" (bool) per
//     registered id, and "vx_box_min"/"vx_box_max" (vec3i, inclusive) when a box was exported.
//   - file metadata: "creator" = "vx".
//   - compression ZIP + active mask by default (no Blosc: it is optional in OpenVDB builds, zlib
//     is not), or active mask only.
//   - written by our streaming writer (vdb_stream.h): the tree's bytes are OpenVDB's for the same
//     tree; OpenVDB's optional "file_delayed_load" grid metadata is left out.
//
// Coordinates: block (x, y, z) is VDB voxel (x, y, z) in index space. OpenVDB index coordinates
// name voxel centres, so the grid's transform is "voxel size 1, translated by +0.5": voxel
// (i, j, k) has its centre at world (i + 0.5, j + 0.5, k + 0.5) and covers world
// [i, i + 1) x [j, j + 1) x [k, k + 1), exactly the space block (i, j, k) fills in vx.
// OpenVDB indexes voxels with 32-bit integers: blocks must lie within +-kVdbCoordLimit.

#include <cstdint>
#include <optional>
#include <string>

#include "world/base/result.h"
#include "world/coords.h"
#include "world/store/chunk_store.h"
#include "world/world.h"

namespace vx::vdb {

// An axis-aligned box of world blocks, both corners inclusive (world block coordinates). A plain
// value: thread-safe to read.
struct BlockBox {
    world::BlockPos min{0};
    world::BlockPos max{-1};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    bool contains(world::BlockPos p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};

// Largest |block coordinate| a VDB file may hold. OpenVDB's index space is int32; a margin of
// 2^13 keeps its node-origin and bounding-box arithmetic (nodes up to 4096 voxels wide) clear of
// overflow.
inline constexpr int64_t kVdbCoordLimit = (int64_t(1) << 31) - (int64_t(1) << 13);

enum class VdbCompression {
    Zip,  // zlib per node: small files; zlib is in every OpenVDB build. ~1 ms per mixed chunk.
    None, // Active-mask compression only: larger files, faster to write.
};

struct VdbExportOptions {
    std::optional<BlockBox> box; // Export only these blocks; the whole world when empty.
    VdbCompression compression = VdbCompression::Zip;
};

// Writes `world` (or its blocks inside options.box) to `path` as described above. The file is
// written to a temporary beside `path` and renamed over it only on success, so a failed export
// leaves an existing file untouched. Fails (with a one-line reason) on I/O errors and on blocks
// beyond kVdbCoordLimit. Streams node by node (VdbStreamWriter): memory is one Internal4 node (4³
// chunks) and the chunk coordinates (12 bytes each), beside `world`. Runs in the calling thread,
// starting none. Thread-safe as long as nobody writes `world` meanwhile.
Status export_vdb(const world::World& world, const std::string& path, const VdbExportOptions& options = {});

// As export_vdb, from a store, loading its chunks in file order: memory is one Internal4 node and
// the store's chunk coordinates (12 bytes each), flat in world size (but the store's own: a
// VdbOverlayStore holds its file's chunks; export_overlay_vdb streams that file instead).
// `registry` becomes the file's block metadata. Uses `store` from the calling thread (ChunkStore's
// rules); a damaged chunk fails the export. Returns the chunks written (those in options.box).
Result<uint64_t> export_store_vdb(world::ChunkStore& store, const world::BlockRegistry& registry, const std::string& path,
                        const VdbExportOptions& options = {});

struct VdbWorldImportOptions {
    std::optional<BlockBox> box;         // Import only these blocks; everything when empty.
    uint64_t max_chunks = uint64_t(1) << 22; // Refuse files whose (boxed) content spans more chunks.
};

// Reads a world written by export_vdb (or any file with an Int32 grid named "blocks" holding
// block ids 0..65535; its registry metadata is optional). The registry comes from the file's
// metadata when present, else the default registry. Partial import reads only the part of the
// tree inside options.box. The result is a new World: nothing on disk changes, so a failed import
// leaves any existing output untouched. Runs in the calling thread. Thread-safe (shares only
// OpenVDB's type registry, which openvdb::initialize() fills once under a lock). For untrusted
// files see import_world_vdb_isolated (vdb_isolated.h).
Result<world::World> import_world_vdb(const std::string& path, const VdbWorldImportOptions& options = {});

} // namespace vx::vdb
