#pragma once
// Reference meshers: one quad per face, written for clarity. They are comparison points for
// benchmarks and `vx mesh --mesher`, and oracles for the greedy mesher's tests; not part of the
// library a game links (target vx_mesh_reference, not installed).
//
// Same input, face rule and output layout as GreedyMesher (world/mesh/mesher.h). Thread-safe:
// no state.

#include <cstdint>

#include "world/mesh/mesher.h"

namespace vx::world {

// One quad per visible face.
void mesh_culled(const MesherInput& in, ChunkMesh& out);
// One quad per face of every non-air block, hidden or not.
void mesh_naive(const MesherInput& in, ChunkMesh& out);

// The classic per-slice greedy mesher (thesis listing 3.1, generalised to block ids and aprons):
// scalar and plain, the reference the bitmask mesher matches quad for quad.
void mesh_classic_greedy(const MesherInput& in, ChunkMesh& out);

enum class MesherKind : uint8_t { Greedy, Culled, Naive };
const char* mesher_name(MesherKind kind);

} // namespace vx::world
