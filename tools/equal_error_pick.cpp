#include "equal_error_pick.h"

#include <initializer_list>

namespace vx::tools {

static EqualErrorCandidate candidate(uint32_t spp, uint32_t bounce_spp, bool denoise, bool light_cache) {
    EqualErrorCandidate c{spp, bounce_spp, denoise};
    c.light_cache = light_cache;
    return c;
}

std::vector<EqualErrorCandidate> equal_error_candidates(bool reflections) {
    std::vector<EqualErrorCandidate> v;
    for (bool cache : {false, true})
        for (bool denoise : {false, true})
            for (uint32_t spp : {1u, 2u, 4u, 8u, 16u, kThesisSpp}) {
                if (!reflections) {
                    v.push_back(candidate(spp, 0, denoise, cache));
                    continue;
                }
                uint32_t last = 0; // {1, 2, 4, 8, 16, spp} repeats a count when spp <= 16.
                for (uint32_t bounce : {1u, 2u, 4u, 8u, 16u, spp})
                    if (bounce <= spp && bounce != last) {
                        v.push_back(candidate(spp, bounce, denoise, cache));
                        last = bounce;
                    }
            }
    if (!reflections)
        return v;
    // By weight (exponent 1), then by weight^0.8 (render::RenderSettings::weight_exponent): its
    // counts are finer where stop 29's pick lay between two.
    const std::initializer_list<uint32_t> by_weight = {16u, kThesisSpp, 32u, 40u, 44u, 48u, 52u, 54u, 56u, 64u};
    const std::initializer_list<uint32_t> by_weight_08 = {32u, 36u, 40u, 42u, 44u, 46u, 48u, 52u, 56u};
    for (float exponent : {1.f, 0.8f})
        for (bool denoise : {false, true})
            for (uint32_t spp : exponent == 1.f ? by_weight : by_weight_08) {
                EqualErrorCandidate c = candidate(spp, 0, denoise, false);
                c.by_weight = true;
                c.weight_exponent = exponent;
                v.push_back(c);
            }
    return v;
}

bool equal_error_skip(const EqualErrorCandidate& c, std::span<const EqualErrorCandidate> measured, double best_ms) {
    if (best_ms <= 0)
        return false;
    for (const EqualErrorCandidate& m : measured)
        if (m.frame_ms >= best_ms && m.by_weight == c.by_weight && m.weight_exponent == c.weight_exponent &&
            m.spp <= c.spp && m.bounce_spp <= c.bounce_spp &&
            (c.denoise || !m.denoise) &&
            (c.light_cache || !m.light_cache))
            return true;
    return false;
}

const EqualErrorCandidate* cheapest_meeting(std::span<const EqualErrorCandidate> candidates, double target_rmse) {
    const EqualErrorCandidate* best = nullptr;
    for (const EqualErrorCandidate& c : candidates)
        if (c.frame_ms > 0 && c.rmse >= 0 && c.rmse <= target_rmse && (!best || c.frame_ms < best->frame_ms))
            best = &c;
    return best;
}

} // namespace vx::tools
