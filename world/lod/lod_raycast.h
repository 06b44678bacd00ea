#pragma once
// CPU raycast through a levels-of-detail scene (issue 16): a set of chunks of any levels that
// overlap nowhere (a cut, lod_cut.h), each with its cells. A ray hits the first non-air cell of
// whichever scene chunk covers the point it is in; blocks no scene chunk covers are air.
//
// Why: the proof, on the CPU, that a LOD scene never lets a ray through where full detail would
// stop it (a coarse cell is non-air if any block under it is, downsample.h). The caster works on
// cells, not meshes, so it checks the data's conservativeness and the cut's coverage; the meshes
// add one thing it does not see: coarse chunks are meshed with an air apron (every border face
// drawn) and level-0 chunks with their real neighbours, so a face between a level-0 chunk and a
// coarser one is drawn from the coarse side at least, and a mesh is closed wherever the cells are.
//
// Method: the block walk of raycast() (Amanatides & Woo, same tie rules), each block answered by
// the covering chunk's cell (the last chunk found is cached, so a step is a box test and a cell
// read). Entering a level-k cell means crossing one of its faces, which is a block face, so a hit's
// distance is the ray's entry into the coarse cell exactly, as a per-level walk would give; the
// walk costs one step per block crossed, not per cell: a test oracle, not a renderer.
//
// Coordinates: world block units (lod_coords.h). Not thread-safe to build; raycast_lod() and the
// const queries are thread-safe on a scene no one modifies.

#include <unordered_map>
#include <unordered_set>

#include "world/chunk.h"
#include "world/lod/lod_coords.h"
#include "world/raycast.h"

namespace vx::world {

class LodScene {
public:
    // Adds chunk `c` (level 0..kMaxLodLevel) holding `cells`. Returns false, adding nothing, when
    // `c` overlaps a chunk already in the scene (equal, an ancestor or a descendant of it).
    bool add(LodCoord c, Chunk cells);

    // The chunk at exactly `c`, or null.
    const Chunk* find(LodCoord c) const;

    struct Covering {
        const Chunk* chunk = nullptr; // Null: no scene chunk holds the block.
        LodCoord coord{};             // The covering chunk, or (chunk null) the coarsest chunk
                                      // around the block that holds no scene chunk at all.
    };
    // The scene chunk holding block `p`: descends from the coarsest level, at most
    // max_level() + 1 lookups.
    Covering covering(BlockPos p) const;
    // The cell id at block `p` (kAir where no chunk covers it); `level` gets the covering level
    // (-1 when none) if not null.
    BlockId cell_at(BlockPos p, int* level = nullptr) const;

    int max_level() const { return m_max_level; }
    size_t size() const { return m_chunks.size(); }

private:
    std::unordered_map<LodCoord, Chunk, LodCoordHash> m_chunks;
    std::unordered_set<LodCoord, LodCoordHash> m_above; // Strict ancestors of every scene chunk.
    int m_max_level = 0;
};

struct LodRaycastHit {
    // As raycast(): `block` is the block through which the ray entered the hit cell (inside it),
    // `id` the cell's id, `distance` the ray's entry into the cell.
    RaycastHit hit;
    int level = -1;       // Level of the chunk hit (-1 on a miss).
    BlockPos cell{0};     // The hit cell's minimum block (its corner; the cell spans 2^level).
};

// The first non-air cell within `max_distance` blocks (inclusive) along `ray`; validation and
// the origin-inside case as raycast(). Thread-safe.
LodRaycastHit raycast_lod(const LodScene& scene, const Ray& ray, double max_distance);

} // namespace vx::world
