#version 460
#extension GL_GOOGLE_include_directive : require
// Nearest hit of a primary or reflection ray: looks up the quad of the hit triangle (two
// triangles per quad slot) and returns a robust secondary-ray origin: the hit point snapped onto
// the quad's integer face plane (chunk-local cell units, exact in float), clamped inside the quad,
// and offset by kSurfaceOffset along the face normal, then moved to origin-relative space by the
// instance's transform (gl_ObjectToWorldEXT: a level-k chunk's is scaled by 2^k) and pushed
// kOffsetUlps ulps further along the normal (far from the render origin the rounding of that move is
// larger than kSurfaceOffset). No tMin is needed: the origin is strictly on the air side of the
// face it left, also after the traversal moves it back into the instance's space. `through` is
// the same point on the face's other side along the ray: where a ray that passes a transparent
// face continues.
#include "shared/rt_common.glsl"

layout(location = 0) rayPayloadInEXT HitPayload payload;

void main() {
    QuadSlots quads = chunk_quads(gl_InstanceCustomIndexEXT);
    uvec2 q = quads.slot[gl_PrimitiveID >> 1];
    uint packed = q.x;
    uint u0 = packed & 31u, v0 = (packed >> 5u) & 31u;
    uint w = ((packed >> 10u) & 31u) + 1u, h = ((packed >> 15u) & 31u) + 1u;
    uint plane = (packed >> 20u) & 63u, axis = (packed >> 26u) & 3u;
    bool positive = ((packed >> 28u) & 1u) != 0u;
    // Plane axes as in world/chunk_mesh.h: X planes (y, z), Y planes (x, z), Z planes (x, y).
    uint ua = axis == 0u ? 1u : 0u;
    uint va = axis == 2u ? 1u : 2u;

    vec3 local = gl_ObjectRayOriginEXT + gl_ObjectRayDirectionEXT * gl_HitTEXT;
    local[ua] = clamp(local[ua], float(u0) + kSurfaceOffset, float(u0 + w) - kSurfaceOffset);
    local[va] = clamp(local[va], float(v0) + kSurfaceOffset, float(v0 + h) - kSurfaceOffset);
    vec3 far_side = local;
    bool ahead = gl_ObjectRayDirectionEXT[axis] > 0.0;
    local[axis] = float(plane) + (positive ? kSurfaceOffset : -kSurfaceOffset);
    far_side[axis] = float(plane) + (ahead ? kSurfaceOffset : -kSurfaceOffset);

    payload.position = vx_push_off_ulps(gl_ObjectToWorldEXT * vec4(local, 1.0), axis, positive);
    payload.through = vx_push_off_ulps(gl_ObjectToWorldEXT * vec4(far_side, 1.0), axis, ahead);
    payload.t = gl_HitTEXT;
    payload.block = q.y & 0xffffu;
    payload.face = axis * 2u + (positive ? 1u : 0u) + (((q.y >> 16u) & kQuadMayTouch) != 0u ? kFaceMayTouch : 0u);
}
