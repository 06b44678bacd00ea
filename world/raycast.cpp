#include "world/raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "world/world.h"

namespace vx::world {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool is_finite(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Walk state in coordinates relative to the anchor. The start block is local (0,0,0) except
// where the origin lies on a plane the ray crosses backwards (see the δ·d rule in the header).
struct Walk {
    glm::dvec3 o;        // Origin offset in [0, 1).
    glm::dvec3 d;        // Direction.
    int64_t cell[3];     // Current block, relative to the anchor.
    int step[3];         // -1, 0 or +1 per axis.
    double t_next[3];    // Parameter (direction units) of the next boundary crossing per axis.
};

// Parameter of the boundary `plane` (relative to the anchor) on axis a. No accumulation: ties
// that are exact in real arithmetic stay exact whenever plane - o is exact (see header).
double crossing(const Walk& w, int a, int64_t plane) { return (double(plane) - w.o[a]) / w.d[a]; }

// The axis whose boundary the ray crosses first, ties broken in Simulation-of-Simplicity order:
// positive-direction axes by increasing index, then negative ones by decreasing index. Scanning
// x, y, z, a later axis b wins a tie exactly when the current best steps negatively.
int next_axis(const Walk& w) {
    int best = 0;
    for (int b = 1; b < 3; ++b) {
        if (w.t_next[b] < w.t_next[best] || (w.t_next[b] == w.t_next[best] && w.d[best] < 0))
            best = b;
    }
    return best;
}

// For an origin inside a solid block: the axis of the last boundary the ray's line crossed
// before the origin (the latest back crossing, in the same tie order).
int entry_axis_behind(const Walk& w) {
    double t_prev[3];
    for (int a = 0; a < 3; ++a)
        t_prev[a] = w.step[a] == 0 ? -kInf : crossing(w, a, w.cell[a] + (w.step[a] > 0 ? 0 : 1));
    int best = 0;
    for (int b = 1; b < 3; ++b) {
        if (t_prev[b] > t_prev[best] || (t_prev[b] == t_prev[best] && w.d[best] > 0))
            best = b;
    }
    return best;
}

Walk start_walk(glm::dvec3 o, glm::dvec3 d) {
    Walk w{};
    w.o = o;
    w.d = d;
    for (int a = 0; a < 3; ++a) {
        if (d[a] > 0) {
            w.step[a] = 1;
            w.cell[a] = 0;
            w.t_next[a] = crossing(w, a, 1);
        } else if (d[a] < 0) {
            w.step[a] = -1;
            w.cell[a] = o[a] == 0.0 ? -1 : 0; // On the plane, moving back: already in the block below.
            w.t_next[a] = crossing(w, a, w.cell[a]);
        } else {
            w.step[a] = 0;
            w.cell[a] = 0; // Parallel to the planes: the positive-side (floor) block.
            w.t_next[a] = kInf;
        }
    }
    return w;
}

RaycastHit make_hit(BlockPos block, BlockId id, int axis, int step, double distance) {
    RaycastHit h;
    h.hit = true;
    h.block = block;
    h.id = id;
    h.face = make_face(axis, step < 0); // Stepping +x enters through the block's -x face.
    h.distance = distance;
    h.previous = block + BlockPos(face_normal(h.face));
    return h;
}

} // namespace

Ray Ray::from_world(glm::dvec3 origin, glm::dvec3 direction) {
    const glm::dvec3 fl = glm::floor(origin);
    return Ray{BlockPos(fl), origin - fl, direction};
}

RaycastHit raycast(const Ray& ray, double max_distance, BlockQueryRef query) {
    VX_ASSERT_RETURN(is_finite(ray.direction) && is_finite(ray.offset), RaycastHit{});
    VX_ASSERT_RETURN(ray.direction != glm::dvec3(0.0), RaycastHit{});
    VX_ASSERT_RETURN(std::isfinite(max_distance), RaycastHit{});
    // Past 2^52 the offset has no fraction left, and its floor would not fit the anchor's integers.
    VX_ASSERT_RETURN(glm::all(glm::lessThan(glm::abs(ray.offset), glm::dvec3(0x1p52))), RaycastHit{});
    // Scaled by a power of two (exact): any finite length walks, and t * len stays the distance.
    const glm::dvec3 d = scaled_direction(ray.direction);
    if (!(max_distance >= 0.0))
        return {};
    // Fold the integer part of the offset into the anchor (both steps exact).
    const glm::dvec3 fl = glm::floor(ray.offset);
    const BlockPos anchor = ray.anchor + BlockPos(fl);
    Walk w = start_walk(ray.offset - fl, d);
    const double len = glm::length(d);

    auto block_at = [&] { return anchor + BlockPos(w.cell[0], w.cell[1], w.cell[2]); };
    BlockId id = query(block_at());
    if (id != kAir) {
        const int a = entry_axis_behind(w);
        RaycastHit h = make_hit(block_at(), id, a, w.step[a], 0.0);
        h.inside = true;
        return h;
    }
    for (;;) {
        const int a = next_axis(w);
        const double t = w.t_next[a];
        if (t == kInf || !(t * len <= max_distance)) // In the distance reported: inclusive exactly.
            return {};
        w.cell[a] += w.step[a];
        w.t_next[a] = crossing(w, a, w.cell[a] + (w.step[a] > 0 ? 1 : 0));
        id = query(block_at());
        if (id != kAir)
            return make_hit(block_at(), id, a, w.step[a], t * len);
    }
}

double clip_to_world(const Ray& ray, double max_distance) {
    if (!std::isfinite(max_distance))
        return max_distance; // raycast() refuses it, as documented.
    const glm::dvec3 u = unit_direction(ray.direction);
    double enter = 0.0, leave = max_distance;
    for (int a = 0; a < 3; ++a) {
        // The world's faces relative to the origin, widened by their rounding (anchors past 2^53).
        const double anchor = double(ray.anchor[a]);
        const double margin = 4.0 + std::abs(anchor) * 0x1p-50;
        const double lo = double(kWorldMinBlock) - anchor - ray.offset[a] - margin;
        const double hi = double(kWorldMaxBlock) + 1.0 - anchor - ray.offset[a] + margin;
        if (u[a] == 0.0) {
            if (lo > 0.0 || hi < 0.0)
                return -1.0; // Beside the world, parallel to it.
            continue;
        }
        const double t0 = lo / u[a], t1 = hi / u[a];
        enter = std::max(enter, std::min(t0, t1));
        leave = std::min(leave, std::max(t0, t1));
    }
    return leave < enter ? -1.0 : leave;
}

RaycastHit raycast(const World& world, const Ray& ray, double max_distance) {
    // One chunk lookup per chunk crossed instead of one per block.
    ChunkCoord cached_coord(0);
    const Chunk* cached = nullptr;
    bool valid = false;
    auto query = [&](BlockPos p) -> BlockId {
        if (!in_world(p)) // Beyond the edge is air (chunk_of would wrap to the far side).
            return kAir;
        const ChunkCoord c = chunk_of(p);
        if (!valid || c != cached_coord) {
            cached = world.find_chunk(c);
            cached_coord = c;
            valid = true;
        }
        return cached ? cached->get(local_of(p)) : kAir;
    };
    return raycast(ray, clip_to_world(ray, max_distance), query);
}

} // namespace vx::world
