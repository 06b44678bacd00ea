// Layouts shared by the GLSL ray-tracing shaders and render/ (C++). Every struct is made of
// 16-byte vectors and 8-byte addresses so std140/std430 and C++ agree; render/gpu_layouts.h
// checks sizes and offsets with static_assert.
#ifndef VX_SHADERS_RENDER_TYPES_H
#define VX_SHADERS_RENDER_TYPES_H

#include "glsl_types.h"
VX_GPU_BEGIN

// Shading modes (FrameParams.mode_seed.x).
VX_CONST uint kModeFlat = 0;       // Albedo of the hit block, sky colour on a miss; no lighting.
VX_CONST uint kModeFull = 1;       // Sun, sky, area light, emitters, reflections; HDR, tone-mapped.
VX_CONST uint kModeVisibility = 2; // Fraction of unoccluded shadow samples at the primary hit.

// The ray generation's passes (TracePush). One dispatch traces whole paths (first_hit 0,
// last_hit kTraceToEnd), or several do (RenderSettings::split_hits): each shades the hits
// first_hit..last_hit of its paths, the next continuing the paths the last saved (a PathState
// each) and listed. The first hit's many coherent shadow rays then do not share the GPU with the
// bounces' scattered rays (H200: 25 first-hit samples cost 10.0 ms alone, 15.9 ms beside 5
// bounces; docs/render_report.md, stop 28), and a later pass runs only over the paths still
// going (a dense list: no warp waits on ended paths). The image is the same.
//
// The paths' buffer (TracePush.path_states), for P pixels: PathState[P]; two lists of live paths
// (uint pixel index each, P long), pass k appending to list k % 2; then kMaxSplitHits counters,
// counter k the length of pass k's list (zeroed before the first pass).
VX_CONST uint kTraceToEnd = 0xffffffffu;
VX_CONST uint kMaxSplitHits = 64;

// A frame whose chunks hold see-through blocks, the eye in none, may be traced in two dispatches
// (RenderSettings::see_through_check): first the variant without the see-through code (kSeeThrough
// false) over the image (kCheckMark), where a pixel any of whose rays meets a see-through face
// stores nothing and is marked instead; then the variant with it over the image again
// (kCheckMarked), where every pixel but the marked ones returns at once. A pixel none of whose
// rays meets one comes out the same either way, and the marked ones as from one dispatch with the
// see-through code: the image is that of one such dispatch, with that code run only where a ray
// needs it (it costs every ray of the terrain's view 10% on the H100, where few rays meet water:
// docs/render_report.md, stop 56). The marks are per pixel, not an appended list, so which pixels
// run together is the same each time: an appended list's order varies from run to run, and so did
// the NVIDIA driver's images of it. The buffer (TracePush.check_marks): a uint count of the
// marked pixels, a uint count of the pixels whose view ray's first walk met a see-through face,
// then a uint per pixel (x + width y), 1 where marked. Where many pixels' rays meet such faces
// the two dispatches cost more than one: such a frame traces in one with the see-through code
// (kCheckCount) and counts the view rays that met one (only those: a flag kept for every ray
// would cost that variant's rays), so the next frame can choose again
// (RenderSettings::see_through_check_share).
VX_CONST uint kCheckOff = 0;
VX_CONST uint kCheckMark = 1;
VX_CONST uint kCheckMarked = 2;
VX_CONST uint kCheckCount = 3;

// Push constants of the ray generation (raygen.rgen; the Flat one reads none).
struct TracePush {
    uint64_t path_states; // Address of PathState[width * height] (several passes), else 0.
    uint first_hit;       // The first hit this dispatch shades (0: the primary hit).
    uint last_hit;        // The last (kTraceToEnd: to the path's end); a path going on is saved.
    uint64_t check_marks;  // Address of the see-through check's count and marks, else 0.
    uint check;           // kCheckOff, kCheckMark, kCheckMarked or kCheckCount.
    uint pad;
};

// A path between two passes, at the bounce the next pass starts from (pixel x + width y).
struct PathState {
    vec4 origin_length;      // xyz: the bounce ray's origin (origin-relative blocks); w: path length so far.
    vec4 throughput;         // xyz: the path's throughput; w: the see-through block the origin lies in (uint bits; 0: none).
    vec4 direction_variance; // xyz: the bounce ray's unit direction; w: the primary hit's variance.
    vec4 radiance_occluder;  // xyz: radiance so far; w: the primary hit's occluder distance.
    vec4 reflected;          // xyz: the reflected part so far (render/gbuffer.h); w: 0.
};

// Ray payload locations and miss shader indices.
VX_CONST int kPrimaryPayload = 0;
VX_CONST int kShadowPayload = 1;
VX_CONST uint kPrimaryMiss = 0;
VX_CONST uint kShadowMiss = 1;

// Transparent (non-opaque registry) blocks a primary, reflection or sky ray passes through
// before it counts as blocked: deep water or a stack of glass panes ends there.
VX_CONST uint kMaxTransparentLayers = 8;

// Emissive blocks light points within this many cells of their chunk's box (farther, a lamp
// cell's light is under 1% of its emission: solid angle < 1/kEmitterRange^2; a cell of a level-k
// chunk is 2^k blocks, so is its reach). Sky rays look
// for emitters only at hits that near one of the kMaxEmitterChunks emissive chunks nearest the
// camera (FrameParams::emitter_chunks); farther emissive chunks light nothing.
VX_CONST float kEmitterRange = 16.0f;
VX_CONST uint kMaxEmitterChunks = 64;
// Emissive faces sampled directly (next-event estimation, shared/finite_light.glsl): the
// faces of the nearest emissive chunks, whole chunks only, up to this many per frame
// (render/emitter_quads.h). Sky rays no longer count the emission of those chunks' blocks.
VX_CONST uint kMaxEmitterQuads = 1024;
// Candidates per sample of the resampled choice among them (Talbot 2005; ReSTIR DI's first step).
VX_CONST uint kEmitterCandidates = 8;
// Cells per chunk edge (world::kChunkSize, checked in render/gpu_layouts.h), at every LOD level.
VX_CONST float kChunkCells = 32.0f;

// Secondary rays start this far off the hit's face plane, along the face normal, in chunk-local
// cell units (64 ulps at 32.0): blocks at level 0, 2^k / 1024 blocks for a level-k chunk drawn
// scaled by 2^k (world/lod/lod_coords.h), the same fraction of a cell at every level, as robust
// in the instance's own space. It survives the move to origin-relative space (positions relative
// to the render origin, which stays within 2^12 blocks of the camera: render/tlas_instances.h)
// only near the origin: at level 0 it is 32 ulps at 256 blocks and less than one beyond 8,192.
VX_CONST float kSurfaceOffset = 1.0f / 1024.0f;

// So the origin-relative ray origin is then also pushed this many ulps of its own normal component
// further along the normal (Waechter & Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6). Two suffice with round-to-nearest: rounding the
// instance transform loses at most half an ulp and each step is at least half an ulp (a step down
// across a power of two); four leave room for a driver's transform being a little less exact.
// At 2^20 blocks from the origin that is half a block, far below a pixel there.
VX_CONST int kOffsetUlps = 4;
// Below this magnitude the ulp push is skipped (it would cross zero) and kSurfaceOffset holds.
VX_CONST float kOffsetUlpsFrom = 1.0f / 32.0f;

// Edits the denoiser must not smooth over (render/edit_marks.h): at most this many boxes a frame.
VX_CONST uint kMaxEditBoxes = 8;
// The albedo image's alpha on a surface within a box (render/gbuffer.h): its history is stale.
VX_CONST float kEditedAlpha = 0.5f;

// Per-frame constants (uniform buffer, std140). Positions are relative to the render origin
// (the TLAS's, render/tlas_instances.h): world block position minus the origin's block
// (computed in 64-bit on the CPU), in block units.
struct FrameParams {
    vec4 camera_origin;  // xyz: camera position (its block - origin + offset in it); w: tan(vertical fov / 2).
    vec4 camera_forward; // xyz: unit view direction; w: aspect ratio (width / height).
    vec4 camera_right;   // xyz: unit, right in the image.
    vec4 camera_up;      // xyz: unit, up in the image.
    vec4 sky_color;      // xyz: linear RGB radiance of the sky (returned by missed rays).
    vec4 light_corner;   // xyz: one corner of the rectangular area light.
    vec4 light_edge_u;   // xyz: first edge from the corner.
    vec4 light_edge_v;   // xyz: second edge from the corner.
    vec4 light_emission; // xyz: radiance of the light (two-sided); 0: no area light.
    vec4 sun_direction;  // xyz: unit world direction towards the sun; w: cos(angular radius).
    vec4 sun_irradiance; // xyz: irradiance on a surface facing the sun (linear RGB); 0: no sun.
    vec4 sky_light;      // xyz: radiance of the sky seen by sky rays (0: no sky term); w: 0.
    uvec4 size_samples;  // width, height, shadow samples per pixel (first hit), max bounces.
    uvec4 mode_seed;     // mode, seed, material count, shadow samples on reflection bounces.
    uvec4 flags;         // x: 1 = trace sun and sky rays (0: skipped, sealed off from the sky);
                         // y: emitter_chunks entries (0..kMaxEmitterChunks);
                         // z: emitter_quads entries (0..kMaxEmitterQuads, 0: no direct sampling);
                         // w: how many of emitter_chunks (the first) have all their faces there.
    vec4 exposure;       // x: radiance to tone-curve input (vx_exposure_scale, tonemap.h);
                         // y: 1 = meter the frame into exposure_meter (auto exposure), 0: not;
                         // z: 1 = the denoiser runs: it writes the output image, which the trace
                         // (or the light cache's resolve) then leaves unwritten, and the trace
                         // finds its occluder guide (render/gbuffer.h); 0: the trace writes the
                         // output, and its sky rays are occlusion rays that measure no distance.
    vec4 haze;           // Aerial perspective (shared/haze.glsl), Full mode: x: extinction per
                         // block at and below the base height (0: no haze); y: its falloff per
                         // block above; z: the height of origin-relative y = 0 above the base
                         // height, blocks; w: 0.
    uvec4 cache;         // The light cache (shared/light_cache.glsl), Full mode: x: its
                         // table's cells (a power of two; 0: no cache); y: the mirror bounces
                         // cached after the primary hit (0..kMaxCachedBounces); z: a cell's width
                         // in pixels at the hit's distance (float bits); w: 0.
    uvec4 sampling;      // x: 1 = each hit's light samples by its weight in the pixel
                         // (RenderSettings::samples_by_weight: ceil(size_samples.z x weight^y),
                         // at least 1, in place of size_samples.z and mode_seed.w); y: the
                         // exponent (RenderSettings::weight_exponent, float bits); zw: 0.
    uvec4 edits;         // x: boxes in edit_boxes (0..kMaxEditBoxes); y: the block the eye lies in
                         // (RenderSettings::eye_block); zw: 0.
    vec4 edit_boxes[2 * kMaxEditBoxes]; // Box i: [2i].xyz its low corner, [2i + 1].xyz its high
                         // corner: blocks edited since the last frame, widened by their reach
                         // (render/edit_marks.h), origin-relative blocks.
    uint64_t chunk_table; // Address of uint64[instance]: each instance's Quad buffer address.
    uint64_t materials;   // Address of Material[material count], indexed by block id.
    uint64_t emitter_chunks; // Address of vec4[flags.y]: xyz chunk origin (origin-relative), w its
                             // edge in blocks (32 << LOD level).
    uint64_t exposure_meter; // Address of an ExposureMeter (exposure.y = 1), else 0.
    uint64_t emitter_quads;  // Address of EmitterQuad[flags.z].
    uint64_t emitter_bounds; // Address of EmitterBound[flags.w]: the first flags.w emitter chunks'.
    uint64_t cache_table;    // Address of the cache's uint keys[cache.x], vec4 values[cache.x], vec4 stats[cache.x].
    uint64_t cache_records;  // Address of uvec4[width * height * (cache.y + 1) * 2]: each pixel's records.
};

// The light cache (shared/light_cache.glsl, render/light_cache.h): the hits of one frame's paths
// share their light estimates through a hash table of surface cells.
VX_CONST uint kMaxCachedBounces = 8;     // Mirror bounces cached at most (deeper ones: not cached).
VX_CONST uint kCacheNoSlot = 0xffffffffu; // A record of no hit (or one not cached).
VX_CONST uint kCacheOwn = 0xfffffffeu;    // A hit whose cell found the table full: its own light.
VX_CONST uint kCacheProbes = 8;          // Linear probes before a hit gives up its cell.

// An emissive block face (a greedy quad: one rectangle of one block type), origin-relative
// blocks: the points corner + u edge_u + v edge_v, u, v in [0, 1]; it emits towards
// cross(edge_u, edge_v) (the face's outward normal) only.
struct EmitterQuad {
    vec4 corner;   // xyz; w: area, blocks^2.
    vec4 edge_u;   // xyz; w: 0.
    vec4 edge_v;   // xyz; w: 0.
    vec4 emission; // xyz: emitted radiance (the block's material); w: its luminance.
};

// The box around one emitter chunk's emissive faces (origin-relative blocks) and their power, for
// the cheap test of whether they could matter at a point (shared/raygen_emitters.glsl emitter_reach()).
struct EmitterBound {
    vec4 lo; // xyz: the box's low corner; w: sum over the faces of luminance x area (blocks^2).
    vec4 hi; // xyz: its high corner; w: 0.
};

// Auto exposure's metering, summed by raygen with atomics over Full-mode pixels whose x and y
// are multiples of kMeterStride and that some light reaches: log2 of the radiance's luminance,
// clamped to [kMeterLogMin, kMeterLogMax], minus kMeterLogMin, in 1/kMeterScale steps. The
// largest sum, a 4096 x 2160 frame at the brightest: 4096 * 2160 / 16 * 32 * 64 = 1.1e9 < 2^32.
struct ExposureMeter {
    uint log_sum; // Sum of the samples' fixed-point values.
    uint count;   // Samples.
};
VX_CONST uint kMeterStride = 4;
VX_CONST float kMeterLogMin = -20.0f; // log2 of radiance units (tonemap.h: 1 = 10^4 cd/m^2).
VX_CONST float kMeterLogMax = 12.0f;
VX_CONST float kMeterScale = 64.0f;

// One block type's material (std430 array element).
struct Material {
    vec4 albedo_reflectivity; // xyz: linear albedo; w: mirror reflectivity 0..1.
    vec4 emission;            // xyz: emitted radiance; w: 1 = transparent (registry opacity false).
};

// A quad slot of a chunk BLAS is world::Quad verbatim (uint packed, uint16 block, uint16 spare),
// read as a uvec2: x = packed (u0:5 v0:5 w-1:5 h-1:5 plane:6 axis:2 positive:1), y & 0xffff = block,
// y >> 16 = the spare, whose bit kQuadMayTouch the renderer sets (render/touching_faces.h).
VX_CONST uint kQuadMayTouch = 1; // A transparent face that may share its plane with another's.

VX_GPU_END
#endif
