#pragma once
// The block id of a coarse cell, elected from the votes of what lies under it, in two stages: the
// class by majority (opaque against see-through, ties to opaque), then the id by plurality within
// that class, ties to the smaller id. A plain plurality let water, one id, win a coast cell over
// land split between grass, sand and dirt, and the ground seen through the water sank (issue 16).
// One rule for downsample() and the terrain's direct coarse levels, so that they pick alike.

#include "world/base/assert.h"
#include "world/block_registry.h"

namespace vx::world {

class CellVote {
public:
    // Distinct ids one cell may see: downsample() has 4 voters, the terrain votes for 6 ids.
    static constexpr int kMaxCandidates = 8;

    // One vote for `id`; `opaque` is its class. Air abstains: a cell nothing votes for is air.
    void add(BlockId id, bool opaque) {
        if (id == kAir)
            return;
        for (int i = 0; i < m_n; ++i)
            if (m_ids[i] == id) {
                ++m_counts[i];
                return;
            }
        VX_ASSERT(m_n < kMaxCandidates); // Once per new id, so cheap.
        m_ids[m_n] = id;
        m_opaque[m_n] = opaque;
        m_counts[m_n++] = 1;
    }

    BlockId winner() const {
        int clear = 0, total = 0;
        for (int i = 0; i < m_n; ++i) {
            clear += m_opaque[i] ? 0 : m_counts[i];
            total += m_counts[i];
        }
        const bool want_opaque = 2 * clear <= total;
        BlockId best = kAir;
        int best_count = 0;
        for (int i = 0; i < m_n; ++i)
            if (m_opaque[i] == want_opaque &&
                (m_counts[i] > best_count || (m_counts[i] == best_count && m_ids[i] < best))) {
                best = m_ids[i];
                best_count = m_counts[i];
            }
        return best;
    }

private:
    BlockId m_ids[kMaxCandidates];
    int m_counts[kMaxCandidates];
    bool m_opaque[kMaxCandidates];
    int m_n = 0;
};

} // namespace vx::world
