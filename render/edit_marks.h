#pragma once
// Where blocks changed since the last frame, for the denoiser: a surface near an edit may keep
// its normal and depth (the floor beside a placed block) while its light changed (the block's
// contact shadow and occlusion), and the history clamp lets such a small change fade over the
// whole history instead (docs/render_report.md, "Edits drop the history near them"). The ray
// generation marks the primary hits and first mirror bounces that lie in a box, and the
// temporal pass starts their history again (render/gbuffer.h, albedo a). Main thread only
// (the Renderer's).

#include <cstddef>
#include <vector>

#include "render/gpu_layouts.h"
#include "world/coords.h"

namespace vx::render {

// How far an edit's light reaches, blocks beyond the edited box: where a block's occlusion of the
// sky and the area light is more than a few per cent (a unit cube 4 blocks away covers about
// 1/16 sr: 2% of the sky's light). Farther changes (a long shadow) are left to the clamp.
inline constexpr int64_t kEditReach = 4;

class EditMarks {
public:
    struct Box {
        world::BlockPos lo, hi; // Inclusive, world blocks.
    };

    // Blocks [lo, hi] (inclusive, world blocks; lo <= hi on every axis) changed. Beyond
    // gpu::kMaxEditBoxes boxes the two whose union grows least are merged (a larger region
    // restarts its history: never a missed edit).
    void add(world::BlockPos lo, world::BlockPos hi);

    // Writes the boxes, widened by kEditReach, relative to the render origin `origin`, into
    // p.edits and p.edit_boxes.
    void write(gpu::FrameParams& p, world::BlockPos origin) const;

    void clear() { m_boxes.clear(); }
    const std::vector<Box>& boxes() const { return m_boxes; }

private:
    std::vector<Box> m_boxes; // At most gpu::kMaxEditBoxes.
};

} // namespace vx::render
