// Issue 18's rule for the sandbox's defaults (tools/defaults_rule.h).
#include "defaults_rule.h"

#include <algorithm>

namespace vx::tools {

DefaultsRuleResult apply_defaults_rule(std::span<const CostError> candidates, double error_slack,
                                       double cost_factor) {
    DefaultsRuleResult out;
    for (const CostError& c : candidates) {
        double best = c.error;
        for (const CostError& d : candidates)
            if (d.cost <= cost_factor * c.cost)
                best = std::min(best, d.error);
        out.best_within.push_back(best);
        out.qualifies.push_back(c.error <= error_slack * best);
    }
    for (size_t i = 0; i < candidates.size(); ++i) {
        if (!out.qualifies[i])
            continue;
        const CostError& c = candidates[i];
        if (!out.pick || c.cost < candidates[*out.pick].cost ||
            (c.cost == candidates[*out.pick].cost && c.error < candidates[*out.pick].error))
            out.pick = i;
    }
    return out;
}

} // namespace vx::tools
