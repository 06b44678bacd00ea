// The one vote of downsample() and the terrain's direct coarse levels (world/lod/cell_vote.h).
#include <initializer_list>
#include <utility>

#include <gtest/gtest.h>

#include "world/lod/cell_vote.h"

namespace {

using vx::world::BlockId;
using vx::world::CellVote;
using vx::world::kAir;

constexpr bool kOpaque = true, kClear = false;

// The winner of the votes (id, opaque), cast in order.
BlockId elect(std::initializer_list<std::pair<BlockId, bool>> votes) {
    CellVote ballot;
    for (auto [id, opaque] : votes)
        ballot.add(id, opaque);
    return ballot.winner();
}

TEST(CellVote, NoVotesAndAllAirGiveAir) {
    EXPECT_EQ(CellVote().winner(), kAir);
    EXPECT_EQ(elect({{kAir, kOpaque}, {kAir, kClear}, {kAir, kOpaque}, {kAir, kOpaque}}), kAir);
}

TEST(CellVote, AirAbstains) {
    // Water 2 of the 3 votes cast: see-through wins. Were the 5 air votes counted as opaque,
    // the class would go to sand.
    constexpr BlockId kSand = 4, kWater = 9;
    EXPECT_EQ(elect({{kWater, kClear}, {kAir, kOpaque}, {kWater, kClear}, {kAir, kOpaque}, {kSand, kOpaque},
                     {kAir, kOpaque}, {kAir, kClear}, {kAir, kOpaque}}),
              kWater);
}

TEST(CellVote, ClassTieGoesToOpaque) {
    // 2 see-through against 2 opaque: opaque, although water has the most votes of any id.
    constexpr BlockId kSand = 4, kGrass = 6, kWater = 9;
    EXPECT_EQ(elect({{kWater, kClear}, {kGrass, kOpaque}, {kWater, kClear}, {kSand, kOpaque}}), kSand);
    // With the smaller id see-through, the tie still goes to the opaque class.
    EXPECT_EQ(elect({{2, kClear}, {7, kOpaque}}), BlockId(7));
}

TEST(CellVote, ClassByMajorityThenPluralityWithin) {
    // A coast: water 3, land 4 split over grass 2, sand and dirt: land, then grass.
    constexpr BlockId kDirt = 2, kGrass = 3, kSand = 4, kWater = 9;
    EXPECT_EQ(elect({{kWater, kClear}, {kGrass, kOpaque}, {kWater, kClear}, {kSand, kOpaque}, {kWater, kClear},
                     {kDirt, kOpaque}, {kGrass, kOpaque}}),
              kGrass);
    // See-through 3 of 5: water (2) over glass (1), although stone has 2 votes and the smaller id.
    constexpr BlockId kStone = 1, kGlass = 8;
    EXPECT_EQ(elect({{kStone, kOpaque}, {kWater, kClear}, {kGlass, kClear}, {kStone, kOpaque}, {kWater, kClear}}),
              kWater);
}

TEST(CellVote, IdTieWithinClassGoesToTheSmallerId) {
    EXPECT_EQ(elect({{7, kOpaque}, {5, kOpaque}, {7, kOpaque}, {5, kOpaque}}), BlockId(5));
    EXPECT_EQ(elect({{5, kOpaque}, {7, kOpaque}, {5, kOpaque}, {7, kOpaque}}), BlockId(5));
    EXPECT_EQ(elect({{12, kClear}, {10, kClear}, {3, kOpaque}}), BlockId(10));
}

TEST(CellVote, HoldsEveryCandidate) {
    // kMaxCandidates distinct ids; the last one gets a second vote and wins.
    CellVote ballot;
    for (int i = 1; i <= CellVote::kMaxCandidates; ++i)
        ballot.add(BlockId(i), kOpaque);
    ballot.add(BlockId(CellVote::kMaxCandidates), kOpaque);
    EXPECT_EQ(ballot.winner(), BlockId(CellVote::kMaxCandidates));
}

} // namespace
