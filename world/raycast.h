#pragma once
// Voxel raycast: walks the blocks a ray passes through in order (Amanatides & Woo, "A Fast Voxel
// Traversal Algorithm for Ray Tracing", Eurographics 1987) and stops at the first non-air block.
//
// Precision: the origin is a 64-bit block position (anchor) plus a double offset. The walk runs
// in coordinates relative to the anchor, so a ray at 2^40 gives bit-identical results to the
// same ray at 0 (the anchor only enters through exact integer additions).
//
// Tie-breaking (exact rays along block faces, edges and corners). Blocks are half-open cubes
// [k, k+1). The ray is resolved as if its origin o were displaced to o + δ·d + (ε, ε², ε³) with
// infinitesimals δ ≫ ε > 0 (Simulation of Simplicity, Edelsbrunner & Mücke 1990). Consequences:
//   * A ray lying in a face plane belongs to the block on the plane's positive side: a ray along
//     y = 5 grazes the top of a solid at y = 4 without hitting it, but runs through blocks at y = 5.
//   * An origin exactly on a plane that the ray crosses belongs to the block the ray moves into
//     (the δ·d part): a ray starting on a block's face and pointing away does not start inside it.
//   * Passing exactly through an edge or corner, the ray steps one axis at a time (it always enters
//     a block through a face): first the axes with a positive direction in order x, y, z, then
//     the axes with a negative direction in order z, y, x.
// Crossing times are computed as (boundary - offset) / direction with no accumulation, so exact
// ties on rays with dyadic offsets (0, 0.5, 0.25, ...) and equal-magnitude or integer-ratio
// direction components are found exactly; for other rays a tie within rounding is broken by the
// same rule. Distances are along the normalized direction; the max distance is inclusive.

#include <cstdint>
#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "world/block_registry.h"
#include "world/coords.h"

namespace vx::world {

class World;

// A ray in world block coordinates: origin = anchor + offset, direction need not be normalized
// (it must be finite and not zero; any length, 1e-300 or 1e300, is the same ray, up to rounding). Keep |offset|
// small (say < 2^20) for full precision; the raycast folds its integer part into the anchor.
struct Ray {
    BlockPos anchor{0};
    glm::dvec3 offset{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};

    // A ray from a plain double world position (exact only where doubles are, |p| < 2^52).
    static Ray from_world(glm::dvec3 origin, glm::dvec3 direction);
};

struct RaycastHit {
    bool hit = false;
    // The origin was already inside a non-air block: distance is 0, `face` is the face through
    // which the ray's backward extension entered that block, `previous` the block behind it.
    bool inside = false;
    BlockPos block{0};         // World position of the hit block.
    BlockId id = kAir;         // Its id.
    Face face = Face::NegX;    // Face of `block` the ray entered through (its normal faces the ray).
    double distance = 0.0;     // Along the normalized ray, from the origin to the entry point, blocks.
    BlockPos previous{0};      // block + face_normal(face): where a placed block goes.
};

// A non-owning reference to any callable `BlockId(BlockPos)`: the block source (a World, a chunk
// snapshot, a generator). The callable must outlive the reference: pass lambdas straight to
// raycast(), never keep a BlockQueryRef made from a temporary.
class BlockQueryRef {
public:
    using Fn = BlockId (*)(BlockPos);

    // Any callable object, capture-less lambdas included (they convert to Fn too, but that
    // would take two conversions at the call); plain functions take the Fn overload.
    template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, BlockQueryRef> &&
                                                !std::is_function_v<std::remove_pointer_t<std::decay_t<F>>>>>
    BlockQueryRef(F&& f) // NOLINT: implicit on purpose, lambdas convert at the call.
        : m_ctx{const_cast<void*>(static_cast<const void*>(&f))},
          m_call([](Ctx ctx, BlockPos p) -> BlockId { return (*static_cast<std::remove_reference_t<F>*>(ctx.obj))(p); }) {}
    BlockQueryRef(Fn fn) // NOLINT: plain functions too.
        : m_call([](Ctx ctx, BlockPos p) -> BlockId { return ctx.fn(p); }) {
        m_ctx.fn = fn;
    }

    BlockId operator()(BlockPos p) const { return m_call(m_ctx, p); }

private:
    union Ctx {
        void* obj;
        Fn fn;
    };
    Ctx m_ctx;
    BlockId (*m_call)(Ctx, BlockPos);
};

// Finds the first non-air block within `max_distance` blocks (inclusive) along the ray; the
// origin's own block counts (then `inside` is set). To see through a block type (water, say),
// have the query return kAir for it. Returns hit = false for a zero or non-finite direction, a
// non-finite offset or max distance, an offset past 2^52 (these also log), or a negative max
// distance. Thread-safe if the query is.
RaycastHit raycast(const Ray& ray, double max_distance, BlockQueryRef query);

// The same on a World (chunks not present are air). The walk ends where the ray leaves the world
// (clip_to_world); a ray from outside walks the air up to the world's edge. Thread-safe for
// concurrent reads.
RaycastHit raycast(const World& world, const Ray& ray, double max_distance);

// `max_distance` cut to where the ray leaves the world's box (a few blocks past it, for rounding),
// or -1 if the ray meets no part of the box within it: past the edge everything is air, and a
// walk there could take hours (a max distance of 1e12 blocks). Any thread.
double clip_to_world(const Ray& ray, double max_distance);

} // namespace vx::world
