// The equal-error search's pure parts (tools/equal_error_pick.h): the candidates, the skip rule
// and the cheapest candidate meeting a target.
#include <gtest/gtest.h>

#include "equal_error_pick.h"

namespace vx::tools {
namespace {

using C = EqualErrorCandidate;

// Without reflections: 6 spp x raw/denoised x light cache off/on, bounce spp 0. With: bounce spp
// {1, 2, 4, 8, 16, spp} up to spp, repeats dropped: 1 + 2 + 3 + 4 + 5 + 6 = 21 per denoiser and
// cache setting, then 10 by weight and 9 by weight^0.8, raw and denoised.
TEST(EqualErrorPick, Candidates) {
    const std::vector<C> shadows = equal_error_candidates(false);
    ASSERT_EQ(shadows.size(), 24u);
    for (const C& c : shadows)
        EXPECT_EQ(c.bounce_spp, 0u);
    const std::vector<C> both = equal_error_candidates(true);
    ASSERT_EQ(both.size(), 122u);
    std::vector<uint32_t> bounces_of_4, bounces_of_16, bounces_of_25;
    std::vector<uint32_t> by_weight, by_weight_08;
    for (const C& c : both) {
        EXPECT_FALSE(c.light_cache && c.by_weight);
        if (c.by_weight) {
            EXPECT_EQ(c.bounce_spp, 0u);
            EXPECT_TRUE(c.weight_exponent == 1.f || c.weight_exponent == 0.8f) << c.weight_exponent;
            if (!c.denoise)
                (c.weight_exponent == 1.f ? by_weight : by_weight_08).push_back(c.spp);
            continue;
        }
        EXPECT_EQ(c.weight_exponent, 1.f);
        EXPECT_LE(c.bounce_spp, c.spp);
        EXPECT_GE(c.bounce_spp, 1u);
        EXPECT_LT(c.frame_ms, 0.0); // Unmeasured.
        if (!c.denoise && !c.light_cache && c.spp == 4)
            bounces_of_4.push_back(c.bounce_spp);
        if (!c.denoise && !c.light_cache && c.spp == 16)
            bounces_of_16.push_back(c.bounce_spp);
        if (!c.denoise && !c.light_cache && c.spp == 25)
            bounces_of_25.push_back(c.bounce_spp);
    }
    EXPECT_EQ(bounces_of_4, (std::vector<uint32_t>{1, 2, 4}));
    EXPECT_EQ(bounces_of_16, (std::vector<uint32_t>{1, 2, 4, 8, 16}));
    EXPECT_EQ(bounces_of_25, (std::vector<uint32_t>{1, 2, 4, 8, 16, 25}));
    EXPECT_EQ(by_weight, (std::vector<uint32_t>{16, 25, 32, 40, 44, 48, 52, 54, 56, 64}));
    EXPECT_EQ(by_weight_08, (std::vector<uint32_t>{32, 36, 40, 42, 44, 46, 48, 52, 56}));
    for (const C& c : shadows)
        EXPECT_FALSE(c.by_weight); // Without bounces it would only scale the first hit's count.
    // Measuring order: nothing precedes a candidate it has no fewer samples than (same denoiser,
    // cache and allocation), samples by weight come last (by weight^0.8 after by weight), before
    // them every one without the cache precedes every one with it, and within each, every raw one
    // precedes every denoised one.
    for (size_t i = 0; i < both.size(); ++i)
        for (size_t j = i + 1; j < both.size(); ++j) {
            EXPECT_LE(both[i].by_weight, both[j].by_weight);
            EXPECT_GE(both[i].weight_exponent, both[j].weight_exponent);
            if (!both[j].by_weight) {
                EXPECT_LE(both[i].light_cache, both[j].light_cache);
            }
            const bool same_allocation =
                both[i].by_weight == both[j].by_weight && both[i].weight_exponent == both[j].weight_exponent;
            if (both[i].light_cache == both[j].light_cache && same_allocation) {
                EXPECT_LE(both[i].denoise, both[j].denoise);
            }
            if (both[i].denoise == both[j].denoise && both[i].light_cache == both[j].light_cache && same_allocation) {
                EXPECT_FALSE(both[j].spp <= both[i].spp && both[j].bounce_spp <= both[i].bounce_spp) << i << " " << j;
            }
        }
}

// The cheapest measured candidate at or below the target; unmeasured and worse ones never count.
TEST(EqualErrorPick, CheapestMeeting) {
    const std::vector<C> v = {
        {25, 25, false, 58.0, 0.0020}, // The target itself.
        {4, 4, false, 16.0, 0.0033},   // Cheaper, worse.
        {4, 4, true, 17.0, 0.0019},    // Meets: the answer.
        {8, 8, true, 25.0, 0.0015},    // Meets, dearer.
        {2, 2, true, -1.0, -1.0},      // Skipped (unmeasured).
        {1, 1, true, 9.0, 0.0020},     // Meets at exactly the target, cheapest.
    };
    const C* best = cheapest_meeting(v, 0.0020);
    ASSERT_NE(best, nullptr);
    EXPECT_EQ(best, &v[5]);
    best = cheapest_meeting(v, 0.0019); // 1/1 no longer meets: 4/4 denoised.
    ASSERT_NE(best, nullptr);
    EXPECT_EQ(best, &v[2]);
    EXPECT_EQ(cheapest_meeting(v, 0.0010), nullptr); // None reaches it.
    EXPECT_EQ(cheapest_meeting({}, 1.0), nullptr);
    const std::vector<C> no_times = {{25, 25, false, -1.0, 0.0020}}; // No GPU timestamps.
    EXPECT_EQ(cheapest_meeting(no_times, 0.0020), nullptr);
}

// Skipped: a candidate bounded below (no more samples of either kind, no denoiser it lacks) by a
// measured one that already cost at least the best so far. Not skipped: nothing known yet, a
// bound that is cheaper, or a bound with more samples or with a denoiser the candidate lacks.
TEST(EqualErrorPick, Skip) {
    const std::vector<C> measured = {
        {25, 25, false, 58.0, 0.0020}, // The target: best so far is 58 ms.
        {8, 4, false, 30.0, 0.0030},
        {4, 4, true, 60.0, 0.0010},    // Denoised, dear (a slow denoiser).
        {16, 16, false, -1.0, -1.0},   // Unmeasured: bounds nothing.
    };
    EXPECT_FALSE(equal_error_skip({16, 4, false}, measured, -1.0)); // Nothing meets yet.
    EXPECT_FALSE(equal_error_skip({16, 4, false}, measured, 58.0)); // 8/4 at 30 ms < 58.
    EXPECT_TRUE(equal_error_skip({16, 4, false}, measured, 25.0));  // 8/4 at 30 ms >= 25.
    EXPECT_TRUE(equal_error_skip({25, 25, true}, measured, 58.0));  // The target plus the denoiser.
    EXPECT_FALSE(equal_error_skip({4, 1, true}, measured, 58.0));   // Fewer bounce samples than 4/4.
    EXPECT_FALSE(equal_error_skip({8, 8, false}, measured, 58.0));  // 4/4 denoised bounds no raw row.
    EXPECT_TRUE(equal_error_skip({8, 8, true}, measured, 58.0));    // ... but does bound a denoised one.
    EXPECT_FALSE(equal_error_skip({25, 25, false}, measured, 70.0)); // No measured one took 70 ms.
    const std::vector<C> shadows = {{25, 0, false, 11.0, 0.001}};
    EXPECT_TRUE(equal_error_skip({25, 0, true}, shadows, 11.0));
    EXPECT_FALSE(equal_error_skip({16, 0, true}, shadows, 11.0));
    // The light cache only adds work: a row without it bounds one with it, not the other way.
    C cached{25, 0, false};
    cached.light_cache = true;
    EXPECT_TRUE(equal_error_skip(cached, shadows, 11.0));
    const std::vector<C> cached_rows = {{8, 0, false, 11.0, 0.001, true}};
    EXPECT_FALSE(equal_error_skip({16, 0, false}, cached_rows, 11.0));
    // Samples by weight are their own family: a plain row with fewer samples bounds none of them.
    C weighted{32, 0, false};
    weighted.by_weight = true;
    EXPECT_FALSE(equal_error_skip(weighted, measured, 25.0));
    std::vector<C> weighted_rows = {weighted};
    weighted_rows[0].frame_ms = 30.0;
    C more = weighted;
    more.spp = 40;
    EXPECT_TRUE(equal_error_skip(more, weighted_rows, 25.0));
    EXPECT_FALSE(equal_error_skip({40, 4, false}, weighted_rows, 25.0));
    // ... and so is each exponent: 32 by weight at 30 ms bounds no count by weight^0.8.
    C weighted_08 = more;
    weighted_08.weight_exponent = 0.8f;
    EXPECT_FALSE(equal_error_skip(weighted_08, weighted_rows, 25.0));
    weighted_rows[0].weight_exponent = 0.8f;
    EXPECT_TRUE(equal_error_skip(weighted_08, weighted_rows, 25.0));
    EXPECT_TRUE(equal_error_skip(cached, cached_rows, 11.0));
}

} // namespace
} // namespace vx::tools
