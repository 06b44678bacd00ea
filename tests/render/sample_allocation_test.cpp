// Light samples by each hit's weight in the pixel (RenderSettings::samples_by_weight): the counts
// it gives, that a matte scene keeps its image, and that glazed blocks converge to the same image
// with fewer rays.
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <set>

#include "scene_util.h"

#include "render/image_metrics.h"

namespace vx::render {
namespace {

using test::RendererTest;

// A floor of `floor` blocks [-12, 12) x [0, 1) x [-12, 12) with a wall of `wall` along x = 0
// (z in [-12, 12), y up to 6): its shadow's penumbra crosses the floor.
world::World yard(const char* floor, const char* wall) {
    world::World w;
    test::fill_box(w, {-12, 0, -12}, {12, 1, 12}, test::block_id(floor));
    test::fill_box(w, {0, 1, -12}, {1, 7, 12}, test::block_id(wall));
    return w;
}

// The thesis's light: the area light alone, wide and to one side, so the wall's shadow is soft.
RenderSettings thesis_light(ShadingMode mode) {
    RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.mode = mode;
    s.light.block = {4, 20, -8};
    s.light.edge_u = {10, 0, 0};
    s.light.edge_v = {0, 0, 16};
    s.light.emission = glm::vec3(3.f);
    s.sun.irradiance = glm::vec3(0.f);
    s.sky_light = 0.f;
    s.max_bounces = 3;
    return s;
}

// Looking down at the floor in the wall's penumbra (x from -6.5 to -1.9), the wall in view.
const Camera kView = Camera::look_at({-10.5, 9.0, 0.3}, {-2.0, 1.0, 0.0});

// The distinct grey levels of a Visibility image (the visible fraction of the first hit's samples).
std::set<int> levels(const RenderImage& img) {
    std::set<int> out;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        out.insert(img.rgba[i]);
    return out;
}

// `v` is one of `levels` to within one 8-bit step: a half (127.5) rounds to 127 on an NVIDIA
// driver and to 128 on lavapipe.
bool near_one_of(int v, std::initializer_list<int> levels) {
    for (int l : levels)
        if (std::abs(v - l) <= 1)
            return true;
    return false;
}

// A first hit's count is ceil(shadow_samples x (1 - reflectivity)): 4 samples on a glazed floor
// (reflectivity 0.25) become 3, so the visible fractions are thirds; on stone they stay quarters.
TEST_F(RendererTest, SamplesByWeightCountAFirstHitsDiffuseShare) {
    RenderSettings s = thesis_light(ShadingMode::Visibility);
    s.shadow_samples = 4;
    s.samples_by_weight = true;
    auto fractions = [&](const char* floor) {
        test::load_meshes(*m_renderer, test::mesh_world(yard(floor, "stone")));
        const std::set<int> l = levels(m_renderer->render(s, kView));
        std::printf("%s floor, by weight:", floor);
        for (int v : l)
            std::printf(" %d", v);
        std::printf("\n");
        return l;
    };
    const std::set<int> glazed = fractions("glazed");
    EXPECT_TRUE(glazed.count(85) || glazed.count(170)); // A penumbra: 1/3 or 2/3 of 3 samples.
    for (int v : glazed) // The sky (no hit) is the sky colour's red channel, not a fraction.
        EXPECT_TRUE(near_one_of(v, {0, 85, 170, 255, 140})) << v;
    const std::set<int> stone = fractions("stone");
    EXPECT_TRUE(stone.count(64) || stone.count(127) || stone.count(128) || stone.count(191));
    for (int v : stone)
        EXPECT_TRUE(near_one_of(v, {0, 64, 128, 191, 255, 140})) << v;
    // weight_exponent 0.8: ceil(4 x 0.75^0.8) = ceil(3.18) = 4 samples on the glazed floor: quarters.
    s.weight_exponent = 0.8f;
    const std::set<int> glazed_08 = fractions("glazed");
    EXPECT_TRUE(glazed_08.count(64) || glazed_08.count(127) || glazed_08.count(128) || glazed_08.count(191));
    for (int v : glazed_08)
        EXPECT_TRUE(near_one_of(v, {0, 64, 128, 191, 255, 140})) << v;
}

// An exponent outside (0, 1] reaches the renderer only past the facade's and the CLI's checks
// (a game's own settings): it counts as 1, the same image as exponent 1, never NaN counts.
TEST_F(RendererTest, SamplesByWeightTakeABadExponentAsOne) {
    test::load_meshes(*m_renderer, test::mesh_world(yard("glazed", "stone")));
    RenderSettings s = thesis_light(ShadingMode::Full);
    s.shadow_samples = 4;
    s.samples_by_weight = true;
    const RenderImage one = m_renderer->render(s, kView);
    s.weight_exponent = 0.5f; // A valid exponent changes the counts: the test can tell.
    EXPECT_NE(m_renderer->render(s, kView).rgba, one.rgba);
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), 0.f, -1.f, 2.f,
                      std::numeric_limits<float>::infinity()}) {
        s.weight_exponent = bad;
        EXPECT_EQ(m_renderer->render(s, kView).rgba, one.rgba) << bad;
    }
}

// With no glazed or mirror block every hit weighs 1: the same samples, byte for byte.
TEST_F(RendererTest, SamplesByWeightKeepAMatteSceneAsItWas) {
    test::load_meshes(*m_renderer, test::mesh_world(yard("stone", "dirt")));
    RenderSettings s = thesis_light(ShadingMode::Full);
    s.shadow_samples = 8;
    const RenderImage plain = m_renderer->render(s, kView);
    s.samples_by_weight = true;
    const RenderImage weighted = m_renderer->render(s, kView);
    EXPECT_EQ(plain.rgba, weighted.rgba);
}

// Glazed blocks (a quarter mirrored, as the thesis's): by weight, 8 samples on the floor become 6
// and those of the surfaces seen in it 2 (8 x 0.25 x 0.75 = 1.5, rounded up) and 1, so one frame
// differs and is noisier, but the mean of many frames is the plain mean's: the same image.
TEST_F(RendererTest, SamplesByWeightConvergeToTheSameImage) {
    test::load_meshes(*m_renderer, test::mesh_world(yard("glazed", "glazed")));
    RenderSettings s = thesis_light(ShadingMode::Full);
    s.seed = 1000;
    const ImageF reference = to_float(test::accumulated(*m_renderer, s, kView, 64, 16));
    s.seed = 1;
    const ImageF plain = to_float(test::accumulated(*m_renderer, s, kView, 32, 8));
    s.samples_by_weight = true;
    const ImageF weighted = to_float(test::accumulated(*m_renderer, s, kView, 32, 8));
    s.weight_exponent = 0.8f; // More of the rays on the bounces: the same image too.
    const ImageF weighted_08 = to_float(test::accumulated(*m_renderer, s, kView, 32, 8));
    s.weight_exponent = 1.f;
    s.accumulate = 1;
    s.shadow_samples = 8;
    const ImageF one_weighted = to_float(m_renderer->render(s, kView));
    s.samples_by_weight = false;
    const ImageF one_plain = to_float(m_renderer->render(s, kView));
    double mean_plain = 0, mean_weighted = 0, mean_08 = 0, mean_ref = 0;
    for (size_t i = 0; i < reference.rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c) {
            mean_ref += reference.rgba[i + c];
            mean_plain += plain.rgba[i + c];
            mean_weighted += weighted.rgba[i + c];
            mean_08 += weighted_08.rgba[i + c];
        }
    const double n = 3.0 * double(reference.rgba.size() / 4);
    std::printf("glazed yard: 32 frames plain RMSE %.5f, by weight %.5f, by weight^0.8 %.5f; one frame %.5f, "
                "by weight %.5f; mean %.5f, plain %.5f, by weight %.5f, by weight^0.8 %.5f\n",
                rmse(plain, reference), rmse(weighted, reference), rmse(weighted_08, reference),
                rmse(one_plain, reference), rmse(one_weighted, reference), mean_ref / n, mean_plain / n,
                mean_weighted / n, mean_08 / n);
    EXPECT_NEAR(mean_08 / n, mean_ref / n, 0.1 / 255.0);
    EXPECT_LT(rmse(weighted_08, reference), 2.0 * rmse(plain, reference) + 1.0 / 255.0);
    EXPECT_NE(one_plain.rgba, one_weighted.rgba); // The setting changes the samples.
    // The same image: the means agree to a tenth of an 8-bit step, the error stays that of noise.
    EXPECT_NEAR(mean_weighted / n, mean_ref / n, 0.1 / 255.0);
    EXPECT_NEAR(mean_plain / n, mean_ref / n, 0.1 / 255.0);
    EXPECT_LT(rmse(weighted, reference), 2.0 * rmse(plain, reference) + 1.0 / 255.0);
}

} // namespace
} // namespace vx::render
