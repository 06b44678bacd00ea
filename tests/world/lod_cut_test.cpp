// The levels-of-detail cut (world/lod/lod_cut.h): every block within the view distance is covered
// by exactly one chunk of the target cut, the boxes nest, and the coarse chunks an engine keeps
// hold every parent a coarsening can need.
#include <gtest/gtest.h>

#include <unordered_set>

#include "world/lod/lod_cut.h"

namespace vx::world {
namespace {

using LodSet = std::unordered_set<LodCoord, LodCoordHash>;

LodViewSettings small_settings() {
    LodViewSettings s;
    s.radius0 = 3;
    s.vradius0 = 2;
    s.ring = 3;
    s.vertical_reach = 64;
    s.view_distance = 700;
    return s;
}

// The cut chunk covering block p, or none: walks p's ancestors.
int covers(const LodSet& cut, BlockPos p, int top) {
    int n = 0;
    for (int k = 0; k <= top; ++k)
        n += int(cut.contains(lod_chunk_of(p, k)));
    return n;
}

TEST(LodCut, EveryBlockInTheViewIsCoveredExactlyOnce) {
    for (const glm::dvec3 viewer : {glm::dvec3(0.5, 10.0, 0.5), glm::dvec3(-1000.3, -77.0, 523.9),
                                    glm::dvec3(31.99, 32.0, -32.01)}) {
        const LodView view(viewer, small_settings());
        ASSERT_GE(view.top_level(), 2) << "the test wants several coarse levels";
        std::vector<LodCoord> cut;
        view.cut(cut);
        const LodSet set(cut.begin(), cut.end());
        ASSERT_EQ(set.size(), cut.size()) << "a chunk listed twice";
        int levels_seen = 0;
        for (int k = 0; k <= view.top_level(); ++k)
            levels_seen += std::any_of(cut.begin(), cut.end(), [k](LodCoord c) { return c.level == k; });
        EXPECT_EQ(levels_seen, view.top_level() + 1);
        // Blocks on a grid through the view, at heights the coarse levels reach.
        const double d = double(small_settings().view_distance);
        int checked = 0;
        for (double x = -d; x <= d; x += 37.0)
            for (double z = -d; z <= d; z += 41.0)
                for (double y = -60.0; y <= 60.0; y += 29.0) {
                    if (std::hypot(x, z) > d - 1.0)
                        continue;
                    const BlockPos p(int64_t(std::floor(viewer.x + x)), int64_t(std::floor(viewer.y + y)),
                                     int64_t(std::floor(viewer.z + z)));
                    ASSERT_EQ(covers(set, p, view.top_level()), 1)
                        << "block " << p.x << "," << p.y << "," << p.z << " from viewer " << viewer.x;
                    ++checked;
                }
        EXPECT_GT(checked, 1000);
    }
}

TEST(LodCut, BoxesNestAndTheKeptChunksHoldEveryParent) {
    const LodView view(glm::dvec3(-5.5, 40.0, 17.25), small_settings());
    std::vector<LodCoord> kept;
    view.coarse_chunks(kept, 200.0);
    const LodSet set(kept.begin(), kept.end());
    for (int k = 0; k < view.top_level(); ++k) {
        const int h = view.half_width(k), v = view.half_height(k);
        for (int x = -h; x <= h; ++x)
            for (int z = -h; z <= h; ++z)
                for (int y = -v; y <= v; ++y) {
                    const LodCoord c{k, view.center(k) + ChunkCoord(x, y, z)};
                    ASSERT_TRUE(view.in_box(c));
                    const LodCoord parent = lod_parent(c);
                    ASSERT_TRUE(view.in_box(parent)) << "level " << k;
                    if (view.distance(parent) <= double(small_settings().view_distance) + 200.0) {
                        ASSERT_TRUE(set.contains(parent)) << "level " << k + 1 << " parent not kept";
                    }
                }
    }
    // Level-0 chunks are the streamer's, never in the coarse list.
    for (LodCoord c : kept)
        EXPECT_GE(c.level, 1);
}

TEST(LodCut, ShortViewDistanceIsFullDetailOnly) {
    LodViewSettings s = small_settings();
    s.view_distance = 3 * kChunkSize;
    const LodView view(glm::dvec3(0.0), s);
    EXPECT_EQ(view.top_level(), 0);
    std::vector<LodCoord> cut, kept;
    view.cut(cut);
    view.coarse_chunks(kept);
    EXPECT_TRUE(kept.empty());
    EXPECT_FALSE(cut.empty());
    for (LodCoord c : cut)
        EXPECT_EQ(c.level, 0);
    s.max_level = 0;
    s.view_distance = 4096;
    EXPECT_EQ(LodView(glm::dvec3(0.0), s).top_level(), 0) << "max_level caps the levels";
}

TEST(LodCut, DefaultsReach4096BlocksWithLevelFour) {
    LodViewSettings s;
    s.view_distance = 4096;
    const LodView view(glm::dvec3(100.0, 60.0, -300.0), s);
    EXPECT_EQ(view.top_level(), 4);
    std::vector<LodCoord> cut;
    view.cut(cut);
    double farthest = 0;
    for (LodCoord c : cut)
        farthest = std::max(farthest, view.distance(c));
    EXPECT_GT(farthest, 4096.0 - double(lod_chunk_blocks(4)));
    EXPECT_LE(farthest, 4096.0);
}

} // namespace
} // namespace vx::world
