#pragma once
// Moving whole worlds between a World in memory and an SqliteStore file, for the CLI.
// Not thread-safe (one thread, the CLI's).

#include <optional>
#include <string>

#include "world/base/result.h"
#include "world/world.h"

namespace vx::tools {

// Every stored chunk of the store at `path` (or those whose chunk lies in [lo, hi]).
Result<world::World> load_store_world(const std::string& path, std::optional<world::ChunkCoord> lo = {},
                                      std::optional<world::ChunkCoord> hi = {});

// Writes `world` as a new store at `path`, atomically: into a temporary beside it, flushed, then
// renamed over `path`. A failure leaves an existing `path` untouched. Prints progress to stderr.
Status save_store_world(const world::World& world, const std::string& path, const std::string& source);

} // namespace vx::tools
