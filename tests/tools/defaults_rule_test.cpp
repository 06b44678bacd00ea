// The rule that picks the sandbox's defaults from measured curves (tools/defaults_rule.h): a
// candidate qualifies if its error is within 1.25x of the best error measured at up to twice its
// cost; the pick is the cheapest qualifying one.
#include <vector>

#include <gtest/gtest.h>

#include "defaults_rule.h"

namespace {

using vx::tools::apply_defaults_rule;
using vx::tools::CostError;

TEST(DefaultsRule, PicksTheCheapestWithinSlackOfTheBestAtTwiceTheCost) {
    const std::vector<CostError> c = {{1, 0.040}, {2, 0.020}, {4, 0.018}, {8, 0.017}};
    const auto r = apply_defaults_rule(c);
    // 1 ms: best at <= 2 ms is 0.020, and 0.040 > 1.25 * 0.020 = 0.025: out.
    // 2 ms: best at <= 4 ms is 0.018, 0.020 <= 0.0225: in. 4 ms: best at <= 8 ms is 0.017,
    // 0.018 <= 0.02125: in. 8 ms: the best of all is its own: in.
    EXPECT_EQ(r.best_within, (std::vector<double>{0.020, 0.018, 0.017, 0.017}));
    EXPECT_EQ(r.qualifies, (std::vector<bool>{false, true, true, true}));
    ASSERT_TRUE(r.pick);
    EXPECT_EQ(*r.pick, 1u);
}

TEST(DefaultsRule, OnlyCandidatesUpToTwiceTheCostCount) {
    // The 2.5 ms candidate is far better but costs more than twice 1 ms: the 1 ms one is compared
    // with itself alone, qualifies and, being cheapest, is the pick.
    const std::vector<CostError> c = {{2.5, 0.010}, {1, 0.030}};
    const auto r = apply_defaults_rule(c);
    EXPECT_EQ(r.best_within, (std::vector<double>{0.010, 0.030}));
    EXPECT_EQ(r.qualifies, (std::vector<bool>{true, true}));
    ASSERT_TRUE(r.pick);
    EXPECT_EQ(*r.pick, 1u);
}

TEST(DefaultsRule, BoundsAreInclusive) {
    // Exactly twice the cost is in the set and exactly 1.25x the error qualifies (1.25 and 1.0
    // are exact in binary); 1.26 does not.
    const auto at = apply_defaults_rule(std::vector<CostError>{{1, 1.25}, {2, 1.0}});
    EXPECT_EQ(at.best_within[0], 1.0);
    EXPECT_TRUE(at.qualifies[0]);
    EXPECT_EQ(*at.pick, 0u);
    const auto over = apply_defaults_rule(std::vector<CostError>{{1, 1.26}, {2, 1.0}});
    EXPECT_FALSE(over.qualifies[0]);
    EXPECT_EQ(*over.pick, 1u);
    // Just past twice the cost, the better candidate no longer counts.
    const auto past = apply_defaults_rule(std::vector<CostError>{{1, 1.26}, {2.001, 1.0}});
    EXPECT_TRUE(past.qualifies[0]);
    EXPECT_EQ(*past.pick, 0u);
}

TEST(DefaultsRule, EqualCostPicksTheLowerErrorAndTheFactorsApply) {
    const auto tie = apply_defaults_rule(std::vector<CostError>{{3, 0.02}, {3, 0.019}, {5, 0.03}});
    EXPECT_EQ(tie.qualifies, (std::vector<bool>{true, true, false}));
    EXPECT_EQ(*tie.pick, 1u);
    // A slack of 2: 0.040 <= 2 * 0.020 qualifies (with 1.25 it does not).
    const std::vector<CostError> slack = {{1, 0.040}, {2, 0.020}};
    EXPECT_FALSE(apply_defaults_rule(slack).qualifies[0]);
    EXPECT_TRUE(apply_defaults_rule(slack, 2.0).qualifies[0]);
    EXPECT_EQ(*apply_defaults_rule(slack, 2.0).pick, 0u);
    // A cost factor of 4 brings the 3 ms candidate into the 1 ms one's set: 0.030 > 1.25 * 0.010.
    const std::vector<CostError> factor = {{1, 0.030}, {3, 0.010}};
    EXPECT_TRUE(apply_defaults_rule(factor).qualifies[0]);
    EXPECT_FALSE(apply_defaults_rule(factor, 1.25, 4.0).qualifies[0]);
    EXPECT_EQ(*apply_defaults_rule(factor, 1.25, 4.0).pick, 1u);
}

TEST(DefaultsRule, NoCandidatesNoPick) {
    const auto r = apply_defaults_rule(std::vector<CostError>{});
    EXPECT_FALSE(r.pick);
    EXPECT_TRUE(r.qualifies.empty());
}

} // namespace
