#pragma once
// Which transparent faces of a chunk the ray tracer probes for a coincident face (coincident_pass
// in shaders/shared/raygen_common.glsl). Where two different transparent blocks touch (glass
// against water) each has its own face on the same plane and the traversal reports only one of
// them; a probe finds the other. It costs a ray per face crossed, so only faces that may have
// such a partner carry the mark (bit kQuadMayTouch of world::Quad::reserved, shaders/shared/
// render_types.h): inside the chunk, exactly the quads that overlap a face of a different
// transparent block on the same plane, facing the other way (a greedy quad is marked whole when
// part of it does); on the chunk's border planes, every transparent quad (the partner would be in
// the neighbour's mesh, which this chunk does not see; the mark stays right whichever neighbour
// comes later). Any thread (pure function).

#include <array>
#include <span>
#include <vector>

#include "world/block_registry.h"
#include "world/mesh/chunk_mesh.h"

namespace vx::render {

// A chunk's transparent faces on its six border planes, which all face out of the chunk: side
// axis * 2 + (plane == kChunkSize), each empty (no such face) or kChunkSize^2 blocks, cell (u, v)
// of the plane (world/mesh/chunk_mesh.h's u and v axes) at u + v * kChunkSize, 0 where no face.
// Whether a neighbour's face meets one of them: render/touching_pairs.h.
using BorderFaces = std::array<std::vector<world::BlockId>, 6>;

struct TouchingFaces {
    bool marked = false; // Some quad carries a mark: `out` holds the marked mesh.
    bool inside = false; // Two different transparent blocks touch within the chunk.
    BorderFaces border;
};

// Writes `mesh` with the marks set into `out` when some quad needs one (else leaves `out` alone,
// as for a chunk without transparent blocks or a lake's chunk away from its borders), and returns
// what the frame's choice of pipeline variant needs. `ids`: the blocks of the mesh's quads (any
// order, each once); a quad whose block is not among them counts as opaque. `mesh` carries no
// marks (as a mesher writes it).
TouchingFaces mark_touching_faces(const world::ChunkMesh& mesh, std::span<const world::BlockId> ids,
                                  const world::BlockRegistry& registry, world::ChunkMesh& out);

} // namespace vx::render
