#pragma once
// The geometry section of `vx bench render`: naive, culled and greedy meshes of one
// scene side by side (triangles, CPU mesh time, BLAS build time and memory, trace times), and
// BLAS refits against rebuilds over k successive block edits (cost per edit burst and the trace
// time after k refits). Main thread only.

#include <cstdint>
#include <string>

#include "engine/scene_loader.h"
#include "render/renderer.h"

namespace vx::tools {

struct GeometryBenchInfo {
    render::DeviceChoice device{};
    render::RenderSettings base; // Size and lights; pipeline, mode and samples are set per row.
    render::Camera camera;
    uint32_t repeat = 5;         // Frames per timing (medians).
    uint32_t reflections = 5;    // Mirror bounces of the RT full rows.
    std::string out;             // Directory for geometry.csv.
};

// Meshes `scene` (its world and aprons) three ways and renders each on a fresh renderer; then
// edits `scene`'s world and meshes (a block toggled inside each non-empty chunk per step, the
// previous step's block restored) and restores them at the end. Returns the report's markdown
// ("## Geometry" with two tables) and writes info.out/geometry.csv. Prints each row.
std::string run_geometry_bench(engine::LoadedScene& scene, const GeometryBenchInfo& info);

} // namespace vx::tools
