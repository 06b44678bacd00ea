// What both ray-generation shaders (raygen.rgen: full shading; raygen_flat.rgen: Flat) share:
// the descriptor bindings (render/rt_pipeline.h), the primary payload, the primary ray through a
// pixel's centre and the walk through transparent blocks. Include after rt_common.glsl.

#include "shared/tonemap.h"

layout(set = 0, binding = 0) uniform accelerationStructureEXT tlas;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D out_image;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D radiance_image;
layout(set = 0, binding = 4, rgba8) uniform writeonly image2D albedo_image;
layout(set = 0, binding = 5, rgba16f) uniform writeonly image2D normal_depth_image;
layout(set = 0, binding = 6, rgba16f) uniform writeonly image2D reflected_image;
layout(set = 0, binding = 7, rgba16f) uniform writeonly image2D mirror_light_image;
layout(set = 0, binding = 8, rgba8) uniform writeonly image2D mirror_albedo_image;
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2D mirror_normal_depth_image;

layout(location = 0) rayPayloadEXT HitPayload payload;
// The pipeline variant (render/rt_pipeline.h): false compiles trace_through's probe out, for frames
// where no two different transparent blocks touch (render/touching_pairs.h): its second trace call
// site cost every ray ~7% on the NVIDIA driver, probing or not (render_report.md).
layout(constant_id = 1) const bool kProbeTouching = true;
// False where no see-through block is drawn and the eye is in none (render/rt_pipeline.h,
// SeeThrough::kNone): every hit is opaque, and the walk, the tints and the surfaces compile out.
layout(constant_id = 2) const bool kSeeThrough = true;
const float kTMax = 1.0e7;

// The see-through check (render_types.h). g_check: this is its first dispatch (kCheckMark; set
// by main from the push constants), where every hit is opaque. g_met: a ray of the pixel met a
// see-through face. In that dispatch any ray (the walk, trace_shadow): the pixel is traced again
// with the see-through code. In the variant with that code the last walk alone (shade() counts the
// view ray's: kCheckCount).
bool g_check = false;
bool g_met = false;

vec3 face_normal(uint face) {
    face &= ~kFaceMayTouch;
    vec3 n = vec3(0.0);
    n[face >> 1u] = (face & 1u) != 0u ? 1.0 : -1.0;
    return n;
}

vec3 primary_dir(uvec2 px) {
    vec2 ndc = (vec2(px) + 0.5) / vec2(frame.size_samples.xy) * 2.0 - 1.0;
    float th = frame.camera_origin.w, aspect = frame.camera_forward.w;
    return normalize(frame.camera_forward.xyz + ndc.x * th * aspect * frame.camera_right.xyz -
                     ndc.y * th * frame.camera_up.xyz);
}

// The transparent block whose face is coincident with the one just crossed, where two different
// transparent blocks touch (glass against water: each block has its own face there, and the
// traversal reports only one of the two at the same distance); 0: none. A short probe from
// `through` back across the plane, culling the crossed face by its facing (a face is
// front-facing seen from its air side: render/tlas_instances.cpp), finds the other: the face of
// the same plane with the opposite normal (`face` ^ 1) and another block than the crossed face's
// `block` (the mesher writes no face between two blocks of one kind). Anything else it meets
// (near an edge, the faces the ray came through, a block of the same kind diagonally across the
// plane, met within rounding of a cell's edge) is not that face. `back` is the probe's reach, just
// past the plane. Traced only from faces that may have such a partner (kFaceMayTouch:
// render/touching_faces.h). Overwrites payload.
uint coincident_partner(vec3 through, vec3 dir, float back, uint face, uint block, bool entering) {
    uint cull = entering ? gl_RayFlagsCullBackFacingTrianglesEXT : gl_RayFlagsCullFrontFacingTrianglesEXT;
    traceRayEXT(tlas, gl_RayFlagsOpaqueEXT | cull, 0xFFu, 0u, 1u, kPrimaryMiss, through, 0.0, -dir, back,
                kPrimaryPayload);
    if (payload.t < 0.0 || (payload.face & ~kFaceMayTouch) != (face ^ 1u) || payload.block == block)
        return 0u;
    return vx_transparent(vx_material(payload.block)) ? payload.block : 0u;
}

// The see-through block the last trace_through() ended inside (0: none): a hit there lies in it
// (the mesher writes no face between a see-through block and an opaque one: a pond's water on its
// floor, glass on a wall), and the rays the hit sends out start in it.
uint g_inside = 0u;

// The see-through block the eye lies in (RenderSettings::eye_block), else 0. The primary ray
// starts in it.
uint eye_inside() {
    uint b = frame.edits.y;
    return kSeeThrough && b != 0u && vx_transparent(vx_material(b)) ? b : 0u;
}

// What a walk (trace_through) models: kWalkTint what the blocks' bodies absorb alone, the view
// bent at each face (Flat mode: albedo, no light); kWalkLight also the share each interface
// mirrors away (vx_interface_pass: against air or the touching block), the ray straight (sky
// rays from points in air, as shadow rays: shadow.rahit); kWalkEye the view bent at each face
// (Snell's law, between the two media's indices, vx_index), the share the interface mirrors and the
// radiance's n^2 law, and the mirroring face whose reflection weighs most (g_surface), which
// shade() may follow as it follows a mirror block; kWalkSun the sun's light traced back from a
// point inside a see-through block (sun_light in raygen.rgen): bent at each face as the view is,
// less the share each interface mirrors; the n^2 law is left to the caller (its irradiance's
// cosine ratio); kWalkSky a sky ray from a point inside a see-through block that bends light: as
// kWalkEye but for the kept surface (the sky reaches the point through Snell's window alone).
const uint kWalkTint = 0u, kWalkLight = 1u, kWalkEye = 2u, kWalkSun = 3u, kWalkSky = 4u;

// Of the faces of see-through blocks that mirror which the last kWalkEye walk met, the one whose
// reflection weighs most in the pixel (a pane's 4% against the lake behind it at a grazing angle:
// the lake's; the others' shares are dropped). `t` its distance from the walk's origin along the
// path (< 0: none), `position` on the side the ray came from (the reflected ray's origin),
// `face` as HitPayload's, `weight` the walk's tint up to it times the share it mirrors,
// `dir` the reflected direction and `inside` the see-through block the reflected ray starts in
// (0: air).
struct Surface {
    vec3 position;
    float t;
    vec3 weight;
    uint face;
    vec3 dir;
    uint inside;
};
Surface g_surface;

// The sun's direction (unit, in air) the last kWalkSun walk traces back to (sun_through in
// raygen.rgen). Once the walk leaves the blocks into air along another direction the way is dead:
// in air a ray no longer turns (faces of blocks it may yet cross come in parallel pairs, which
// shift it), so the walk stops there without tracing on to the sky.
vec3 g_sun_dir = vec3(0.0);

// Where the last kWalkSun walk first crossed into air: the face's axis (3: it never did) and a
// point on the face (camera-relative). light_through() in raygen.rgen finds a way's exit plane so.
uint g_exit_axis = 3u;
vec3 g_exit_at = vec3(0.0);

// Traces to the first opaque hit, passing through up to kMaxTransparentLayers transparent faces.
// The see-through blocks' bodies absorb along the path's segments in them (vx_absorb: where two
// transparent blocks touch, the probe says which the ray goes on in: coincident_partner); `kind`
// says what else the faces do (kWalkTint, kWalkLight, kWalkEye, kWalkSun above). payload holds that
// hit (t < 0: a miss), with t the whole path's length from `origin`; `dir` is a unit vector, on
// return the path's last direction. Past the critical angle (total internal reflection) the walk
// goes on along the reflection, all of the light's way. Returns what passes; g_inside says which
// block the hit lies in, `inside` the block the origin lies in (0: none). A miss inside a block
// (water to the loaded world's edge) is absorbed all the way. kWalkSun stops, all absorbed, where
// it leaves into air along another direction than g_sun_dir (payload.t then the path so far).
vec3 trace_through(vec3 origin, inout vec3 dir, uint inside, uint kind) {
    vec3 tint = vec3(1.0);
    float travelled = 0.0;
    g_inside = inside;
    if (kind == kWalkEye)
        g_surface.t = -1.0;
    g_exit_axis = 3u;
    for (uint layer = 0u;; ++layer) {
        traceRayEXT(tlas, gl_RayFlagsOpaqueEXT, 0xFFu, 0u, 1u, kPrimaryMiss, origin, 0.0, dir, kTMax, kPrimaryPayload);
        if (!kSeeThrough) {
            if (g_check && payload.t >= 0.0 && vx_transparent(vx_material(payload.block)))
                g_met = true;
            return tint;
        }
        if (g_inside != 0u) // The segment to this face (or to the end: a miss) runs in g_inside.
            tint *= vx_absorb(vx_material(g_inside), payload.t < 0.0 ? kTMax : payload.t);
        if (payload.t < 0.0)
            return tint;
        travelled += payload.t;
        Material m = vx_material(payload.block);
        g_met = g_met || vx_transparent(m);
        if (!vx_transparent(m) || layer >= kMaxTransparentLayers) {
            payload.t = travelled;
            if (vx_transparent(m)) // Stopped on a see-through face, shaded as a surface.
                g_inside = 0u;
            return tint;
        }
        // The face is front-facing (the ray enters its block) when the ray runs against its normal.
        uint face = payload.face & ~kFaceMayTouch, axis = face >> 1u, block = payload.block;
        bool entering = (dir[axis] > 0.0) != ((face & 1u) != 0u);
        vec3 at = payload.position, next = payload.through, hit = origin + dir * payload.t;
        uint from = g_inside, to = entering ? block : 0u; // The media on either side.
        uint partner = 0u;
        if (kProbeTouching && (payload.face & kFaceMayTouch) != 0u) {
            // From `next` back to the plane is next's offset along the axis over the ray's slope;
            // twice that (at least a little) reaches just past the plane and nothing much beyond.
            float to_plane = abs(next[axis] - hit[axis]) / max(abs(dir[axis]), 1e-6);
            partner = coincident_partner(next, dir, 2.0 * to_plane + 1e-4, face, block, entering);
            if (partner != 0u) {
                if (entering) // Out of the partner into this block, else out of this one into it.
                    from = partner;
                else
                    to = partner;
            }
        }
        g_inside = to;
        origin = next;
        float cos_i = abs(dir[axis]);
        if (kind == kWalkLight) { // Straight on; one share per interface, as a shadow ray's.
            bool paired = partner != 0u; // Else a face against air: its own share.
            tint *= paired ? vx_interface_pass(index_of(from), index_of(to), cos_i) : vx_face_pass(m, cos_i);
            continue;
        }
        float eta = index_of(to) / index_of(from); // n_t / n_i.
        vec3 n = face_normal(face);
        n = dot(dir, n) < 0.0 ? n : -n; // Against the ray.
        // The near side (the reflected ray's origin): the face's air side where the ray enters its
        // block (closest_hit.rchit's position), else just inside the block.
        vec3 near_side = entering ? at : vx_push_off_ulps(hit + n * kSurfaceOffset, axis, n[axis] > 0.0);
        vec3 bent = eta == 1.0 ? dir : refract(dir, n, 1.0 / eta);
        if (bent == vec3(0.0)) { // Total internal reflection: all of it mirrors, and the walk follows.
            dir = reflect(dir, n);
            origin = near_side;
            g_inside = from;
            continue;
        }
        float mirrored = kind == kWalkTint ? 0.0 : vx_fresnel_eta(cos_i, eta);
        if (kind == kWalkEye && mirrored > 0.0) {
            vec3 weight = tint * mirrored;
            if (g_surface.t < 0.0 || vx_luminance(weight) > vx_luminance(g_surface.weight))
                g_surface = Surface(near_side, travelled, weight, face, reflect(dir, n), from);
        }
        // Radiance across an interface scales by (n_near / n_far)^2 (PBRT 4th ed., 9.5.2): the
        // far side's light is squeezed into a wider or narrower cone of directions.
        if (kind == kWalkEye || kind == kWalkSky)
            tint *= (1.0 - mirrored) / (eta * eta);
        else if (kind == kWalkSun)
            tint *= 1.0 - mirrored;
        dir = normalize(bent);
        if (kind == kWalkSun && to == 0u && g_exit_axis == 3u) {
            g_exit_axis = axis;
            g_exit_at = at;
        }
        if (kind == kWalkSun && to == 0u && dot(dir, g_sun_dir) <= 1.0 - 1e-5) {
            payload.t = travelled; // Not a miss: the way does not count.
            return vec3(0.0);
        }
    }
}
