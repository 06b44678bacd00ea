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

} // namespace vx::engine
