// The one median() of the tools and benchmarks (world/base/median.h).
#include <vector>

#include <gtest/gtest.h>

#include "world/base/median.h"

namespace {

TEST(Median, OddEvenAndEmpty) {
    EXPECT_EQ(vx::median({3.0, 1.0, 2.0}), 2.0);
    EXPECT_EQ(vx::median({4.0, 1.0, 3.0, 2.0}), 2.5); // The mean of the middle two, 2 and 3.
    EXPECT_EQ(vx::median({7.0}), 7.0);
    EXPECT_EQ(vx::median({5.0, 5.0, 1.0, 9.0}), 5.0);
    EXPECT_EQ(vx::median({}), -1.0); // No samples: the callers' "no figure".
}

} // namespace
