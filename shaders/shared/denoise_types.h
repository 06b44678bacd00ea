// Push constants of the denoiser's compute shaders (denoise_temporal.comp, denoise_atrous.comp),
// shared with render/denoiser.cpp. Made of 16-byte vectors so std430 and C++ agree;
// render/denoiser.cpp checks the size with static_assert.
#ifndef VX_SHADERS_DENOISE_TYPES_H
#define VX_SHADERS_DENOISE_TYPES_H

#include "glsl_types.h"
VX_GPU_BEGIN

// Threads per workgroup side (16 x 16). On lavapipe 8 x 8 made issue 18's denoised frame 0.6%
// dearer against 25 spp raw (medians of 6 runs of `vx render --versus-raw 25`; 32 x 32 and
// 8 x 32 were dearer too in noisier runs): docs/render_report.md, stop 67.
VX_CONST uint kDenoiseGroupSize = 16;

// flags (DenoisePush.params.w bits).
VX_CONST uint kDenoiseHistoryValid = 1u; // Temporal: the history images hold a previous frame.
VX_CONST uint kDenoiseLastPass = 2u;     // Remodulate by albedo into the outputs (the last pass).
VX_CONST uint kDenoiseHistoryClamp = 4u; // Temporal: clamp or drop history that left the fast one.
VX_CONST uint kDenoiseMirror = 8u;       // The mirror images are inputs (else not read).
VX_CONST uint kDenoiseKeepHistory = 16u; // Temporal: write the history (a next frame reads it).

// What the ray tracer hands the denoiser (render/gbuffer.h), in one place for both sides:
// a pixel's variance is its estimator's sample variance times kStratifiedVarianceScale (shaders/
// raygen.rgen: the sample variance over count overstates the variance of the mean of stratified
// samples; measured on lavapipe, terrain and mirror field at 4 and 16 spp, the denoiser's error
// was lowest with 1/16 of 1, 1/4, 1/16, 1/64), so the undiscounted variance is that over the
// scale; and the reflected image's alpha is kNoOccluder (blocks, exact in half float) where none
// of the primary hit's sky rays hit a block, a value the temporal pass's light footprint keeps.
VX_CONST float kStratifiedVarianceScale = 1.0f / 16.0f;
VX_CONST float kNoOccluder = 60000.0f;

// From this many shadow samples per pixel at the first hit (DenoisePush camera.w) a pixel's own
// light and variance are measured well enough to trust: the first a-trous pass compares with the
// centre, not its 3x3 blur (denoise_atrous.comp, prefiltered_luminance), and the luminance stop
// narrows (DenoiseSettings::sigma_luminance_many). Fewer: filtered as few (docs/render_report.md,
// stops 40-41).
VX_CONST float kDenoiseManySamples = 16.0f;

struct DenoisePush {
    // Temporal pass: maps (x d, y d, d, 1) of the current pixel centre (x, y) at view depth d to
    // (x' d', y' d', d', 1) of the previous frame's pixel (x', y') and view depth d'.
    // Identity for a still camera.
    mat4 reproject;
    // x: sigma_normal (exponent), y: sigma_depth, z: sigma_luminance, w: max history frames.
    vec4 sigmas;
    // x, y: image size in pixels; z: a-trous step in pixels (1, 2, 4, ...); w: flags.
    uvec4 params;
    // x: tan(vertical fov / 2), y: aspect (width / height) of the pinhole camera
    // (shaders/raygen.rgen): turns distances along primary rays into view depths. z: exposure
    // of the 8-bit output (vx_exposure_scale, tonemap.h). w: the first hit's shadow samples per
    // pixel (0: unknown, as a few).
    vec4 camera;
    // Temporal pass: the rotation (unit quaternion x, y, z, w) from world to the previous
    // frame's view space, whose pixels `reproject` maps to: turns world normals into that space
    // for the history's plane test (denoise_temporal.comp, history_taps).
    vec4 history_rotation;
};

VX_GPU_END

#endif
