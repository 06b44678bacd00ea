// Declarations shared by the ray-tracing stages.
#extension GL_EXT_ray_tracing : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/render_types.h"
#include "shared/optics.glsl"

layout(set = 0, binding = 2, std140) uniform FrameBlock { FrameParams frame; };

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ChunkTable { uint64_t quads[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer QuadSlots { uvec2 slot[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Materials { Material m[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EmitterChunks { vec4 origin[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EmitterQuads { EmitterQuad q[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EmitterBounds { EmitterBound b[]; };

// An instance's quads: its chunk table entry (render/tlas_instances.cpp) is their address.
QuadSlots chunk_quads(uint instance) { return QuadSlots(ChunkTable(frame.chunk_table).quads[instance]); }

// HitPayload::face's bit 3: the hit quad's mark kQuadMayTouch (bits 0-2: the face).
const uint kFaceMayTouch = 8u;

// Primary/reflection ray result, written by the closest-hit shader.
struct HitPayload {
    vec3 position; // Camera-relative secondary-ray origin: on the face, offset to its air side.
    float t;       // Hit distance, < 0 on a miss.
    uint block;    // Block id.
    uint face;     // world::Face (axis * 2 + positive) | kFaceMayTouch.
    vec3 through;  // Origin to continue the ray past this face (its far side along the ray).
};

// Shadow ray result: visible is set by the shadow miss shader (nothing opaque in the way);
// transmittance is the product of what the transparent faces crossed pass (any-hit shader: each
// face's 1 - Fresnel); depth the optical depth their blocks' bodies add, sum over faces of
// +sigma t where the ray leaves a block, -sigma t where it enters one (any order: vx_absorb);
// last_t is the farthest of those faces' distances (< 0: none) and last_block its block if the
// ray enters the block there, else 0 (air): where the ray ends, inside a block or not. pending_t
// and pending_face hold up to kShadowPending faces marked kQuadMayTouch whose coincident partner
// has not been met yet (shadow.rahit: a pair passes its interface's share once); trace_shadow()
// gives those left unpaired their own share against air. pending_face: 0 (free) or
// kPendingUsed | block | axis << 16 | entering << 18.
const uint kShadowPending = 2u, kPendingUsed = 1u << 19u;
struct ShadowPayload {
    vec3 transmittance;
    uint visible;
    vec3 depth;
    float last_t;
    uint last_block;
    float pending_t[kShadowPending];
    uint pending_face[kShadowPending];
};

Material vx_material(uint block) {
    if (block < frame.mode_seed.z)
        return Materials(frame.materials).m[block];
    Material m;
    m.albedo_reflectivity = vec4(1.0, 0.0, 1.0, 0.0);
    m.emission = vec4(0.0);
    return m;
}

bool vx_transparent(Material m) { return m.emission.w > 0.5; }

// The share of light a see-through block's face mirrors, met from air at cosine cos_i to its
// normal, with the block's reflectivity r as its reflectance at normal incidence (vx_index); r = 0
// is a block that only tints. Shadow rays and sky rays from points in air are not bent (the
// sun's light and the sky rays at a point inside a block are: sun_through in raygen.rgen,
// kWalkSky), so for them a face lit from inside passes what it would from outside at that angle.
float vx_fresnel(float r, float cos_i) { return r <= 0.0 ? 0.0 : vx_fresnel_eta(cos_i, vx_index(r)); }

// What a see-through block's face passes of light crossing it at cosine cos_i to its normal:
// the share its surface does not mirror. The block's body absorbs apart (vx_absorb).
float vx_face_pass(Material m, float cos_i) { return 1.0 - vx_fresnel(m.albedo_reflectivity.w, cos_i); }

// What the interface between see-through media of indices n_a and n_b passes of light a straight
// (unbent) ray carries across it at cosine cos_i to its normal: 1 - F at the relative index
// n_high / n_low, the angle taken on the lower index's side, as vx_fresnel takes it on the air's.
// Where glass touches water one interface mirrors (0.4% head-on), not each face against air (6%).
float vx_interface_pass(float n_a, float n_b, float cos_i) {
    return 1.0 - vx_fresnel_eta(cos_i, max(n_a, n_b) / min(n_a, n_b));
}

// The index of refraction of see-through block b's medium, air's (1) for 0 (vx_index).
float index_of(uint b) { return b == 0u ? 1.0 : vx_index(vx_material(b).albedo_reflectivity.w); }

// A see-through block's absorption coefficient, per block of path: its albedo is the share of
// light one block's length of it passes (Beer-Lambert: albedo^d over d blocks; PBRT 4th ed.,
// 11.1.1), so sigma = -ln(albedo). Clamped: an albedo of 0 stops all light within a block.
vec3 vx_sigma(Material m) { return -log(max(m.albedo_reflectivity.xyz, vec3(1e-30))); }

// The optical depth of d blocks of path through see-through block m: sigma d, 0 where sigma is 0
// however far (no 0 x infinity); d may be a segment's length or a ray's whole reach (kTMax).
vec3 vx_depth(Material m, float d) {
    vec3 sigma = vx_sigma(m);
    return mix(sigma * d, vec3(0.0), equal(sigma, vec3(0.0)));
}

// What d blocks of path through see-through block m pass.
vec3 vx_absorb(Material m, float d) { return exp(-vx_depth(m, d)); }

// Moves p[axis] kOffsetUlps ulps towards + (positive) or - along that axis: a robust secondary-ray
// origin far from the camera, where the chunk-local kSurfaceOffset is lost in rounding
// (Waechter & Binder, Ray Tracing Gems ch. 6: integer steps of the float's bits).
vec3 vx_push_off_ulps(vec3 p, uint axis, bool positive) {
    float x = p[axis];
    if (abs(x) >= kOffsetUlpsFrom) {
        // The bits are sign and magnitude: adding grows |x|, so moving towards zero subtracts.
        int step = (x < 0.0) == positive ? -kOffsetUlps : kOffsetUlps;
        p[axis] = intBitsToFloat(floatBitsToInt(x) + step);
    }
    return p;
}
