// Player physics against small block worlds: gravity lands exactly on the floor, walls stop the
// box at their face, a one-block ledge can be jumped onto and a two-block wall cannot, nothing
// tunnels at high speed, and across thousands of random steps in a random world the box never
// ends inside a block. Also the view conventions of the replay's pose command.
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "player_physics.h"

using sandbox::MoveIntent;
using sandbox::Player;

namespace {

struct BlockWorld {
    std::set<std::tuple<int64_t, int64_t, int64_t>> solid;
    void add(int64_t x, int64_t y, int64_t z) { solid.insert({x, y, z}); }
    // A floor: the layer y = top - 1 over [-r, r]².
    void floor(int64_t top, int64_t r) {
        for (int64_t x = -r; x <= r; ++x)
            for (int64_t z = -r; z <= r; ++z)
                add(x, top - 1, z);
    }
    sandbox::SolidQuery query() const {
        return [this](vx::BlockPos p) { return solid.count({p.x, p.y, p.z}) > 0; };
    }
};

constexpr double kDt = 1.0 / 60.0;

Player walker(glm::dvec3 feet) {
    Player p;
    p.set_walking(true);
    p.set_feet(feet);
    return p;
}

} // namespace

TEST(PlayerPhysics, FallsOntoTheFloorAndStands) {
    BlockWorld w;
    w.floor(0, 4); // Top face at y = 0.
    Player p = walker({0.5, 5.25, 0.5});
    for (int i = 0; i < 120; ++i)
        p.step(kDt, {}, w.query());
    EXPECT_DOUBLE_EQ(p.feet().y, 0.0);
    EXPECT_TRUE(p.on_ground());
    EXPECT_FALSE(p.inside_solid(w.query()));
}

TEST(PlayerPhysics, WallStopsTheBoxAtItsFace) {
    BlockWorld w;
    w.floor(0, 8);
    for (int64_t y = 0; y < 3; ++y)
        for (int64_t z = -8; z <= 8; ++z)
            w.add(3, y, z); // Wall occupying x in [3, 4).
    Player p = walker({0.5, 0.0, 0.5});
    MoveIntent in;
    in.wish = {1, 0, 0};
    for (int i = 0; i < 120; ++i)
        p.step(kDt, in, w.query());
    EXPECT_DOUBLE_EQ(p.feet().x, 3.0 - 0.3); // Box max x on the wall's face.
    EXPECT_FALSE(p.inside_solid(w.query()));
    // Sliding along the wall still moves in z.
    in.wish = glm::normalize(glm::dvec3(1, 0, 1));
    const double z0 = p.feet().z;
    for (int i = 0; i < 30; ++i)
        p.step(kDt, in, w.query());
    EXPECT_GT(p.feet().z, z0 + 1.0);
    EXPECT_DOUBLE_EQ(p.feet().x, 2.7);
}

TEST(PlayerPhysics, JumpsOntoAOneBlockLedgeButNotATwoBlockWall) {
    BlockWorld w;
    w.floor(0, 8);
    for (int64_t x = 2; x <= 8; ++x)
        for (int64_t z = -8; z <= 8; ++z)
            w.add(x, 0, z); // Ledge: top at y = 1 for x >= 2.
    Player p = walker({0.5, 0.0, 0.5});
    MoveIntent in;
    in.wish = {1, 0, 0};
    in.jump = true;
    for (int i = 0; i < 90; ++i)
        p.step(kDt, in, w.query());
    EXPECT_GT(p.feet().x, 2.3);
    EXPECT_DOUBLE_EQ(p.feet().y, 1.0) << "did not land on the ledge";

    BlockWorld high;
    high.floor(0, 8);
    for (int64_t y = 0; y < 2; ++y)
        for (int64_t z = -8; z <= 8; ++z)
            high.add(2, y, z);
    Player q = walker({0.5, 0.0, 0.5});
    for (int i = 0; i < 90; ++i)
        q.step(kDt, in, high.query());
    EXPECT_LE(q.feet().x, 1.7);
    EXPECT_FALSE(q.inside_solid(high.query()));
}

TEST(PlayerPhysics, NoTunnellingAtHighSpeed) {
    BlockWorld w;
    w.add(0, 0, 0); // One block under the player, 1000 blocks down.
    Player p = walker({0.5, 1000.0, 0.5});
    for (int i = 0; i < 60 * 30; ++i)
        p.step(0.5, {}, w.query()); // Steps of up to 39 blocks at terminal speed.
    EXPECT_DOUBLE_EQ(p.feet().y, 1.0);
}

TEST(PlayerPhysics, NeverInsideABlockAcrossRandomPlay) {
    std::mt19937 rng(9);
    BlockWorld w;
    w.floor(0, 12);
    std::uniform_int_distribution<int> coord(-10, 10), height(0, 4), coin(0, 3);
    for (int i = 0; i < 400; ++i)
        w.add(coord(rng), height(rng), coord(rng));
    for (int64_t y = 0; y < 8; ++y) // A closed pen so nobody walks off the floor.
        for (int64_t i = -12; i <= 12; ++i) {
            w.add(i, y, -12);
            w.add(i, y, 12);
            w.add(-12, y, i);
            w.add(12, y, i);
        }
    Player p = walker({0.5, 7.0, 0.5});
    ASSERT_FALSE(p.inside_solid(w.query()));
    std::uniform_real_distribution<double> angle(0, 6.283185307179586);
    MoveIntent in;
    for (int i = 0; i < 6000; ++i) {
        if (i % 20 == 0) {
            const double a = angle(rng);
            in.wish = {std::cos(a), 0, std::sin(a)};
            in.jump = coin(rng) == 0;
        }
        p.step(kDt, in, w.query());
        ASSERT_FALSE(p.inside_solid(w.query())) << "step " << i << " at " << p.feet().x << " " << p.feet().y << " "
                                                << p.feet().z;
    }
}

TEST(PlayerPhysics, FlyIgnoresBlocksAndGravity) {
    BlockWorld w;
    w.floor(0, 4);
    Player p;
    p.set_feet({0.5, 3.0, 0.5});
    MoveIntent in;
    in.wish = {0, -1, 0};
    p.step(1.0, in, w.query());
    EXPECT_DOUBLE_EQ(p.feet().y, 3.0 - p.params().fly_speed);
}

TEST(PlayerPhysics, OverlapAndViewConventions) {
    Player p;
    p.set_feet({0.5, 10.0, 0.5}); // Box [0.2, 0.8] × [10, 11.8] × [0.2, 0.8].
    EXPECT_TRUE(p.overlaps_block({0, 10, 0}));
    EXPECT_TRUE(p.overlaps_block({0, 11, 0}));
    EXPECT_FALSE(p.overlaps_block({0, 12, 0}));
    EXPECT_FALSE(p.overlaps_block({0, 9, 0})); // Standing on it touches, no overlap.
    EXPECT_FALSE(p.overlaps_block({1, 10, 0}));
    EXPECT_DOUBLE_EQ(p.eye().y, 11.62);

    const glm::dvec3 f0 = sandbox::view_forward(0, 0), f90 = sandbox::view_forward(90, 0);
    EXPECT_NEAR(f0.z, -1, 1e-12);
    EXPECT_NEAR(f90.x, -1, 1e-12);
    EXPECT_NEAR(sandbox::view_forward(0, 90).y, 1, 1e-12);
    EXPECT_NEAR(sandbox::view_right(0).x, 1, 1e-12);
    EXPECT_NEAR(glm::dot(sandbox::view_right(90), f90), 0, 1e-12);
}
