#pragma once
// The incremental edit path: a block edit updates the world and remeshes only the slices that
// bound the edited block (six in its chunk, plus one border plane in each face neighbour it
// touches). Engine and CLI both apply edits through this. Not thread-safe (main thread).

#include <unordered_map>
#include <vector>

#include "world/apron.h"
#include "world/chunk_mesh.h"
#include "world/mesher.h"
#include "world/world.h"

namespace vx::world {

struct MeshedChunk {
    ChunkMesh mesh;
    Apron apron; // Kept current so edits never re-read neighbours.
};

using MeshMap = std::unordered_map<ChunkCoord, MeshedChunk, ChunkCoordHash>;

struct EditResult {
    bool changed = false;                  // False when the block already had that id.
    std::vector<ChunkCoord> touched;       // Chunks whose mesh changed (edited one first).
    int slices_remeshed = 0;
};

class EditMesher {
public:
    // Meshes chunk `c` of `world` from scratch into `meshes`.
    void mesh_chunk(const World& world, ChunkCoord c, MeshMap& meshes);

    // Sets block `p` to `id` and brings every affected mesh in `meshes` up to date. A chunk the
    // edit creates is meshed whole; neighbours absent from `meshes` are left alone.
    EditResult apply(World& world, BlockPos p, BlockId id, MeshMap& meshes);

    GreedyMesher& mesher() { return m_mesher; }

private:
    GreedyMesher m_mesher;
};

} // namespace vx::world
