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

// Whether `path` can take a new world (a PostgreSQL URI, a file or nothing yet; not a folder):
// checked before an import reads anything.
Status check_store_output(const std::string& path);

// Writes `world` as a new store at `path`, atomically: into a temporary beside it, flushed, then
// renamed over `path`. A failure leaves an existing `path` untouched and no temporary behind. Prints progress to stderr.
Status save_store_world(const world::World& world, const std::string& path, const std::string& source);

} // namespace vx::tools
