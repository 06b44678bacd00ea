#pragma once
// Issue 18's rule for the sandbox's default render settings, chosen from measured curves: the
// cheapest settings whose error is within 1.25x of the best measured at up to twice their cost.
// Used by `vx bench render --sections defaults` (tools/bench_render_defaults.h). Pure functions:
// thread-safe.

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace vx::tools {

// One measured candidate: its cost (GPU ms per frame, > 0) and its error (e.g. an RMSE, >= 0).
struct CostError {
    double cost = 0;
    double error = 0;
};

struct DefaultsRuleResult {
    // Per candidate: the lowest error among the candidates costing at most cost_factor times its
    // cost (itself included, so never above its own error).
    std::vector<double> best_within;
    // Per candidate: error <= error_slack * best_within.
    std::vector<bool> qualifies;
    // The cheapest qualifying candidate (the lower error on equal cost, then the first). Empty
    // only for no candidates: the one of least error always qualifies.
    std::optional<size_t> pick;
};

// Candidate c qualifies if error(c) <= error_slack * min{ error(d) : cost(d) <= cost_factor *
// cost(c) }; returns that for each candidate and the pick. O(n^2), n is a few dozen.
// Preconditions: error_slack >= 1, cost_factor >= 1.
DefaultsRuleResult apply_defaults_rule(std::span<const CostError> candidates, double error_slack = 1.25,
                                       double cost_factor = 2.0);

} // namespace vx::tools
