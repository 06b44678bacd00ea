#pragma once
// The incremental edit path: a block edit updates the world and remeshes only the slices that
// bound the edited block (six in its chunk, plus one border plane in each face neighbour it
// touches). Engine and CLI both apply edits through this. Not thread-safe (main thread).

#include <array>
#include <functional>
#include <unordered_map>
#include <vector>

#include "world/mesh/apron.h"
#include "world/mesh/chunk_mesh.h"
#include "world/mesh/mesher.h"
#include "world/world.h"

namespace vx::world {

struct MeshedChunk {
    ChunkMesh mesh;
    Apron apron; // Input of batch meshing; edits read neighbours from the world instead.
};

using MeshMap = std::unordered_map<ChunkCoord, MeshedChunk, ChunkCoordHash>;

// The slices of one chunk's mesh an edit changed (full: the whole mesh was made anew). Slices
// not listed are exactly as before the edit.
struct SliceUpdate {
    ChunkCoord chunk{0};
    bool full = false;
    int count = 0;
    std::array<int, 6> slices{}; // slice_index() values, count of them.
};

struct EditResult {
    bool changed = false;             // False when the block already had that id.
    std::vector<SliceUpdate> updates; // Edited chunk first, then neighbours.
    int slices_remeshed = 0;
};

// Finds the mesh of a chunk, or null when the chunk is not meshed (then it is left alone).
using MeshLookup = std::function<ChunkMesh*(ChunkCoord)>;

class EditMesher {
public:
    // `isolated`: the meshes were made with air aprons (engine::LoadedScene::isolated, the seed
    // scene: each chunk meshed alone, as in the thesis). Edits then read air beyond the chunk
    // and leave the neighbours' meshes alone. Read from the world instead, an edit on a border
    // kept the quad of a block it removed (the neighbour hid it "before", so it was not redone).
    explicit EditMesher(bool isolated = false) : m_isolated(isolated) {}

    // Meshes chunk `c` of `world` from scratch into `meshes`.
    void mesh_chunk(const World& world, ChunkCoord c, MeshMap& meshes);

    // Sets block `p` to `id` and updates the meshes `lookup` finds: the edited chunk's six
    // slices (reported: those that changed; no update when none did) and the border plane of each
    // face neighbour the block touches. Neighbour blocks
    // are read from `world` (only the apron faces those slices use), so no apron is stored.
    // A chunk without a mesh is not meshed here; the caller decides (see full below).
    EditResult apply(World& world, BlockPos p, BlockId id, const MeshLookup& lookup);

    // MeshMap convenience: a chunk the edit creates (absent from `meshes`) is meshed whole.
    EditResult apply(World& world, BlockPos p, BlockId id, MeshMap& meshes);

    GreedyMesher& mesher() { return m_mesher; }

private:
    bool m_isolated = false;
    GreedyMesher m_mesher;
    Apron m_apron;
};

} // namespace vx::world
