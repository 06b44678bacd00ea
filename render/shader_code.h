#pragma once
// SPIR-V of the ray-tracing, raster and denoiser stages, compiled from shaders/ at build time and embedded in the
// library (so binaries work from any directory). Thread-safe (constant data).

#include <cstdint>
#include <span>

namespace vx::render::spirv {

std::span<const uint32_t> raygen();
std::span<const uint32_t> raygen_flat();
std::span<const uint32_t> primary_miss();
std::span<const uint32_t> shadow_miss();
std::span<const uint32_t> closest_hit();
std::span<const uint32_t> shadow_any_hit();
std::span<const uint32_t> denoise_temporal(); // Compute stages of render/denoiser.
std::span<const uint32_t> denoise_atrous();
std::span<const uint32_t> light_cache_resolve(); // render/light_cache.
std::span<const uint32_t> light_cache_gather();  // render/light_cache.
std::span<const uint32_t> raster_vert(); // The raster baseline (render/raster_pipeline).
std::span<const uint32_t> raster_frag();
std::span<const uint32_t> ui_vert(); // A game's 2D UI (render/ui_pass).
std::span<const uint32_t> ui_frag();

} // namespace vx::render::spirv
