// Edits and the denoiser's history (render/edit_marks.h): a cube placed on a floor darkens the
// floor around it (its contact shadow and occlusion of the sky and the area light), where
// normal and depth stay as they were. Without the edit's mark the history clamp lets that small
// change fade over the whole history (a ghost: the first frame after the edit is worse there
// than a raw frame); with it, the history near the edit starts again.
#include <algorithm>
#include <cstdio>

#include "scene_util.h"

#include "render/image_metrics.h"
#include "world/mesh/edit_mesher.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Issue 18's scene (scripts/measure_sampling.py): a stone floor, four grass pillars holding a
// sand overhang 8 blocks up, a mirror wall; `vx bench render`'s default view and light. The
// edit path's cube (tools/bench_render_paths.cpp): 4 blocks of stone on the overhang's centre.
const world::BlockPos kCubeLo(22, 9, 22), kCubeHi(25, 12, 25);
const Camera kView = Camera::look_at({-2.07, 35.46, -2.07}, {24.0, 12.0, 24.0});

RenderSettings settings() {
    RenderSettings s;
    s.width = 112;
    s.height = 72;
    s.mode = ShadingMode::Full;
    s.light.block = {16, 56, 16};
    s.light.edge_u = {16, 0, 0};
    s.light.edge_v = {0, 0, 16};
    s.max_bounces = 4;
    s.shadow_samples = 4;
    return s;
}

world::World scene_world() {
    world::World w;
    test::fill_box(w, {0, 0, 0}, {48, 1, 48}, test::block_id("stone"));
    for (int64_t px : {10, 28})
        for (int64_t pz : {10, 26})
            test::fill_box(w, {px, 1, pz}, {px + 2, 8, pz + 2}, test::block_id("grass"));
    test::fill_box(w, {8, 8, 8}, {32, 9, 30}, test::block_id("sand"));
    test::fill_box(w, {40, 1, 2}, {41, 14, 46}, test::block_id("mirror"));
    return w;
}

struct EditErrors {
    double denoised = 0, raw = 0; // In the pixels the edit changed, the first frame after it.
    size_t changed = 0;
};

// Renders 8 still denoised frames (history 8), places the cube through the edit mesher and
// set_chunk (with note_edit when `mark`), and measures the next frame against a converged
// reference of the edited scene, beside a raw frame of the same samples.
EditErrors first_frame_after_edit(Renderer& r, bool mark) {
    world::World w = scene_world();
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(r, meshes);
    RenderSettings s = settings();
    const ImageF before = to_float(test::accumulated(r, s, kView, 32, 8));
    s.denoise = true;
    s.accumulate = 8;
    for (int i = 0; i < 8; ++i)
        r.render(s, kView);
    world::EditMesher em;
    for (int64_t y = kCubeLo.y; y <= kCubeHi.y; ++y)
        for (int64_t z = kCubeLo.z; z <= kCubeHi.z; ++z)
            for (int64_t x = kCubeLo.x; x <= kCubeHi.x; ++x)
                for (const world::SliceUpdate& u : em.apply(w, {x, y, z}, test::block_id("stone"), meshes).updates)
                    r.set_chunk(u.chunk, meshes[u.chunk].mesh, test::changed_slices(u));
    if (mark)
        r.note_edit(kCubeLo, kCubeHi);
    const ImageF denoised = to_float(r.render(s, kView));
    s.denoise = false;
    s.accumulate = 1;
    const ImageF raw = to_float(r.render(s, kView));
    const ImageF after = to_float(test::accumulated(r, settings(), kView, 32, 8));
    // The pixels the edit changed, as the bench's edit path counts them.
    const std::vector<bool> mask = changed_pixels(before, after);
    EditErrors e;
    e.changed = size_t(std::count(mask.begin(), mask.end(), true));
    e.denoised = masked_rmse(denoised, after, mask);
    e.raw = masked_rmse(raw, after, mask);
    return e;
}

TEST_F(RendererTest, EditDropsTheHistoryNearIt) {
    const EditErrors marked = first_frame_after_edit(*m_renderer, true);
    std::unique_ptr<Renderer> other = test::make_renderer();
    ASSERT_NE(other, nullptr);
    const EditErrors unmarked = first_frame_after_edit(*other, false);
    EXPECT_EQ(other->validation_errors(), 0u);
    // 2026-12-03, lavapipe: 66 pixels; 0.0183 marked, 0.0520 not, raw 0.0395.
    std::printf("edit: %zu pixels changed; first frame after it, denoised: %.4f marked, %.4f not; raw %.4f\n",
                marked.changed, marked.denoised, unmarked.denoised, marked.raw);
    ASSERT_GT(marked.changed, 40u); // The cube and its shadow are in view.
    // No ghost: the marked frame is no worse than a raw frame where the edit changed the light.
    EXPECT_LT(marked.denoised, marked.raw);
    // The control: unmarked, the old light lingers there, worse than the raw frame.
    EXPECT_GT(unmarked.denoised, unmarked.raw);
    EXPECT_LT(marked.denoised, 0.75 * unmarked.denoised);
}

} // namespace
} // namespace vx::render
