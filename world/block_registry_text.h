#pragma once
// A block table as text, for a store's "registry" meta: what each id means (name and material),
// so a world's blocks survive the trip through a store (import-vdb, then export-vdb) instead of
// coming back as the default palette.
//
// One line per id from 1: empty for an id not registered, else five tab-separated fields:
//   name, albedo "r g b", reflectivity, emission "r g b", opaque (0 or 1)
// Floats are written with 9 significant digits (float's round trip: exact). Names hold no
// control characters (BlockRegistry refuses them), so neither a tab nor a newline.
// Any thread.

#include <string>
#include <string_view>

#include "world/base/result.h"
#include "world/block_registry.h"

namespace vx::world {

std::string registry_to_text(const BlockRegistry& registry);

// The names alone, one per line for ids 1, 2, ... (a store's "blocks" meta: what the engine
// compares a game's block list with, so stored ids keep their meaning).
std::string registry_names_text(const BlockRegistry& registry);

// Errors: one line naming the line that is not five fields of the kinds above, or a name the
// registry refuses (empty, a duplicate).
Result<BlockRegistry> registry_from_text(std::string_view text);

} // namespace vx::world
