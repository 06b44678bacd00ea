#include "world/raycast.h"

#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "world/world.h"

namespace vx::world {
namespace {

// ---- Exact reference: a slab test against every block, in rational arithmetic ----
// Test rays have origin anchor + O / kDen (integer O) and integer direction D, so every boundary
// crossing time (plane·kDen - O) / (kDen·D) is an exact rational. The reference applies the
// header's Simulation-of-Simplicity rule symbolically: a crossing on axis a carries the
// infinitesimal term -ε_a / D_a with ε_x ≫ ε_y ≫ ε_z, and δ·d shifts all times by -δ.

constexpr int64_t kDen = 1024;

struct Time {
    __int128 num = 0, den = 1; // den > 0.
    int axis = -1;             // Axis whose plane this is (for the ε term).
    int64_t dir = 0;           // D[axis].
};

// a < b in the perturbed order.
bool earlier(const Time& a, const Time& b) {
    const __int128 l = a.num * b.den, r = b.num * a.den;
    if (l != r)
        return l < r;
    if (a.axis == b.axis)
        return false;
    // The smaller axis index carries the dominant ε; its term -ε/D is negative when D > 0.
    return a.axis < b.axis ? a.dir > 0 : b.dir < 0;
}

Time crossing_time(int64_t plane, int64_t o, int64_t d, int axis) {
    Time t{__int128(plane) * kDen - o, __int128(kDen) * d, axis, d};
    if (t.den < 0) {
        t.num = -t.num;
        t.den = -t.den;
    }
    return t;
}

double to_double(const Time& t) { return double(t.num) / double(t.den); }

struct RationalRay {
    glm::i64vec3 o; // Origin offset numerators, relative to the anchor (units 1 / kDen).
    glm::i64vec3 d; // Integer direction.
};

// Entry/exit of block b (relative to the anchor); false when the ray's line misses it.
bool slab(const RationalRay& r, glm::i64vec3 b, Time& enter, Time& exit) {
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] == 0) {
            // Parallel: inside iff b ≤ o + ε < b + 1, i.e. b·kDen ≤ O < (b + 1)·kDen.
            if (!(b[a] * kDen <= r.o[a] && r.o[a] < (b[a] + 1) * kDen))
                return false;
            continue;
        }
        const Time in = crossing_time(r.d[a] > 0 ? b[a] : b[a] + 1, r.o[a], r.d[a], a);
        const Time out = crossing_time(r.d[a] > 0 ? b[a] + 1 : b[a], r.o[a], r.d[a], a);
        if (!any || earlier(enter, in))
            enter = in;
        if (!any || earlier(out, exit))
            exit = out;
        any = true;
    }
    return any && earlier(enter, exit) && exit.num > 0; // Exit at real 0 is before δ: behind.
}

using Scene = BlockId (*)(BlockPos);

// Sparse random blocks: about 12% solid, ids 1..5, a pure function of the position.
BlockId random_scene(BlockPos p) {
    uint64_t h = uint64_t(p.x) * 0x9E3779B97F4A7C15ull ^ uint64_t(p.y) * 0xC2B2AE3D27D4EB4Full ^
                 uint64_t(p.z) * 0x165667B19E3779F9ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return (h % 100) < 12 ? BlockId(1 + (h >> 40) % 5) : kAir;
}

// Reference raycast, plus `ambiguous` when the answer sits within rounding of max_distance.
RaycastHit reference(const RationalRay& r, BlockPos anchor, double max_distance, Scene scene, bool& ambiguous) {
    const glm::dvec3 d(r.d);
    const double len = glm::length(d);
    const double t_limit = max_distance / len;
    const glm::dvec3 o = glm::dvec3(r.o) / double(kDen);
    const glm::dvec3 e = o + d * t_limit;
    const glm::i64vec3 lo = glm::i64vec3(glm::floor(glm::min(o, e))) - int64_t(1);
    const glm::i64vec3 hi = glm::i64vec3(glm::floor(glm::max(o, e))) + int64_t(1);
    RaycastHit best;
    Time best_enter;
    ambiguous = false;
    for (int64_t z = lo.z; z <= hi.z; ++z)
        for (int64_t y = lo.y; y <= hi.y; ++y)
            for (int64_t x = lo.x; x <= hi.x; ++x) {
                const glm::i64vec3 b(x, y, z);
                Time in, out;
                const BlockId id = scene(anchor + b);
                if (id == kAir || !slab(r, b, in, out))
                    continue;
                const double t_in = std::max(0.0, to_double(in));
                if (std::abs(t_in - t_limit) < 1e-9 * std::max(1.0, t_limit))
                    ambiguous = true;
                if (t_in > t_limit || (best.hit && !earlier(in, best_enter)))
                    continue;
                best_enter = in;
                best.hit = true;
                best.inside = in.num <= 0; // Entry at or before the origin (real part ≤ 0 < δ).
                best.block = anchor + b;
                best.id = id;
                best.face = make_face(in.axis, in.dir < 0);
                best.distance = best.inside ? 0.0 : to_double(in) * len;
                best.previous = best.block + BlockPos(face_normal(best.face));
            }
    return best;
}

Ray to_ray(const RationalRay& r, BlockPos anchor) {
    return Ray{anchor, glm::dvec3(r.o) / double(kDen), glm::dvec3(r.d)};
}

::testing::AssertionResult same_hit(const RaycastHit& a, const RaycastHit& b, double tol) {
    if (a.hit != b.hit)
        return ::testing::AssertionFailure() << "hit " << a.hit << " vs " << b.hit;
    if (!a.hit)
        return ::testing::AssertionSuccess();
    if (a.inside != b.inside || a.block != b.block || a.id != b.id || a.face != b.face || a.previous != b.previous)
        return ::testing::AssertionFailure()
               << "block (" << a.block.x << "," << a.block.y << "," << a.block.z << ") face " << int(a.face)
               << " inside " << a.inside << " vs (" << b.block.x << "," << b.block.y << "," << b.block.z
               << ") face " << int(b.face) << " inside " << b.inside;
    if (!(std::abs(a.distance - b.distance) <= tol))
        return ::testing::AssertionFailure() << "distance " << a.distance << " vs " << b.distance;
    return ::testing::AssertionSuccess();
}

// Random rational rays; many start on planes, edges or corners and many have equal-magnitude or
// zero direction components, so ties are frequent.
RationalRay random_ray(std::mt19937_64& rng, int max_dir) {
    std::uniform_int_distribution<int64_t> pos(-3 * kDen, 3 * kDen);
    std::uniform_int_distribution<int> kind(0, 9);
    std::uniform_int_distribution<int64_t> dir(-max_dir, max_dir);
    RationalRay r;
    for (int a = 0; a < 3; ++a) {
        r.o[a] = pos(rng);
        const int k = kind(rng);
        if (k < 4)
            r.o[a] = r.o[a] / kDen * kDen; // On an integer plane.
        else if (k < 6)
            r.o[a] = r.o[a] / (kDen / 2) * (kDen / 2); // Half-way.
        r.d[a] = kind(rng) < 3 ? 0 : dir(rng);
    }
    if (r.d == glm::i64vec3(0))
        r.d.x = 1;
    if (kind(rng) < 3) // Equal magnitudes: 45° rays through edges and corners.
        for (int a = 1; a < 3; ++a)
            r.d[a] = r.d[a] == 0 ? 0 : (r.d[a] > 0 ? 1 : -1) * std::abs(r.d[0] == 0 ? 1 : r.d[0]);
    return r;
}

void compare_random(int max_dir, int count, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> dist(0.0, 9.0);
    int hits = 0, inside = 0, skipped = 0;
    for (int i = 0; i < count; ++i) {
        const RationalRay r = random_ray(rng, max_dir);
        const double max_d = dist(rng);
        bool ambiguous = false;
        const BlockPos anchor(-5, 17, 3);
        const RaycastHit want = reference(r, anchor, max_d, random_scene, ambiguous);
        if (ambiguous) {
            ++skipped;
            continue;
        }
        const RaycastHit got = raycast(to_ray(r, anchor), max_d, random_scene);
        ASSERT_TRUE(same_hit(got, want, 1e-12 * std::max(1.0, want.distance)))
            << "ray " << i << " o=(" << r.o.x << "," << r.o.y << "," << r.o.z << ")/" << kDen << " d=(" << r.d.x
            << "," << r.d.y << "," << r.d.z << ") max " << max_d;
        hits += got.hit;
        inside += got.inside;
    }
    // The scene and ray mix are fixed: most rays hit something, a few start inside, few skip.
    EXPECT_GT(hits, count / 3);
    EXPECT_GT(inside, 0);
    EXPECT_LT(skipped, count / 100 + 1);
}

TEST(Raycast, MatchesExactReferenceOnSmallDirections) { compare_random(2, 3000, 1); }
TEST(Raycast, MatchesExactReferenceOnGeneralDirections) { compare_random(64, 3000, 2); }

// ---- Hand-made edge, face and corner cases ----

struct BlockSet {
    std::set<std::tuple<int64_t, int64_t, int64_t>> solid;
    BlockId operator()(BlockPos p) const { return solid.count({p.x, p.y, p.z}) ? BlockId(1) : kAir; }
};

RaycastHit cast(const BlockSet& s, glm::dvec3 o, glm::dvec3 d, double max_d = 20.0) {
    return raycast(Ray::from_world(o, d), max_d, s);
}

TEST(Raycast, RayInFacePlaneBelongsToPositiveSide) {
    // Along the plane y = 0: the floor at y = -1 is grazed, never hit.
    BlockSet floor;
    for (int x = -10; x <= 10; ++x)
        floor.solid.insert({x, -1, 0});
    EXPECT_FALSE(cast(floor, {0.5, 0.0, 0.5}, {1, 0, 0}).hit);
    EXPECT_FALSE(cast(floor, {0.5, 0.0, 0.5}, {-1, 0, 0}).hit);
    // A block at y = 0 on the way is in the ray's row: entered through its -x face at 2.5.
    BlockSet row = floor;
    row.solid.insert({3, 0, 0});
    const RaycastHit h = cast(row, {0.5, 0.0, 0.5}, {1, 0, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, BlockPos(3, 0, 0));
    EXPECT_EQ(h.face, Face::NegX);
    EXPECT_EQ(h.distance, 2.5);
    EXPECT_EQ(h.previous, BlockPos(2, 0, 0));
}

TEST(Raycast, EdgeCrossingStepsPositiveAxesFirstInXyzOrder) {
    // From the centre of (0,0,0) along (1,1,0): the edge x = y = 1 at t = 0.5; x steps first.
    BlockSet s{{{1, 0, 0}}};
    RaycastHit h = cast(s, {0.5, 0.5, 0.5}, {1, 1, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, BlockPos(1, 0, 0));
    EXPECT_EQ(h.face, Face::NegX);
    EXPECT_DOUBLE_EQ(h.distance, 0.5 * std::sqrt(2.0));
    // (0,1,0) is only touched at the edge: not visited; (1,1,0) is entered from (1,0,0) through -y.
    s.solid = {{0, 1, 0}, {1, 1, 0}};
    h = cast(s, {0.5, 0.5, 0.5}, {1, 1, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, BlockPos(1, 1, 0));
    EXPECT_EQ(h.face, Face::NegY);
    EXPECT_EQ(h.previous, BlockPos(1, 0, 0));
}

TEST(Raycast, NegativeAxesStepInZyxOrderAfterPositiveOnes) {
    // Along (-1,-1,0): y steps before x, so (0,-1,0) is visited and (-1,0,0) is not.
    BlockSet s{{{-1, 0, 0}, {0, -1, 0}}};
    RaycastHit h = cast(s, {0.5, 0.5, 0.5}, {-1, -1, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, BlockPos(0, -1, 0));
    EXPECT_EQ(h.face, Face::PosY);
    // Corner along (1,-1,1): x, then z, then y.
    const BlockPos path[] = {{1, 0, 0}, {1, 0, 1}, {1, -1, 1}};
    const Face faces[] = {Face::NegX, Face::NegZ, Face::PosY};
    for (int i = 0; i < 3; ++i) {
        BlockSet one{{{path[i].x, path[i].y, path[i].z}}};
        h = cast(one, {0.5, 0.5, 0.5}, {1, -1, 1});
        ASSERT_TRUE(h.hit) << i;
        EXPECT_EQ(h.block, path[i]);
        EXPECT_EQ(h.face, faces[i]);
        EXPECT_DOUBLE_EQ(h.distance, 0.5 * std::sqrt(3.0));
    }
    // The other blocks at that corner are never visited.
    BlockSet others{{{0, -1, 0}, {0, 0, 1}, {0, -1, 1}, {1, -1, 0}}};
    h = cast(others, {0.5, 0.5, 0.5}, {1, -1, 1}, 0.9);
    EXPECT_FALSE(h.hit);
}

TEST(Raycast, OriginOnFaceBelongsToTheBlockAhead) {
    BlockSet s{{{0, 0, 0}}};
    // On the -x face of (0,0,0): pointing away it is outside, pointing in it is inside.
    EXPECT_FALSE(cast(s, {0.0, 0.5, 0.5}, {-1, 0, 0}).hit);
    RaycastHit h = cast(s, {0.0, 0.5, 0.5}, {1, 0, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_TRUE(h.inside);
    EXPECT_EQ(h.distance, 0.0);
    EXPECT_EQ(h.face, Face::NegX);
    EXPECT_EQ(h.previous, BlockPos(-1, 0, 0));
    // Same on the +x face of (-1,0,0), seen from the other side.
    BlockSet t{{{-1, 0, 0}}};
    h = cast(t, {0.0, 0.5, 0.5}, {-1, 0, 0});
    ASSERT_TRUE(h.hit);
    EXPECT_TRUE(h.inside);
    EXPECT_EQ(h.face, Face::PosX);
    EXPECT_EQ(h.previous, BlockPos(0, 0, 0));
    EXPECT_FALSE(cast(t, {0.0, 0.5, 0.5}, {1, 0, 0}).hit);
}

TEST(Raycast, InsideAtCentreReportsEntryFaceOfBackwardRay) {
    BlockSet s{{{4, 4, 4}}};
    // Centre of the block, direction (1, 2, 0.5): the backward ray leaves through y first (|d_y|
    // largest), so the forward ray entered through -y.
    const RaycastHit h = cast(s, {4.5, 4.5, 4.5}, {1, 2, 0.5});
    ASSERT_TRUE(h.hit);
    EXPECT_TRUE(h.inside);
    EXPECT_EQ(h.face, Face::NegY);
    EXPECT_EQ(h.previous, BlockPos(4, 3, 4));
}

TEST(Raycast, MaxDistanceIsInclusive) {
    BlockSet s{{{3, 0, 0}}};
    EXPECT_TRUE(cast(s, {0.5, 0.5, 0.5}, {1, 0, 0}, 2.5).hit);
    EXPECT_FALSE(cast(s, {0.5, 0.5, 0.5}, {1, 0, 0}, 2.4999).hit);
    EXPECT_FALSE(cast(s, {0.5, 0.5, 0.5}, {1, 0, 0}, -1.0).hit);
    // Non-normalized direction: distances stay in blocks.
    const RaycastHit h = cast(s, {0.5, 0.5, 0.5}, {8, 0, 0}, 2.5);
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.distance, 2.5);
    // Zero max distance still sees the origin's own block.
    BlockSet o{{{0, 0, 0}}};
    EXPECT_TRUE(cast(o, {0.5, 0.5, 0.5}, {0, 1, 0}, 0.0).inside);
    // Inclusive in the distance reported, not in direction units: a hit found again with its own
    // distance as the limit, never reported past the limit (the two rounded apart: about one hit
    // in seven was lost, and some reported 1 ulp past the limit).
    BlockSet diag{{{4, 0, 4}}};
    const RaycastHit far = cast(diag, {0.5, 0.5, 0.5}, {1, 0, 1});
    ASSERT_TRUE(far.hit);
    EXPECT_TRUE(cast(diag, {0.5, 0.5, 0.5}, {1, 0, 1}, far.distance).hit) << far.distance;
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int lost = 0, past = 0, hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Ray ray = Ray::from_world({u(rng) * 8, u(rng) * 8, u(rng) * 8}, {u(rng), u(rng), u(rng)});
        const double limit = 4.0 + 8.0 * (u(rng) + 1.0);
        const RaycastHit first = raycast(ray, limit, random_scene);
        if (!first.hit || first.inside)
            continue;
        ++hits;
        past += first.distance > limit;
        lost += !raycast(ray, first.distance, random_scene).hit;
    }
    EXPECT_GT(hits, 10000);
    EXPECT_EQ(lost, 0) << "of " << hits;
    EXPECT_EQ(past, 0) << "of " << hits;
}

// A direction component too small to scale keeps its sign: a ray from the plane y = 0 going
// down, however slightly, starts in the block below (the δ·d rule). (1, -5e-324, 0) lost the
// sign, ran along the plane and missed the floor.
TEST(Raycast, TinyComponentsKeepTheirSign) {
    BlockSet floor;
    for (int x = -2; x <= 12; ++x)
        floor.solid.insert({x, -1, 0});
    for (const glm::dvec3 d : {glm::dvec3(1, -5e-324, 0), glm::dvec3(1, -1e-323, 0), glm::dvec3(1e300, -1e-30, 0),
                               glm::dvec3(1, -1e-10, 0)}) {
        const RaycastHit h = cast(floor, {0.5, 0.0, 0.5}, d);
        ASSERT_TRUE(h.hit) << d.y;
        EXPECT_TRUE(h.inside) << d.y;
        EXPECT_EQ(h.block, BlockPos(0, -1, 0)) << d.y;
        EXPECT_NE(scaled_direction(d).y, 0.0) << d.y;
        EXPECT_LT(scaled_direction(d).y, 0.0) << d.y;
    }
    EXPECT_FALSE(cast(floor, {0.5, 0.0, 0.5}, {1, 0, 0}).hit); // Along the plane: grazed.
}

// Capture-less lambdas are queries as they are (they convert to a function pointer too, and the
// call needed two conversions: it did not compile); plain functions still are.
TEST(Raycast, CapturelessLambdasAndFunctionsAreQueries) {
    const Ray ray = Ray::from_world({0.5, 0.5, 0.5}, {1, 0, 0});
    const RaycastHit a = raycast(ray, 10.0, [](BlockPos p) -> BlockId { return p.x == 3 ? 1 : kAir; });
    ASSERT_TRUE(a.hit);
    EXPECT_EQ(a.block, BlockPos(3, 0, 0));
    EXPECT_TRUE(same_hit(raycast(ray, 10.0, random_scene), raycast(ray, 10.0, &random_scene), 0.0));
}

// A direction of any finite length is the same ray: 1e-200 and 1e200 long ones find the same
// block at the same distance as a unit one, and keep to max_distance. Their squared lengths
// underflowed (distance 0, no limit: a hit 1000 blocks away at distance 0, and the World walk never
// ended) or overflowed (every ray missed). An offset past 2^52 (no fraction, and a floor past the
// anchor's integers) is refused as a bad ray.
TEST(Raycast, DirectionsOfAnyLengthAreTheSameRay) {
    BlockSet s{{{3, 0, 0}, {1000, 0, 0}}};
    for (const double scale : {1e-300, 1e-200, 1.0, 1e200, 1e300}) {
        const RaycastHit h = cast(s, {0.5, 0.5, 0.5}, {scale, 0, 0}, 10.0);
        ASSERT_TRUE(h.hit) << scale;
        EXPECT_EQ(h.block, BlockPos(3, 0, 0)) << scale;
        EXPECT_NEAR(h.distance, 2.5, 1e-12) << scale;
        EXPECT_FALSE(cast(s, {0.5, 0.5, 0.5}, {scale, 0, 0}, 2.4).hit) << scale;
        const RaycastHit slant = cast(s, {0.5, 0.5, 0.5}, {scale, scale * 1e-3, 0}, 10.0);
        ASSERT_TRUE(slant.hit) << scale;
        EXPECT_NEAR(slant.distance, 2.5 * std::sqrt(1.0 + 1e-6), 1e-12) << scale;
    }
    World empty;
    Ray tiny;
    tiny.direction = {1e-200, 0, 0};
    EXPECT_FALSE(raycast(empty, tiny, 5.0).hit); // Returns: the walk ends at max_distance.
    EXPECT_FALSE(cast(s, {0x1p53, 0.5, 0.5}, {1, 0, 0}, 10.0).hit);
}

TEST(Raycast, NegativeCoordinatesAndZeroComponents) {
    BlockSet s{{{-7, -3, -12}}};
    const RaycastHit h = cast(s, {-6.75, -2.5, 0.25}, {0, 0, -1});
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, BlockPos(-7, -3, -12));
    EXPECT_EQ(h.face, Face::PosZ);
    EXPECT_EQ(h.distance, 11.25);
    EXPECT_EQ(h.previous, BlockPos(-7, -3, -11));
}

TEST(Raycast, FarOffsetsGiveIdenticalResults) {
    std::mt19937_64 rng(3);
    const BlockPos shifts[] = {{int64_t(1) << 24, -(int64_t(1) << 24), 7},
                               {int64_t(1) << 40, (int64_t(1) << 40) + 3, -(int64_t(1) << 40)},
                               {-(int64_t(1) << 40) - 1, 5, int64_t(1) << 40}};
    for (int i = 0; i < 500; ++i) {
        const RationalRay r = random_ray(rng, 16);
        const RaycastHit base = raycast(to_ray(r, BlockPos(0)), 8.0, random_scene);
        for (const BlockPos& shift : shifts) {
            auto moved = [&](BlockPos p) { return random_scene(p - shift); };
            RaycastHit got = raycast(to_ray(r, shift), 8.0, moved);
            got.block -= shift;
            got.previous -= shift;
            ASSERT_TRUE(same_hit(got, base, 0.0)) << i; // Bit-identical distance.
        }
    }
}

TEST(Raycast, OffsetOutsideUnitCubeIsFoldedIntoAnchor) {
    std::mt19937_64 rng(4);
    for (int i = 0; i < 200; ++i) {
        const RationalRay r = random_ray(rng, 8);
        Ray a = to_ray(r, BlockPos(100, -200, 300));
        Ray b = a;
        b.offset += glm::dvec3(-37.0, 12.0, 5.0);
        b.anchor -= BlockPos(-37, 12, 5);
        ASSERT_TRUE(same_hit(raycast(a, 6.0, random_scene), raycast(b, 6.0, random_scene), 0.0)) << i;
    }
}

TEST(Raycast, WorldOverloadMatchesCallback) {
    World world;
    std::mt19937_64 rng(5);
    std::uniform_int_distribution<int64_t> coord(-40, 40);
    for (int i = 0; i < 3000; ++i)
        world.set_block(BlockPos(coord(rng), coord(rng), coord(rng)), BlockId(1 + i % 4));
    auto query = [&](BlockPos p) { return world.get_block(p); };
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0;
    for (int i = 0; i < 500; ++i) {
        const Ray ray = Ray::from_world({u(rng) * 30, u(rng) * 30, u(rng) * 30}, {u(rng), u(rng), u(rng)});
        const RaycastHit a = raycast(world, ray, 60.0);
        ASSERT_TRUE(same_hit(a, raycast(ray, 60.0, query), 0.0)) << i;
        hits += a.hit;
    }
    EXPECT_GT(hits, 100);
}

// Past the world's edge is air: a ray leaving the world does not wrap round to the chunk at the
// other edge (32-bit chunk coordinates would), and a ray coming in from beyond hits what is there.
TEST(Raycast, BeyondTheWorldsEdgeIsAir) {
    World world;
    const BlockPos first(kWorldMinBlock, 0, 0), last(kWorldMaxBlock, 0, 5);
    world.set_block(first, 1); // Where a walk leaving at +x on row z = 0 would wrap to.
    world.set_block(last, 2);  // Where a walk leaving at -x on row z = 5 would wrap to.
    EXPECT_EQ(world.get_block(BlockPos(kWorldMaxBlock + 1, 0, 0)), kAir);
    EXPECT_EQ(world.get_block(BlockPos(kWorldMinBlock - 1, 0, 5)), kAir);
    Ray ray;
    ray.offset = {0.5, 0.5, 0.5};
    ray.anchor = BlockPos(kWorldMaxBlock - 3, 0, 0);
    ray.direction = {1.0, 0.0, 0.0};
    EXPECT_FALSE(raycast(world, ray, 64.0).hit);
    ray.anchor = BlockPos(kWorldMinBlock + 3, 0, 5);
    ray.direction = {-1.0, 0.0, 0.0};
    EXPECT_FALSE(raycast(world, ray, 64.0).hit);
    ray.anchor = BlockPos(kWorldMaxBlock + 40, 0, 5); // From outside, back in.
    const RaycastHit h = raycast(world, ray, 64.0);
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.block, last);
    EXPECT_EQ(h.id, 2);
}

// The walk ends where the ray leaves the world: past it all is air. A ray leaving with a limit of
// 1e12 blocks walked about 1.7 hours (6 ns a block); now it returns at once, and rays that never
// meet the world do not walk at all.
TEST(Raycast, TheWalkEndsAtTheWorldsEdge) {
    World world;
    Ray ray;
    ray.offset = {0.5, 0.5, 0.5};
    ray.anchor = BlockPos(kWorldMaxBlock - 3, 0, 0);
    ray.direction = {1.0, 0.25, 0.0};
    EXPECT_FALSE(raycast(world, ray, 1e12).hit);
    EXPECT_NEAR(clip_to_world(ray, 1e12), 4.5 * std::sqrt(1.0 + 1.0 / 16), 8.0);
    ray.direction = -ray.direction;
    world.set_block(BlockPos(kWorldMaxBlock - 1000, -249, 0), 3); // 996.5 to 997.5 back: y -248.6 to -248.9.
    const RaycastHit back = raycast(world, ray, 2000.0);
    ASSERT_TRUE(back.hit);
    EXPECT_EQ(back.block, BlockPos(kWorldMaxBlock - 1000, -249, 0));
    // Outside and pointing away, or beside the world and parallel to it: nothing to walk.
    Ray away = ray;
    away.anchor = BlockPos(kWorldMaxBlock + 100, 0, 0);
    away.direction = {1.0, 0.0, 0.0};
    EXPECT_LT(clip_to_world(away, 1e12), 0.0);
    EXPECT_FALSE(raycast(world, away, 1e12).hit);
    away.anchor = BlockPos(0, kWorldMinBlock - 10, 0);
    EXPECT_LT(clip_to_world(away, 1e12), 0.0);
    // Inside, the limit stands; anchors far past 2^53 still clip (their rounding is allowed for).
    EXPECT_EQ(clip_to_world(Ray::from_world({0.5, 0.5, 0.5}, {1, 2, 3}), 100.0), 100.0);
    Ray huge;
    huge.anchor = BlockPos(INT64_MAX - 5, 0, 0);
    huge.direction = {-1.0, 0.0, 0.0};
    const double to_edge = double(INT64_MAX) - double(kWorldMaxBlock);
    EXPECT_GT(clip_to_world(huge, 1e30), to_edge);
    EXPECT_LT(clip_to_world(huge, 1e30), to_edge + 2.0 * double(kWorldMaxBlock) + 1e5);
    EXPECT_TRUE(std::isnan(clip_to_world(huge, std::nan("")))); // raycast() refuses it.
}

} // namespace
} // namespace vx::world
