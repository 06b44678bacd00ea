#pragma once
// Scenes for `vx render`: a stored world, a generated terrain world around the camera, the
// thesis's seed scene, or a raw volume, loaded into a World and meshed (greedy). Also the CLI's
// 64-bit-safe parsing of world positions.
// Not thread-safe (meshing fans out internally and joins before returning).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "world/base/result.h"
#include "world/mesh/edit_mesher.h"
#include "world/world.h"

namespace vx::tools {

// A world position in block units: block + frac, frac in [0, 1) per axis. Parsed from decimal
// text as integer part and fraction separately, so it is exact for any block within the world
// (|coordinate| < 2^36) where a double would be exact only to 2^53 / (2^36 steps) ≈ 1e-5 blocks.
struct WorldPos {
    glm::i64vec3 block{0};
    glm::dvec3 frac{0.0};
};

// Parses "X,Y,Z" of decimals ("-12", "3.25", "-0.5"; no exponents). nullopt on anything else or
// outside the world.
std::optional<WorldPos> parse_world_pos(const std::string& s);
// a - b in blocks: the 64-bit block difference, then the fraction (exact while |a - b| < 2^53).
glm::dvec3 world_delta(const WorldPos& a, const WorldPos& b);
WorldPos world_pos_at(glm::dvec3 p); // For positions near the origin (defaults).

struct RenderSceneArgs {
    std::string world_path;            // --world
    std::optional<uint64_t> seed;      // --seed
    std::string scene;                 // --scene (only "seed")
    std::string scene_block = "stone"; // Block of the seed scene (by name).
    std::string raw, dims, type = "u8", origin = "0,0,0";
    int radius = -1;                   // Chunks around the camera (horizontal); -1: default.
    int vradius = 4;                   // Chunks around the camera (vertical).
    std::optional<WorldPos> eye;       // The camera if given (chooses the chunks of --seed/--world).
    unsigned threads = 0;              // 0: all cores.
};

struct RenderScene {
    std::unique_ptr<world::World> world;
    world::MeshMap meshes;            // Every meshed chunk, empty meshes included.
    bool isolated = false;            // Meshed with air aprons (the thesis's seed scene).
    std::string description;          // One line: what was loaded and how.
    glm::i64vec3 box_min{0}, box_max{0}; // Blocks covered by the meshed chunks, [min, max).
    std::optional<WorldPos> default_eye, default_target; // Scene-specific camera defaults.
    std::optional<std::pair<glm::i64vec3, glm::i64vec3>> volume_box; // Raw volumes: their exact box.
    double load_ms = 0, mesh_ms = 0;
    uint64_t triangles = 0;           // 2 per quad.
};

// Loads and meshes the scene that `args` names (exactly one source). Errors are one line.
Result<RenderScene> build_render_scene(const RenderSceneArgs& args);

// Remeshes chunk `c` of `scene` after an edit (its own apron, or air when isolated).
void remesh_chunk(RenderScene& scene, world::ChunkCoord c);

} // namespace vx::tools
