// Push constants of the raster baseline (raster.vert, raster.frag), shared with
// render/raster_pipeline.cpp (which checks the size). 128 bytes: the guaranteed minimum.
#ifndef VX_SHADERS_RASTER_TYPES_H
#define VX_SHADERS_RASTER_TYPES_H

#include "glsl_types.h"
VX_GPU_BEGIN

// Positions are relative to the eye (the camera's block and its offset in it, subtracted in
// 64-bit on the CPU), in block units.
struct RasterPush {
    mat4 clip_from_eye;  // Projection * rotation (Vulkan clip space, y down, depth 0..1).
    vec4 chunk_origin;   // xyz: the chunk's origin (lod_origin) relative to the eye; w: its cell
                         // size in blocks (2^LOD level): the quads' chunk-local cell units scale by it.
    vec4 light_position; // xyz: the point light relative to the eye; w: shading mode (kMode*).
    vec4 light_power;    // xyz: intensity of the point light (linear RGB, per steradian);
                         // w: Full mode's exposure (radiance to tone-curve input,
                         // vx_exposure_scale in tonemap.h).
    uint64_t quads;      // Address of the chunk's Quad records (uvec2 per slot).
    uint64_t materials;  // Address of Material[] (render_types.h), indexed by block id.
};

VX_GPU_END
#endif
