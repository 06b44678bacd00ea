#pragma once
// Scenes loaded into a World and meshed through the engine's job system, for tools that need a
// whole region at once (`vx render`, `vx mesh`): a stored world, generated terrain around a
// camera, the thesis's seed scene, or a raw volume. Loads run on the job system's I/O lane,
// generation and meshing on its pool (engine/region_mesher.h). Terrain can also reach a view
// distance, with levels of detail (world/lod/) or at full detail (the reference LOD is measured
// against).
// Main thread of the JobSystem passed in; the calls block until the scene is ready (run_batch
// semantics, engine/job_batch.h: the system should have no other work meanwhile).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include <glm/glm.hpp>

#include "engine/job_system.h"
#include "engine/region_mesher.h"
#include "world/base/result.h"
#include "world/io/raw_volume.h"
#include "world/lod/lod_coords.h"
#include "world/mesh/edit_mesher.h"
#include "world/world.h"

namespace vx::render {
class Renderer;
}

namespace vx::engine {

// A world position in block units: block + frac, frac in [0, 1) per axis, so it stays exact for
// any block of the world (|coordinate| < 2^36) where a double alone would not. Plain value.
struct WorldPos {
    glm::i64vec3 block{0};
    glm::dvec3 frac{0.0};
};
// Thread-safe (pure). For positions near the origin (defaults): floor and fraction of `p`.
WorldPos world_pos_at(glm::dvec3 p);

enum class SceneKind {
    StoredWorld, // An SQLite store: every chunk, or those around the eye when large or --radius given.
    Terrain,     // Terrain of a seed, generated around the eye with a ring of neighbours for aprons.
    SeedScene,   // The thesis's 32x32-chunk scene, 10% random, chunks meshed in isolation.
    RawVolume,   // A raw block-id volume.
};

// What to load. Plain value (not thread-safe).
struct SceneLoadInfo {
    SceneKind kind = SceneKind::SeedScene;
    std::string world_path;             // StoredWorld: the store (opened read-only).
    uint64_t seed = 0;                  // Terrain: the seed.
    std::string seed_block = "stone";   // SeedScene: the block, by registry name.
    std::string raw_path;               // RawVolume: the file.
    world::RawVolumeDesc raw;           // RawVolume: dims, id type, origin.
    int radius = -1;                    // Chunks around the eye, horizontal; -1: default (8, or a
                                        // whole stored world of at most 20000 chunks). 0..64.
    int vradius = 4;                    // Chunks around the eye, vertical. 0..64.
    std::optional<WorldPos> eye;        // Chooses the chunks of Terrain/StoredWorld.
    ChunkMeshFn mesh_fn;                // Empty: greedy. See RegionMeshInfo.
    // Terrain to a view distance (issue 16): blocks, horizontal, from the eye; 0: only the box
    // of radius/vradius (above). 1..16384. With `lod`, the target cut of world::LodView
    // (lod_cut.h) to the view distance: its level-0 chunks (radius/vradius are level 0's box;
    // real aprons) and its coarse chunks (world::generate_lod, meshed with air aprons, so every
    // border face is drawn and seams between levels close). Without `lod`, the reference: every
    // level-0 chunk within the view distance (real aprons; radius unused). Both reach the
    // terrain's whole height (TerrainGenerator::height_min..max, and vradius around the eye).
    int64_t view_distance = 0;
    bool lod = true;
    int lod_ring = 12;                  // Coarse levels' box half-width (LodViewSettings::ring), 1..64.
};

// Chunks of one level of a loaded scene. Plain value.
struct LevelCounts {
    uint64_t chunks = 0;  // Meshed, empty ones included.
    uint64_t meshed = 0;  // Of them, with quads (a BLAS each once drawn).
    uint64_t quads = 0;
};

// A loaded, meshed scene. Not thread-safe (main thread).
struct LoadedScene {
    std::unique_ptr<world::World> world;
    world::MeshMap meshes;               // Every meshed chunk, empty meshes included.
    bool isolated = false;               // Meshed with air aprons (the seed scene).
    std::string description;             // One line: what was loaded and how.
    glm::i64vec3 box_min{0}, box_max{0}; // Blocks covered by the meshed chunks, [min, max).
    std::optional<WorldPos> default_eye, default_target; // Scene-specific camera defaults.
    // Raw volumes: their exact box. View-distance scenes: the view's (eye +- view distance,
    // the terrain's height range), the same with and without LOD, so both get the same light.
    std::optional<std::pair<glm::i64vec3, glm::i64vec3>> volume_box;
    // View-distance scenes with LOD: the coarse chunks (level >= 1) of the cut, each drawn at its
    // LodCoord (scaled by its cell size). Level 0 is `meshes`.
    std::unordered_map<world::LodCoord, world::ChunkMesh, world::LodCoordHash> coarse;
    int top_level = 0;                   // Coarsest level of a LOD scene (0: full detail only).
    std::array<LevelCounts, world::kMaxLodLevel + 1> levels{}; // By level; [0] counts `meshes`.
    double load_ms = 0, mesh_ms = 0;     // Wall times of loading (or generating) and meshing.
    double coarse_ms = 0;                // Generating and meshing the coarse chunks (LOD scenes).
    uint64_t quads = 0;                  // Every level's.
    uint64_t triangles = 0;              // 2 per quad.
};

// Main thread of `jobs`. Loads and meshes the scene `info` names. Errors are one line (unknown
// block, unreadable store or file, radius, view distance or ring out of range, a view distance
// for a scene other than terrain).
Result<LoadedScene> load_scene(JobSystem& jobs, const SceneLoadInfo& info);

// Main thread (the renderer's). Sends every chunk of `scene` that has quads to `renderer`: level 0
// and the coarse chunks, each at its LodCoord. Returns how many (a BLAS each once built).
uint32_t send_scene(const LoadedScene& scene, render::Renderer& renderer);

// Main thread. Remeshes chunk `c` of `scene` on this thread after an edit (its own apron, or air
// when isolated), with the mesher the scene was loaded with.
void remesh_chunk(LoadedScene& scene, world::ChunkCoord c, const ChunkMeshFn& mesh_fn = {});

} // namespace vx::engine
