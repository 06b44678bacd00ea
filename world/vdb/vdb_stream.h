#pragma once
// Streaming I/O of vx-world VDB files (layout in vdb_world.h) without OpenVDB and without the
// whole tree in memory, so exports stay flat in world size.
//
// An OpenVDB Int32 tree is Root -> Internal (32³ children, 4096³ voxels) -> Internal (16³
// children, 128³ voxels = 4 x 4 x 4 chunks) -> Leaf (8³ voxels). A file holds the topology of the
// whole tree (root children sorted by origin; inside an internal node children by offset, x
// major), then every leaf's values in the same order. "File order" of chunks follows that: by
// Internal5 node (chunk >> 7, lexicographic), then Internal4 node (chunk >> 2), then chunk.
//
// The writer takes chunks in file order and holds one Internal4 node (at most 64 chunks, plus
// 4 MB of dense scratch); it writes topology to the output and leaf values to a scratch file,
// then appends them and patches the offsets and statistics that precede the tree. The reader walks topology and leaf values with two file cursors in lock step and
// hands out one Internal4 node's chunks at a time. Neither uses OpenVDB or starts threads.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "world/base/result.h"
#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/coords.h"
#include "world/vdb/vdb_world.h"

namespace vx::vdb {

// True when chunk a comes before b in file order (see above). Thread-safe.
bool file_order_less(world::ChunkCoord a, world::ChunkCoord b);
// The Internal4 node (4 x 4 x 4 chunks) holding chunk c, as chunk coordinates >> 2. Thread-safe.
inline world::ChunkCoord node_of(world::ChunkCoord c) { return c >> 2; }

// Writes a vx-world VDB file from chunks given in file order. The output is a temporary beside
// `path`, renamed over it by finish(); destroying the writer before finish() removes it, so a
// failed export leaves an existing file untouched. Memory: one Internal4 node (<= 64 chunks),
// 4 MB of scratch and 136 KB for the Internal5 node in progress; that node's children's
// topology, the root's children's and all leaf values wait in scratch files beside `path`
// (unlinked once open). Uniform nodes become tiles as OpenVDB's prune() makes them, up to root
// tiles. Not thread-safe: one thread at a time.
class VdbStreamWriter {
public:
    // Opens the temporaries; metadata and transform as vdb_world.h describes (no
    // "file_delayed_load" item: OpenVDB's optional per-leaf index, which would have to precede
    // the tree; its readers do without it). One-line errors.
    static Result<std::unique_ptr<VdbStreamWriter>> create(const std::string& path, const world::BlockRegistry& registry,
                                                           const VdbExportOptions& options);
    ~VdbStreamWriter();
    VdbStreamWriter(const VdbStreamWriter&) = delete;
    VdbStreamWriter& operator=(const VdbStreamWriter&) = delete;

    // Adds chunk c (clipped to the options' box; air and chunks outside the box write nothing).
    // Chunks must come in file order, each at most once; out of order or beyond kVdbCoordLimit is
    // an error, after which only destruction is valid.
    Status add(world::ChunkCoord c, const world::Chunk& chunk);
    // Writes the rest, then renames the file into place. Call once.
    Status finish();

    uint64_t chunks_written() const { return m_chunks; } // Non-empty chunks added so far.

private:
    struct State;
    explicit VdbStreamWriter(std::unique_ptr<State> s);
    std::unique_ptr<State> m_state;
    uint64_t m_chunks = 0;
};

struct VdbStreamReadOptions {
    // Refuse files whose tiles above leaf level expand to more chunks than this (a 4096³ root tile
    // is 2M chunks); leaves are not counted (each costs file bytes).
    uint64_t max_tile_chunks = uint64_t(1) << 22;
};

// Reads a vx-world VDB file node by node. Accepts what export_vdb and OpenVDB write for the
// layout: one Int32 grid "blocks" (other grids skipped), compression none, ZIP and/or active mask,
// tiles at any level, file versions 222..224. Anything else (Blosc, half floats, other value
// types or transforms, instanced grids, damage) is a one-line error, so the caller can fall back
// to OpenVDB's reader; every count and size read is checked against the file, so garbage never
// crashes it or makes it allocate more than a node. Memory: one Internal4 node's chunks plus
// 4 MB of scratch and 136 KB for the Internal5 node. Not thread-safe: one thread at a time.
class VdbStreamReader {
public:
    static Result<std::unique_ptr<VdbStreamReader>> open(const std::string& path,
                                                         const VdbStreamReadOptions& options = {});
    ~VdbStreamReader();
    VdbStreamReader(const VdbStreamReader&) = delete;
    VdbStreamReader& operator=(const VdbStreamReader&) = delete;

    // The registry from the file's metadata (the default registry when it has none).
    const world::BlockRegistry& registry() const;

    // Replaces `out` with the non-empty chunks of the next Internal4 node in file order (sorted in
    // file order; inactive voxels are air). Returns false at the end of the tree, after checking
    // that both cursors ended where the file says. An error is final.
    Result<bool> next(std::vector<std::pair<world::ChunkCoord, world::Chunk>>& out);

private:
    struct State;
    explicit VdbStreamReader(std::unique_ptr<State> s);
    std::unique_ptr<State> m_state;
};

} // namespace vx::vdb
