#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The raster baseline draws a chunk straight from its quad records (vertex pulling): vertex
// 4k + c is corner c of slot k, indexed by the shared slot pattern (4k, 4k+1, 4k+2),
// (4k, 4k+2, 4k+3) as the BLASes are, decoded as closest_hit.rchit decodes a hit quad, so
// raster and ray tracer see the same geometry without a vertex buffer. Spare slots (block air)
// and back faces are placed outside the clip volume and drawn as nothing: a ray from outside the
// blocks meets an opaque block's front face first (the camera inside a block is the exception),
// and a see-through block's back face is where the ray leaves it, which the transparent pass's
// tint does not need (raster.frag). The pipeline's pass (kTransparentPass) keeps the faces of
// opaque blocks or those of transparent ones, the others culled so (render/raster_pipeline.h).

#include "shared/raster_types.h"
#include "shared/render_types.h"

layout(constant_id = 0) const bool kTransparentPass = false;
layout(push_constant) uniform Push { RasterPush pc; };
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer QuadSlots { uvec2 slot[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Materials { Material m[]; };

layout(location = 0) out vec3 v_position;    // Relative to the eye.
layout(location = 1) flat out uint v_block;
layout(location = 2) flat out uint v_face;   // axis * 2 + positive.
layout(location = 3) out vec3 v_local;       // Chunk-local, in cells: where in its cell a point lies.

void cull() {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    v_position = vec3(0);
    v_face = 0u;
    v_local = vec3(0);
}

void main() {
    const uvec2 q = QuadSlots(pc.quads).slot[uint(gl_VertexIndex) >> 2u];
    v_block = q.y & 0xffffu;
    if (v_block == 0u) { // A spare slot.
        cull();
        return;
    }
    const uint packed = q.x;
    // The face's plane relative to the eye: a +axis face is seen from the eye only when the
    // plane lies below it (eye - plane > 0), a -axis face when it lies above. Quads are in
    // chunk-local cells of chunk_origin.w blocks (a level-k chunk: 2^k).
    const float cell = pc.chunk_origin.w;
    const uint cull_axis = (packed >> 26u) & 3u;
    const float plane_rel = pc.chunk_origin[cull_axis] + cell * float((packed >> 20u) & 63u);
    const bool front = ((packed >> 28u) & 1u) != 0u ? plane_rel < 0.0 : plane_rel > 0.0;
    const bool transparent = Materials(pc.materials).m[v_block].emission.w != 0.0;
    if (transparent != kTransparentPass || !front) { // Another pass's, or a back face.
        cull();
        return;
    }
    const uint u0 = packed & 31u, v0 = (packed >> 5u) & 31u;
    const uint w = ((packed >> 10u) & 31u) + 1u, h = ((packed >> 15u) & 31u) + 1u;
    const uint plane = (packed >> 20u) & 63u, axis = (packed >> 26u) & 3u;
    const uint positive = (packed >> 28u) & 1u;
    const uint ua = axis == 0u ? 1u : 0u; // Plane axes as in world/chunk_mesh.h.
    const uint va = axis == 2u ? 1u : 2u;
    const uint corner = uint(gl_VertexIndex) & 3u;
    vec3 local;
    local[axis] = float(plane);
    local[ua] = float(u0 + ((corner == 1u || corner == 2u) ? w : 0u));
    local[va] = float(v0 + ((corner >= 2u) ? h : 0u));
    v_position = pc.chunk_origin.xyz + cell * local;
    v_local = local;
    v_face = axis * 2u + positive;
    gl_Position = pc.clip_from_eye * vec4(v_position, 1.0);
}
