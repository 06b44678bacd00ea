#pragma once
// The ray tracer's outputs (the G-buffer): the interface a denoiser or raster pass reads.
//
// One set per frame slot (kFramesInFlight), sized like the frame, all in VK_IMAGE_LAYOUT_GENERAL
// after the trace, written by VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR with
// VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT (a reader adds its own barrier from there). Usage:
// STORAGE | SAMPLED | TRANSFER_SRC. Descriptor set 0 of the RT pipeline (render/rt_pipeline.h):
//
//   binding 1  output        RGBA8 (UNORM view)  what render()/present() return: Full mode
//                                                 vx_display(radiance, exposure); Flat and
//                                                 Visibility modes unchanged (linear albedo /
//                                                 visible fraction, no tone mapping)
//   binding 3  radiance      RGBA16F  linear HDR radiance of the pixel before tone mapping, rgb
//                                     (Flat and Visibility modes: the same values as the
//                                     output). a (Full mode): the variance of the luminance of
//                                     the primary hit's diffuse lighting (radiance - reflected)
//                                     divided by its albedo, as estimated from the pixel's light
//                                     samples (sample variance / samples, / 16 for their
//                                     stratification: shaders/raygen.rgen); 0 with shadows off
//                                     (no sampling), -1 at 1 sample (unknown); 1 in Flat mode.
//   binding 4  albedo        RGBA8 UNORM  linear albedo of the first visible (opaque) block hit
//                                     by the primary ray, rgb (no sRGB encoding), times the tint
//                                     of the see-through blocks it is seen through (Full mode: a
//                                     tint's edge stays sharp in the denoiser); the sky colour
//                                     (clamped to 0..1) on a miss; a = 1 on a hit, 0 on a miss,
//                                     gpu::kEditedAlpha on a hit near this frame's edits (render/
//                                     edit_marks.h: the denoiser starts its history again).
//   binding 5  normal_depth  RGBA16F  xyz: unit world-space normal of the face the primary ray
//                                     hit (axis-aligned); w: distance along the primary ray from
//                                     the eye to that hit, in blocks (> 0). A miss: (0, 0, 0, 0)
//                                     (w = 0 is the sentinel).
//   binding 6  reflected     RGBA16F  the part of radiance that is not the primary hit's diffuse
//                                     lighting, rgb: its emission plus the radiance from mirror
//                                     bounces and the haze's in-scattered light (the sky colour on
//                                     a miss) except the first mirror bounce's diffuse lighting
//                                     (bindings 7-9). a (Full mode): the primary hit's occluder
//                                     distance, the denoiser's guide to the scale of its light:
//                                     the harmonic mean distance in blocks (>= 0.25) of its sky
//                                     rays that hit a block (of the first face each ray's
//                                     traversal found, not always the nearest; the walk's hit
//                                     where that face is see-through); 60000 when none did; 0 when no sky
//                                     ray was traced and the sun is not blocked (shadows off, no
//                                     sky access away from emitters, a miss) and in frames the
//                                     denoiser does not run on (their sky rays are occlusion
//                                     rays, which measure no distance). Negative (the same
//                                     magnitude; -60000 without sky rays, -0 without a distance)
//                                     when the sun's shadow rays were traced and all were
//                                     blocked: a sun shadow. Flat mode: 0. The denoiser filters radiance -
//                                     reflected - mirror light x mirror albedo with the primary
//                                     hit's guides, the mirror light with bindings 8-9 as guides,
//                                     and adds this back unfiltered. Flat mode: 0.
//   binding 7  mirror_light  RGBA16F  the diffuse lighting of the surface the first mirror bounce
//                                     hit, over that surface's albedo (the mirror's reflectivity,
//                                     tint and haze included), rgb; a: its luminance variance as
//                                     in radiance.a (bounce_shadow_samples). 0 without such a hit.
//   binding 8  mirror_albedo RGBA8 UNORM  linear albedo of that surface, rgb; a = 1 (0: none;
//                                     gpu::kEditedAlpha: near this frame's edits, as albedo's).
//   binding 9  mirror_normal_depth RGBA16F  xyz: its unit world-space normal; w: the path's
//                                     length from the eye over the mirror to it, in blocks;
//                                     (0, 0, 0, 0) without such a hit (the primary hit is no
//                                     mirror, or the reflected ray missed). Flat mode: all 0.
//
// The tone-map step: today the last thing raygen does (it writes the output from radiance with
// vx_display: exposure, tone curve, sRGB; shaders/shared/tonemap.h). A denoiser that filters
// radiance writes the output itself with the same shared function, so both paths give the
// same bytes for the same radiance. Main thread only (GPU objects owned by the Renderer).

#include "render/vk_common.h"

namespace vx::render {

inline constexpr VkFormat kRadianceFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kAlbedoFormat = VK_FORMAT_R8G8B8A8_UNORM;
inline constexpr VkFormat kNormalDepthFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kReflectedFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kMirrorLightFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kMirrorAlbedoFormat = VK_FORMAT_R8G8B8A8_UNORM;
inline constexpr VkFormat kMirrorNormalDepthFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkImageUsageFlags kGBufferUsage =
    VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;

// Descriptor bindings of the RT pipeline's set 0.
enum RtBinding : uint32_t {
    kBindingTlas = 0,
    kBindingOutput = 1,
    kBindingParams = 2,
    kBindingRadiance = 3,
    kBindingAlbedo = 4,
    kBindingNormalDepth = 5,
    kBindingReflected = 6,
    kBindingMirrorLight = 7,
    kBindingMirrorAlbedo = 8,
    kBindingMirrorNormalDepth = 9,
};

} // namespace vx::render
