#pragma once
// Which transparent faces of a chunk the ray tracer probes for a coincident face (coincident_tint
// in shaders/shared/raygen_common.glsl). Where two different transparent blocks touch (glass
// against water) each has its own face on the same plane and the traversal reports only one of
// them; a probe finds the other. It costs a ray per face crossed, so only faces that may have
// such a partner carry the mark (bit kQuadMayTouch of world::Quad::reserved, shaders/shared/
// render_types.h): inside the chunk, exactly the quads that overlap a face of a different
// transparent block on the same plane, facing the other way (a greedy quad is marked whole when
// part of it does); on the chunk's border planes, every transparent quad (the partner would be in
// the neighbour's mesh, which this chunk does not see). Any thread (pure function).

#include <span>
#include <vector>

#include "world/block_registry.h"
#include "world/mesh/chunk_mesh.h"

namespace vx::render {

// Writes `mesh` with the marks set into `out` and returns the blocks of the marked faces (each
// once); returns none (and leaves `out` alone) when no quad needs a mark, as in a chunk without
// transparent blocks or a lake's chunk away from its borders. `ids`: the blocks of the mesh's
// quads (any order, each once); a quad whose block is not among them counts as opaque. `mesh`
// carries no marks (as a mesher writes it).
std::vector<world::BlockId> mark_touching_faces(const world::ChunkMesh& mesh, std::span<const world::BlockId> ids,
                                                const world::BlockRegistry& registry, world::ChunkMesh& out);

} // namespace vx::render
