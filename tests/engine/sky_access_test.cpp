// engine::sky_access: the renderer's sky_access flag from the blocks around the camera.
#include <gtest/gtest.h>

#include "engine/sky_access.h"
#include "world/world.h"

namespace vx::engine {
namespace {

world::BlockId id_of(const world::World& w, const char* name) {
    const auto id = w.registry().find(name);
    EXPECT_TRUE(id.has_value()) << name;
    return id.value_or(1);
}

void fill(world::World& w, world::BlockPos lo, world::BlockPos hi, world::BlockId id) {
    for (int64_t z = lo.z; z < hi.z; ++z)
        for (int64_t y = lo.y; y < hi.y; ++y)
            for (int64_t x = lo.x; x < hi.x; ++x)
                w.set_block({x, y, z}, id);
}

// Solid stone [-40, 40) x [-100, 0) x [-40, 40) with a 9x5x9 cave hollowed out at y [-30, -25).
world::World cave_world() {
    world::World w;
    fill(w, {-40, -100, -40}, {40, 0, 40}, id_of(w, "stone"));
    fill(w, {-4, -30, -4}, {5, -25, 5}, world::kAir);
    return w;
}

TEST(SkyAccess, OpenGroundSeesTheSky) {
    world::World w;
    fill(w, {-40, -4, -40}, {40, 0, 40}, id_of(w, "stone"));
    EXPECT_TRUE(sky_access(w, {0, 1, 0}));
}

TEST(SkyAccess, NothingLoadedMeansTrue) {
    const world::World w;
    EXPECT_TRUE(sky_access(w, {0, -28, 0}));
}

TEST(SkyAccess, CaveBelowTheSurfaceIsSealed) {
    const world::World w = cave_world();
    EXPECT_FALSE(sky_access(w, {0, -28, 0}));
    EXPECT_FALSE(sky_access(w, {4, -26, -4}));
}

TEST(SkyAccess, ShaftToTheSurfaceOpensTheCave) {
    world::World w = cave_world();
    fill(w, {0, -25, 0}, {1, 0, 1}, world::kAir); // 1x1 shaft above the camera's column.
    EXPECT_TRUE(sky_access(w, {0, -28, 0}));
}

TEST(SkyAccess, TunnelToTheSideOpensTheCave) {
    world::World w = cave_world();
    fill(w, {4, -29, -1}, {40, -26, 2}, world::kAir); // 3x3 tunnel out through the +x face.
    EXPECT_TRUE(sky_access(w, {0, -28, 0}));
}

TEST(SkyAccess, GlassLetsTheSkyInWaterToo) {
    world::World w = cave_world();
    fill(w, {0, -25, 0}, {1, 0, 1}, id_of(w, "glass"));
    EXPECT_TRUE(sky_access(w, {0, -28, 0}));
    fill(w, {0, -25, 0}, {1, 0, 1}, id_of(w, "water"));
    EXPECT_TRUE(sky_access(w, {0, -28, 0}));
    fill(w, {0, -25, 0}, {1, 0, 1}, id_of(w, "dirt"));
    EXPECT_FALSE(sky_access(w, {0, -28, 0}));
}

TEST(SkyAccess, HugePocketCountsAsOpen) {
    // A sealed cave larger than the fill's budget: not proven sealed, so true (always correct).
    const world::World w = cave_world(); // 405 cells.
    EXPECT_FALSE(sky_access(w, {0, -28, 0}, 405));
    EXPECT_TRUE(sky_access(w, {0, -28, 0}, 404));
}

TEST(SkyAccess, UnderARoofWithOpenSidesSeesTheSky) {
    world::World w;
    fill(w, {-40, -4, -40}, {40, 0, 40}, id_of(w, "stone"));
    fill(w, {-3, 3, -3}, {4, 4, 4}, id_of(w, "wood")); // A roof on no walls.
    EXPECT_TRUE(sky_access(w, {0, 0, 0}));
}

TEST(SkyAccess, ClosedRoomAboveGroundIsSealed) {
    world::World w;
    fill(w, {-40, -4, -40}, {40, 0, 40}, id_of(w, "stone"));
    fill(w, {-3, 0, -3}, {4, 5, 4}, id_of(w, "wood"));
    fill(w, {-2, 0, -2}, {3, 4, 3}, world::kAir); // Walls, roof, floor: no opening.
    EXPECT_FALSE(sky_access(w, {0, 1, 0}));
    w.set_block({3, 1, 0}, id_of(w, "glass")); // A window.
    EXPECT_TRUE(sky_access(w, {0, 1, 0}));
}

// The cache answers as sky_access() does and computes again only when the eye's block or the
// world's change counter moved.
TEST(SkyAccessCache, RecomputesOnlyWhenTheEyeOrTheWorldMoves) {
    world::World w = cave_world();
    const world::BlockPos eye{0, -28, 0};
    SkyAccessCache cache;
    EXPECT_FALSE(cache.get(w, eye, 0));
    EXPECT_FALSE(cache.get(w, eye, 0));
    EXPECT_EQ(cache.computations(), 1u);
    EXPECT_FALSE(cache.get(w, eye + world::BlockPos(1, 0, 0), 0)); // Another block of the cave.
    EXPECT_EQ(cache.computations(), 2u);
    fill(w, {0, -25, 0}, {1, 0, 1}, world::kAir); // A shaft from the cave's roof to the surface.
    EXPECT_TRUE(cache.get(w, eye + world::BlockPos(1, 0, 0), 1));
    EXPECT_EQ(cache.computations(), 3u);
}

} // namespace
} // namespace vx::engine
