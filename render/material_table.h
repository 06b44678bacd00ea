#pragma once
// The GPU material table (shaders/shared/render_types.h's Material, indexed by block id), with
// what the shaders need per see-through block worked out once here rather than per ray: the
// absorption coefficient sigma = -ln(albedo) (a log per segment and per shadow-ray face) and the
// index of refraction (a square root and a divide per face the view crosses).
// Any thread (pure functions).

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "render/gpu_layouts.h"
#include "world/block_registry.h"

namespace vx::render {

// Below this albedo a see-through block counts as passing nothing within a block: sigma is capped
// at -ln(kMinPassAlbedo) per block (69), so albedo 0 stays finite and exp(-sigma d) still reaches 0.
inline constexpr float kMinPassAlbedo = 1e-30f;

// The index of refraction of a see-through block of normal-incidence reflectance r (0..1) against
// air, from ((n - 1) / (n + 1))^2 = r: water 0.02 gives 1.33, glass 0.04 gives 1.5, and r = 0 gives
// 1 (a block that only tints bends nothing). r is clamped to 0..0.999 (an index of at most ~3,800).
float refractive_index(float reflectivity);

// A see-through block's absorption coefficient per block of path, per channel: its albedo is the
// share one block's length of it passes, so d blocks pass albedo^d = exp(-sigma d) (Beer-Lambert;
// PBRT 4th ed., 11.1.1). 0 where albedo is 1; capped where albedo is below kMinPassAlbedo.
glm::vec3 absorption_coefficient(glm::vec3 albedo);

// One block type's GPU material: its albedo, reflectivity, emission, whether it is see-through
// (not opaque), and its optics (sigma, index) whatever its opacity (an opaque block's are unused).
gpu::Material gpu_material(const world::BlockInfo& info, bool opaque);

// The table for ids 0..count-1: each id's registry.info() (unregistered ids: the registry's
// generated opaque material), opacity from registry.is_opaque (air, id 0, never reaches a shader).
std::vector<gpu::Material> material_table(const world::BlockRegistry& registry, uint32_t count);

} // namespace vx::render
