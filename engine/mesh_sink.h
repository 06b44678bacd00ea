#pragma once
// Where the streamer hands meshes: the renderer implements this (one BLAS per non-empty chunk);
// tests implement it as a recorder. Main thread only: every call comes from ChunkStreamer::update()
// or an edit, on the thread that owns the streamer.

#include <span>

#include "world/mesh/chunk_mesh.h"
#include "world/coords.h"

namespace vx::engine {

// An empty mesh (nothing to draw: air, or fully buried) that outlives every sink call. Thread-safe.
inline const world::ChunkMesh& empty_mesh() {
    static const world::ChunkMesh kEmpty;
    return kEmpty;
}

class MeshSink {
public:
    virtual ~MeshSink() = default;

    // Main thread. Chunk `c` has a new mesh (chunk-local block units). `changed_slices` lists the
    // slice_index() values an edit replaced; empty means the whole mesh is new. `mesh` stays valid
    // and unchanged until the next call for `c` (the streamer owns it). An empty mesh means nothing
    // to draw (air, or fully buried).
    virtual void on_mesh(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) = 0;

    // Main thread. Chunk `c` left the view; drop whatever was made from its mesh.
    virtual void on_unload(world::ChunkCoord c) = 0;

    // Main thread. Block `p` (world blocks) was edited: after its on_mesh calls, once per
    // change (an edit to the block's own id makes none). The renderer's denoiser drops the
    // history near it (render/edit_marks.h); sinks that keep no history ignore it.
    virtual void on_block_edited(world::BlockPos p) { (void)p; }
};

} // namespace vx::engine
