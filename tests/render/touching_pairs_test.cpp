// Where two different transparent blocks touch across chunk borders (render/touching_pairs.h), at
// one level of detail and across levels; the border faces mark_touching_faces reports. No GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "scene_util.h"

#include "render/touching_pairs.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

constexpr int kN = world::kChunkSize;

// Border faces with one face of `block` on side `side`, cell (u, v).
BorderFaces one_face(int side, int u, int v, world::BlockId block) {
    BorderFaces faces;
    faces[size_t(side)].assign(size_t(kN) * kN, world::kAir);
    faces[size_t(side)][size_t(v * kN + u)] = block;
    return faces;
}

world::LodCoord at(int level, int x, int y, int z) { return {level, world::ChunkCoord(x, y, z)}; }

const world::BlockId kGlass = test::block_id("glass"), kWater = test::block_id("water");

// Two chunks of one level, side by side along x: a pair where their faces on the shared plane hold
// different blocks over one cell; none for faces at different cells, for the same block, or for
// faces on planes that are not shared; gone with either chunk, and as either changes.
TEST(TouchingPairsTest, NeighboursOfOneLevelTouchWhereTheirFacesMeetWithDifferentBlocks) {
    TouchingPairs pairs;
    pairs.set(at(0, 0, 0, 0), false, one_face(1, 9, 9, kWater)); // Its +x plane, x = 32.
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 1, 0, 0), false, one_face(0, 9, 10, kGlass)); // -x plane of the next: a cell apart.
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 1, 0, 0), false, one_face(0, 9, 9, kWater)); // The same cell, the same block.
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 1, 0, 0), false, one_face(1, 9, 9, kGlass)); // Its far plane, x = 64.
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 1, 0, 0), false, one_face(0, 9, 9, kGlass));
    EXPECT_TRUE(pairs.any());
    EXPECT_EQ(pairs.border_pairs(), 1u);
    pairs.set(at(0, 1, 0, 0), false, one_face(0, 9, 9, kGlass)); // Set again: still one pair.
    EXPECT_EQ(pairs.border_pairs(), 1u);
    pairs.set(at(0, 0, 0, 0), false, one_face(1, 9, 8, kWater)); // The water moves a cell.
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 0, 0, 0), false, one_face(1, 9, 9, kWater));
    EXPECT_TRUE(pairs.any());
    pairs.remove(at(0, 0, 0, 0));
    EXPECT_FALSE(pairs.any());
    EXPECT_EQ(pairs.chunks(), std::vector<world::LodCoord>{at(0, 1, 0, 0)});
    // Along y and z too, below zero (the -y plane of (0, 0, -1) is y = 0, shared with (0, -1, -1)).
    pairs.set(at(0, 0, 0, -1), false, one_face(2, 4, 7, kWater));
    pairs.set(at(0, 0, -1, -1), false, one_face(3, 4, 7, kGlass));
    EXPECT_EQ(pairs.border_pairs(), 1u);
    pairs.set(at(0, 0, -2, -1), false, one_face(4, 4, 7, kGlass)); // z planes of another chunk.
    pairs.set(at(0, 0, -2, -2), false, one_face(5, 4, 7, kWater));
    EXPECT_EQ(pairs.border_pairs(), 2u);
    pairs.clear();
    EXPECT_FALSE(pairs.any());
    pairs.set(at(0, 5, 5, 5), true, {}); // A pair inside a chunk.
    EXPECT_TRUE(pairs.any());
    EXPECT_EQ(pairs.chunks_with_inside_pairs(), 1u);
    pairs.set(at(0, 5, 5, 5), false, {});
    EXPECT_FALSE(pairs.any());
    EXPECT_TRUE(pairs.chunks().empty());
}

// A level-0 chunk beside a level-1 chunk, sharing the plane x = 0: the coarse cell (u, v) covers
// fine cells 2u, 2u + 1 (in blocks from the coarse chunk's corner). Found whichever comes first.
TEST(TouchingPairsTest, ChunksOfDifferentLevelsTouchWhereACoarseCellCoversAFineFace) {
    // Level-0 (0, 1, 0): y 32..63, z 0..31; its -x plane's cell (3, 5) is block y 35, z 5. The
    // level-1 chunk (-1, 0, 0) covers x -64..-1 and y, z 0..63: that block lies in its cell (17, 2).
    const world::LodCoord fine = at(0, 0, 1, 0), coarse = at(1, -1, 0, 0);
    for (bool coarse_first : {false, true}) {
        for (int u : {17, 16, 1}) {
            TouchingPairs pairs;
            const BorderFaces f = one_face(0, 3, 5, kWater), c = one_face(1, u, 2, kGlass);
            if (coarse_first)
                pairs.set(coarse, false, c);
            pairs.set(fine, false, f);
            if (!coarse_first)
                pairs.set(coarse, false, c);
            EXPECT_EQ(pairs.any(), u == 17) << "cell " << u << (coarse_first ? ", coarse first" : "");
        }
    }
    // Five levels apart: a level-5 cell is 32 blocks, one whole level-0 chunk's face.
    const world::LodCoord far_coarse = at(5, -1, 0, 0), small = at(0, 0, 10, 3);
    for (bool coarse_first : {false, true}) {
        for (int cell : {10, 11}) {
            TouchingPairs pairs;
            const BorderFaces f = one_face(0, 0, 0, kWater), c = one_face(1, cell, 3, kGlass);
            if (coarse_first)
                pairs.set(far_coarse, false, c);
            pairs.set(small, false, f);
            if (!coarse_first)
                pairs.set(far_coarse, false, c);
            EXPECT_EQ(pairs.any(), cell == 10) << "cell " << cell << (coarse_first ? ", coarse first" : "");
        }
    }
    // A coarse chunk whose border is not on the plane (it would straddle it) is no neighbour.
    TouchingPairs pairs;
    pairs.set(at(0, 1, 0, 0), false, one_face(0, 0, 0, kWater)); // -x plane at x = 32.
    pairs.set(at(1, 0, 0, 0), false, one_face(1, 0, 0, kGlass)); // +x plane at x = 64.
    EXPECT_FALSE(pairs.any());
}

// The border faces mark_touching_faces reports: each transparent face on a border plane at its
// cell, by block; nothing for opaque faces or faces inside the chunk.
TEST(TouchingPairsTest, BorderFacesHoldEachTransparentFaceOnABorderPlane) {
    world::World w;
    w.set_block({0, 5, 7}, kWater);                   // -x plane: u = y 5, v = z 7.
    w.set_block({4, 31, 6}, kGlass);                  // +y plane: u = x 4, v = z 6.
    w.set_block({3, 3, 0}, test::block_id("stone")); // Opaque: none.
    w.set_block({9, 9, 9}, kGlass);                   // Inside: none.
    const world::MeshMap meshes = test::mesh_world(w);
    const world::ChunkMesh& mesh = meshes.at(world::ChunkCoord(0, 0, 0)).mesh;
    world::ChunkMesh out;
    const TouchingFaces t =
        mark_touching_faces(mesh, mesh.block_ids(), world::BlockRegistry::default_registry(), out);
    EXPECT_TRUE(t.marked);
    EXPECT_FALSE(t.inside);
    for (int side = 0; side < 6; ++side) {
        const std::vector<world::BlockId>& cells = t.border[size_t(side)];
        if (side != 0 && side != 3) {
            EXPECT_TRUE(cells.empty()) << "side " << side;
            continue;
        }
        ASSERT_EQ(cells.size(), size_t(kN) * kN) << "side " << side;
        const size_t at_cell = side == 0 ? size_t(7 * kN + 5) : size_t(6 * kN + 4);
        EXPECT_EQ(cells[at_cell], side == 0 ? kWater : kGlass);
        EXPECT_EQ(std::count(cells.begin(), cells.end(), world::kAir), kN * kN - 1) << "side " << side;
    }
}

} // namespace
} // namespace vx::render
