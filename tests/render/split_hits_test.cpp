// Hits in passes of their own (RenderSettings::split_hits): dispatches each going on from the
// paths the last saved make the same image and G-buffer as one, for every split up to the paths'
// length and beyond it (with the light cache, to a step of rounding); their buffer's failure is
// reported and the next frame renders; where the split cannot apply it changes nothing.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "gbuffer_compare.h"
#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

// Over the glazed floor towards the mirror wall (hall()).
const Camera kView = Camera::look_at({-10.5, 7.0, 2.3}, {-1.0, 2.0, 0.0});

// The default lights (sun, sky, area light, haze), a soft area light to one side.
RenderSettings lit() {
    RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.light.block = {4, 20, -8};
    s.light.edge_u = {10, 0, 0};
    s.light.edge_v = {0, 0, 16};
    s.light.emission = glm::vec3(3.f);
    s.shadow_samples = 4;
    s.bounce_shadow_samples = 2;
    s.max_bounces = 3;
    return s;
}

// A glazed floor [-12, 12) x [0, 1) x [-12, 12), a mirror wall along x = 0 (z in [-12, 12), y up
// to 6), a glass block on the floor and a pool of water against the wall: paths reflect up to
// three times, some through glass, some from floor to wall inside the water (a later pass must
// know its path starts in the water: PathState throughput.w).
world::World hall() {
    world::World w;
    test::fill_box(w, {-12, 0, -12}, {12, 1, 12}, test::block_id("glazed"));
    test::fill_box(w, {0, 1, -12}, {1, 7, 12}, test::block_id("mirror"));
    test::fill_box(w, {-5, 1, -1}, {-4, 2, 0}, test::block_id("glass"));
    test::fill_box(w, {-4, 1, 1}, {0, 3, 6}, test::block_id("water"));
    return w;
}

// How many values of a and b differ (each channel of each pixel).
template <class T> size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
    EXPECT_EQ(a.size(), b.size());
    size_t n = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        n += a[i] != b[i] ? 1 : 0;
    return n;
}

// Byte for byte the same output, and the same G-buffer (test::same_gbuffer: equal on Mesa), in
// plain, by-weight and denoised frames (the denoiser reads the first mirror bounce's images, which
// the pass that shades that bounce writes), split after the first hit, the second, every hit (3
// bounces) and more (capped). Control: the reflections change the image (so the later passes had
// work, and did it as one pass would).
TEST_F(RendererTest, SplitHitsGiveTheSameImage) {
    test::load_meshes(*m_renderer, test::mesh_world(hall()));
    for (int variant = 0; variant < 3; ++variant) {
        RenderSettings s = lit();
        s.samples_by_weight = variant == 1;
        s.denoise = variant == 2;
        GBufferImage one_g;
        const RenderImage one = m_renderer->render(s, kView, &one_g);
        for (uint32_t split : {1u, 2u, 3u, 7u}) {
            s.split_hits = split;
            GBufferImage split_g;
            const RenderImage img = m_renderer->render(s, kView, &split_g);
            EXPECT_EQ(differing(one.rgba, img.rgba), 0u) << "variant " << variant << ", split " << split;
            const std::string what = "variant " + std::to_string(variant) + ", split " + std::to_string(split);
            EXPECT_TRUE(test::same_gbuffer(one_g, split_g, m_renderer->device().driver_info, what));
        }
        s.split_hits = 0;
        s.max_bounces = 0;
        const RenderImage flat_mirrors = m_renderer->render(s, kView);
        const size_t changed = differing(one.rgba, flat_mirrors.rgba);
        std::printf("variant %d: %zu of %zu channels change without reflections\n", variant, changed,
                    one.rgba.size());
        EXPECT_GT(changed, one.rgba.size() / 10) << "variant " << variant;
    }
}

// With the light cache the passes' hits go to the same cells and records as one pass's: the same
// image here to a step of rounding (a cell's float sums take the hits in another order; lavapipe
// and the H100 moved none), plain and denoised. A later pass that lost the earlier passes'
// records (the primary hits' cached light) would darken most of the image by far more. Control:
// the cache changes the image.
TEST_F(RendererTest, SplitHitsWithTheLightCacheGiveTheSameImage) {
    test::load_meshes(*m_renderer, test::mesh_world(hall()));
    for (bool denoise : {false, true}) {
        RenderSettings s = lit();
        s.denoise = denoise;
        const RenderImage uncached = m_renderer->render(s, kView);
        s.light_cache = true;
        const RenderImage one = m_renderer->render(s, kView);
        EXPECT_GT(differing(one.rgba, uncached.rgba), one.rgba.size() / 10) << "denoise " << denoise;
        for (uint32_t split : {1u, 2u, 3u}) {
            s.split_hits = split;
            const RenderImage img = m_renderer->render(s, kView);
            const size_t changed = differing(one.rgba, img.rgba);
            std::printf("light cache, denoise %d, split %u: %zu of %zu channels differ\n", int(denoise), split,
                        changed, one.rgba.size());
            EXPECT_LE(test::largest_step(one, img), 1) << "denoise " << denoise << ", split " << split;
            EXPECT_LE(changed, one.rgba.size() / 100) << "denoise " << denoise << ", split " << split;
        }
    }
}

// Out of memory for the paths between the passes: the frame fails with a clear line, also with
// the light cache, and the next one (the allocation possible again) is the one-pass image.
// Frames that cannot use the split (no reflections) never ask for that buffer and do not change.
TEST_F(RendererTest, SplitHitsBufferFailureIsReported) {
    test::load_meshes(*m_renderer, test::mesh_world(hall()));
    RenderSettings s = lit();
    const RenderImage expected = m_renderer->render(s, kView);
    s.split_hits = 2;
    m_renderer->fail_allocations("path states");
    Result<RenderImage> failed = m_renderer->try_render(s, kView);
    ASSERT_FALSE(failed);
    EXPECT_NE(failed.error().find("out of GPU memory for the paths between the trace passes"), std::string::npos)
        << failed.error();
    EXPECT_EQ(failed.error().find('\n'), std::string::npos);
    RenderSettings cached = s;
    cached.light_cache = true;
    Result<RenderImage> failed_cached = m_renderer->try_render(cached, kView);
    ASSERT_FALSE(failed_cached);
    EXPECT_NE(failed_cached.error().find("out of GPU memory for the paths between the trace passes"),
              std::string::npos)
        << failed_cached.error();
    RenderSettings other = s; // Cannot apply: no second buffer is asked for.
    other.max_bounces = 0;
    Result<RenderImage> ok = m_renderer->try_render(other, kView);
    ASSERT_TRUE(ok) << ok.error();
    other.split_hits = 0;
    EXPECT_EQ(differing(ok->rgba, m_renderer->render(other, kView).rgba), 0u);
    m_renderer->fail_allocations("");
    Result<RenderImage> img = m_renderer->try_render(s, kView);
    ASSERT_TRUE(img) << img.error();
    EXPECT_EQ(differing(img->rgba, expected.rgba), 0u);
}

} // namespace
} // namespace vx::render
