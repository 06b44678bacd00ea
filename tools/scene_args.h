#pragma once
// The CLI side of scenes: the scene options of `vx render` (and `vx mesh`), checked and turned
// into an engine::SceneLoadInfo; and the 64-bit-safe parsing of world positions. Loading and
// meshing are the engine's (engine/scene_loader.h).
// Not thread-safe (the CLI's one thread).

#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "engine/scene_loader.h"
#include "world/base/result.h"

namespace vx::tools {

using engine::WorldPos;
using engine::world_pos_at;

// Parses "X,Y,Z" of decimals ("-12", "3.25", "-0.5"; no exponents) as integer part and fraction
// separately, so it is exact for any block within the world (|coordinate| < 2^36) where a double
// would be exact only to 2^53 / (2^36 steps) ≈ 1e-5 blocks. nullopt on anything else or outside
// the world.
std::optional<WorldPos> parse_world_pos(const std::string& s);
// a - b in blocks: the 64-bit block difference, then the fraction (exact while |a - b| < 2^53).
glm::dvec3 world_delta(const WorldPos& a, const WorldPos& b);

struct SceneArgs {
    std::string world_path;            // --world
    std::optional<uint64_t> seed;      // --seed
    std::string scene;                 // --scene (only "seed")
    std::string scene_block = "stone"; // Block of the seed scene (by name).
    std::string raw, dims, type = "u8", origin = "0,0,0";
    int radius = -1;                   // Chunks around the camera (horizontal); -1: default.
    int vradius = 4;                   // Chunks around the camera (vertical).
    std::optional<WorldPos> eye;       // The camera if given (chooses the chunks of --seed/--world).
    unsigned threads = 0;              // 0: all cores.
    std::optional<int64_t> view_distance; // --view-distance, blocks (terrain); none: the radius box.
    std::string lod;                   // --lod on|off (needs --view-distance); empty: on.
    int lod_ring = 12;                 // --lod-ring: coarse levels' box half-width, chunks.
};

// Checks that exactly one scene is named and its options parse. Errors are one line.
Result<engine::SceneLoadInfo> scene_load_info(const SceneArgs& args);

} // namespace vx::tools
