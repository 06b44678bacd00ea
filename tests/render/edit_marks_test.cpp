// Edit marks (render/edit_marks.h): the boxes of blocks edited between two frames, merged past
// gpu::kMaxEditBoxes, written widened by kEditReach relative to the render origin. CPU only.
#include <gtest/gtest.h>

#include "render/edit_marks.h"

namespace vx::render {
namespace {

using world::BlockPos;

bool covers(const EditMarks& m, BlockPos p) {
    for (const EditMarks::Box& b : m.boxes())
        if (glm::all(glm::lessThanEqual(b.lo, p)) && glm::all(glm::lessThanEqual(p, b.hi)))
            return true;
    return false;
}

TEST(EditMarks, KeepsEachEditAndMergesTheNearestPastTheLimit) {
    EditMarks m;
    m.add({5, 5, 5}, {5, 5, 5});
    m.add({5, 5, 5}, {5, 5, 5}); // The same block again: nothing new.
    ASSERT_EQ(m.boxes().size(), 1u);
    // Far-apart single blocks up to the limit, each its own box.
    for (uint32_t i = 1; i < gpu::kMaxEditBoxes; ++i)
        m.add({int64_t(i) * 1000, 0, 0}, {int64_t(i) * 1000, 0, 0});
    ASSERT_EQ(m.boxes().size(), size_t(gpu::kMaxEditBoxes));
    // One more, next to the first: merged with it (the union grows least), not with a far one.
    m.add({7, 5, 5}, {7, 5, 5});
    ASSERT_EQ(m.boxes().size(), size_t(gpu::kMaxEditBoxes));
    EXPECT_EQ(m.boxes()[0].lo, BlockPos(5, 5, 5));
    EXPECT_EQ(m.boxes()[0].hi, BlockPos(7, 5, 5));
    // Every edited block is still covered, whatever merged.
    for (int i = 0; i < 40; ++i)
        m.add({int64_t(i) * 37 - 500, int64_t(i % 5) * 300, -int64_t(i) * 11}, {int64_t(i) * 37 - 500, int64_t(i % 5) * 300, -int64_t(i) * 11});
    EXPECT_LE(m.boxes().size(), size_t(gpu::kMaxEditBoxes));
    for (int i = 0; i < 40; ++i)
        EXPECT_TRUE(covers(m, {int64_t(i) * 37 - 500, int64_t(i % 5) * 300, -int64_t(i) * 11})) << i;
    for (uint32_t i = 1; i < gpu::kMaxEditBoxes; ++i)
        EXPECT_TRUE(covers(m, {int64_t(i) * 1000, 0, 0}));
    EXPECT_TRUE(covers(m, {5, 5, 5}));
    m.clear();
    EXPECT_TRUE(m.boxes().empty());
}

TEST(EditMarks, WritesBoxesWidenedByTheReachRelativeToTheOrigin) {
    EditMarks m;
    const BlockPos origin(int64_t(1) << 40, -64, 3); // Far from 0: 64-bit differences first.
    m.add(origin + BlockPos(2, 3, 4), origin + BlockPos(4, 3, 4));
    gpu::FrameParams p{};
    m.write(p, origin);
    ASSERT_EQ(p.edits.x, 1u);
    const float r = float(kEditReach);
    // Low corner: the first block's; high: the last block's far side (+1), each widened.
    EXPECT_EQ(glm::vec3(p.edit_boxes[0]), glm::vec3(2 - r, 3 - r, 4 - r));
    EXPECT_EQ(glm::vec3(p.edit_boxes[1]), glm::vec3(5 + r, 4 + r, 5 + r));
    m.clear();
    m.write(p, origin);
    EXPECT_EQ(p.edits.x, 0u);
}

} // namespace
} // namespace vx::render
