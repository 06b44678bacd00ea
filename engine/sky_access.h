#pragma once
// Whether the camera can see the open sky, for render::RenderSettings::sky_access: the renderer
// skips every sun and sky ray when it is false, so false must mean "sealed off", never "maybe".
// Thread-safe for concurrent reads of the world (no writer at the same time).

#include <cstddef>
#include <cstdint>

#include "world/coords.h"
#include "world/world.h"

namespace vx::engine {

// How far up the eye's column is walked first, blocks: open to here (or to a chunk that is not
// loaded) means open sky, the common case above ground, decided in one walk.
inline constexpr int64_t kSkyColumnBlocks = 256;
// Cells the fill may visit before it gives up and answers true (about 1 ms at most).
inline constexpr size_t kSkyFillCells = 8192;

// False only when the eye's block (world blocks) lies in a pocket of non-opaque blocks that
// opaque blocks close off on every side (registry().is_opaque: glass, water and air let light
// through): a camera in a cave below its column's surface with no opening. Decided by walking
// up the eye's column, then by a flood fill of the pocket (6-connected) that answers true when it
// reaches a chunk that is not loaded, leaves the world, or visits more than max_cells cells
// (a pocket that large is treated as open: true is always correct, only slower).
bool sky_access(const world::World& world, world::BlockPos eye, size_t max_cells = kSkyFillCells);

// sky_access() for one camera frame after frame: the answer is kept while the eye stays in its
// block and the world is unchanged, so a camera standing in a cave does not flood-fill it every
// frame. `world_changes` is any counter that moves whenever blocks near the eye may have changed
// (the facade counts chunk loads, meshes and unloads). Main thread (one owner).
class SkyAccessCache {
public:
    bool get(const world::World& world, world::BlockPos eye, uint64_t world_changes);
    uint64_t computations() const { return m_computations; } // sky_access() calls so far.

private:
    world::BlockPos m_eye{0};
    uint64_t m_changes = 0;
    bool m_valid = false;
    bool m_open = true;
    uint64_t m_computations = 0;
};

} // namespace vx::engine
