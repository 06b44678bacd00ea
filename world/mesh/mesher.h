#pragma once
// The greedy chunk mesher. The culled, naive and classic meshers (comparison points and test
// oracles) live apart, in world/mesh/reference_meshers.h (target vx_mesh_reference).
//
// Face rule: the face of block A towards neighbour B is emitted iff A is not air, B is not
// opaque, and A != B (two blocks of one transparent type, e.g. water, show no face between
// them). Greedy merging joins faces of one block id and one facing direction only.
//
// Input: the chunk and its apron (chunk + neighbour borders = a snapshot; no world access), so a
// mesher can run on any thread. Output: a ChunkMesh, per slice (see chunk_mesh.h).

#include <cstdint>
#include <vector>

#include "world/mesh/apron.h"
#include "world/block_registry.h"
#include "world/chunk.h"
#include "world/mesh/chunk_mesh.h"

namespace vx::world {

struct MesherInput {
    const Chunk& chunk;
    const Apron& apron;
    const BlockRegistry& registry;
};

inline bool face_visible(BlockId a, BlockId b, const BlockRegistry& registry) {
    return a != kAir && a != b && !registry.is_opaque(b);
}

// Bitmask greedy mesher. Planes are built as 32-bit rows of face masks; runs are found with
// count-trailing-zeros and grown row by row, width first, then height (the classic greedy order,
// so it emits exactly the quads of a classic per-slice greedy mesher).
// Not thread-safe: owns scratch memory; use one instance per thread.
class GreedyMesher {
public:
    GreedyMesher();
    ~GreedyMesher();
    GreedyMesher(const GreedyMesher&) = delete;
    GreedyMesher& operator=(const GreedyMesher&) = delete;

    // Meshes the whole chunk into `out` (its storage is reused).
    void mesh(const MesherInput& in, ChunkMesh& out);

    // After block `p` (chunk-local) changed, remeshes the six slices bounding it (planes p and
    // p + 1 on each axis). `mesh` must be this chunk's mesh before the edit; afterwards it equals
    // mesh() of the new state. A neighbour chunk's border plane is the caller's: when p touches
    // face f, call remesh_slice on the neighbour across f (after updating its apron).
    void remesh_block(const MesherInput& in, LocalPos p, ChunkMesh& mesh);

    // The same when block p was `old` before the edit (its id in the mesh): only the plane sides
    // whose face at p or towards p changed (appeared, vanished or changed id) are touched (an
    // edit leaves about half of them alone); a changed face with no face of its id beside it in
    // the plane is one 1 x 1 quad in or out, swapped in place; the other changed sides are merged
    // again. `mesh` must come from this class (each slice's negative faces first, each side in
    // merge order, as mesh() writes them); the result equals mesh()'s quad for quad, in order.
    // Returns the slices that may have changed: bit 2 * axis + k for plane p[axis] + k (the
    // others are untouched, so a renderer need not upload them).
    uint32_t remesh_block(const MesherInput& in, LocalPos p, BlockId old, ChunkMesh& mesh);

    // Remeshes one slice (axis 0..2, plane 0..32).
    void remesh_slice(const MesherInput& in, int axis, int plane, ChunkMesh& mesh);

private:
    struct Scratch;
    Scratch* m_scratch;
};

} // namespace vx::world
