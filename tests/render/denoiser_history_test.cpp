// The denoiser's history under a moving camera, on synthetic G-buffers: a floor seen from a
// pitched, turning camera (the history must be the previous frame's picture of the same points:
// reprojection with pitch and yaw, the plane test's rotation; never that of another surface of
// the same orientation, a raised layer of blocks one block above the floor), and a wall with a
// mirror seen by a camera moving sideways (the mirror's picture follows its virtual image).
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "render/denoiser.h"
#include "render_test_util.h"

namespace vx::render {
namespace {

constexpr uint32_t kW = 96, kH = 64;
constexpr float kFov = 60.f;
constexpr float kAlbedo = 0.7f;

struct View {
    glm::dvec3 eye, target;
    glm::dmat4 view_from_world() const { return glm::lookAt(eye, target, glm::dvec3(0, 1, 0)); }
};

struct Frame {
    ImageF colour, albedo, normal_depth;
    ImageF reflected;          // Nothing reflected; a: the sun flag's sign (render/gbuffer.h).
    std::vector<glm::dvec3> hit; // Each pixel's world point (x NaN: sky).
    std::vector<bool> raised;    // On the raised square (render_floor's raised_half).
};

// Where the sun is blocked on the floor: world x below `below` or above `above`.
struct SunShadow {
    double below = -1e30, above = 1e30;
};

// Light on the floor at world (x, z), `detail` times: 1, smooth with a period of many pixels;
// more: finer (a few pixels); 0: uniform.
float floor_light(double x, double z, float offset, double detail = 1.0) {
    return float(0.5 + 0.25 * std::sin(detail * x / 4.0) * std::cos(detail * z / 5.0)) + offset;
}

// The ray tracer's picture (shaders/raygen.rgen primary_dir) of the floor y = floor_y (normal
// +y) from `v`, no reflections; `variance`: the pixels' own (render/gbuffer.h; -1: one sample).
// raised_half > 0: a square of that half-size around x = z = 0 one block above the floor (its
// top only: the sides are not drawn). Pixels that miss show black sky (no surface).
Frame render_floor(const View& v, double floor_y, float light_offset, double detail = 1.0,
                   float variance = -1.f, SunShadow shadow = {}, double raised_half = 0.0) {
    Frame f{ImageF::make(kW, kH), ImageF::make(kW, kH), ImageF::make(kW, kH), ImageF::make(kW, kH),
            std::vector<glm::dvec3>(size_t(kW) * kH, glm::dvec3(std::nan(""))),
            std::vector<bool>(size_t(kW) * kH, false)};
    const glm::dvec3 fwd = glm::normalize(v.target - v.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(0, 1, 0)));
    const glm::dvec3 up = glm::cross(right, fwd);
    const double th = std::tan(glm::radians(double(kFov)) * 0.5), aspect = double(kW) / kH;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / glm::dvec2(kW, kH) * 2.0 - 1.0;
            const glm::dvec3 dir = glm::normalize(fwd + ndc.x * th * aspect * right - ndc.y * th * up);
            double t = (floor_y - v.eye.y) / dir.y;
            if (!(t > 0.0))
                continue;
            const double t_top = (floor_y + 1.0 - v.eye.y) / dir.y;
            const glm::dvec3 top = v.eye + t_top * dir;
            const bool raised = t_top > 0.0 && std::abs(top.x) < raised_half && std::abs(top.z) < raised_half;
            if (raised)
                t = t_top;
            const glm::dvec3 hit = v.eye + t * dir;
            f.hit[size_t(y) * kW + x] = hit;
            f.raised[size_t(y) * kW + x] = raised;
            const bool blocked = hit.x < shadow.below || hit.x > shadow.above;
            f.reflected.at(x, y)[3] = blocked ? -20.f : 20.f; // Occluder distance in blocks; sign: sun.
            const float light = floor_light(hit.x, hit.z, light_offset, detail);
            for (int c = 0; c < 3; ++c) {
                f.colour.at(x, y)[c] = kAlbedo * light;
                f.albedo.at(x, y)[c] = kAlbedo;
            }
            f.colour.at(x, y)[3] = variance;
            f.albedo.at(x, y)[3] = 1.f;
            const float nd[4] = {0.f, 1.f, 0.f, float(t)};
            std::copy(nd, nd + 4, f.normal_depth.at(x, y));
        }
    return f;
}

// RMSE over the pixels away from the image's edges (what comes into view has no history).
double inner_rmse(const ImageF& test, const ImageF& reference) {
    double sum = 0.0;
    size_t n = 0;
    for (uint32_t y = 6; y + 6 < kH; ++y)
        for (uint32_t x = 6; x + 6 < kW; ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = double(test.at(x, y)[c]) - reference.at(x, y)[c];
                sum += d * d;
                ++n;
            }
    return std::sqrt(sum / double(n));
}

// The second frame of a temporal-only denoiser (no filter, no clamp: nothing dropped) that saw
// `first` from `before` and now `second` from `after`; `reproject` false: the history is read
// at the same pixel (the scale of a wrong reprojection).
ImageF second_frame(Context& ctx, const View& before, const Frame& first, const View& after, const Frame& second,
                    bool reproject) {
    DenoiseSettings s;
    s.iterations = 0;
    s.history_clamp = false;
    Denoiser denoiser(ctx, kW, kH);
    denoise_on_host(ctx, denoiser, first.colour, first.albedo, first.normal_depth, s, glm::mat4(1.f), kFov);
    const glm::dmat4 prev = before.view_from_world(), cur = after.view_from_world();
    const glm::mat4 m = reproject ? reprojection_matrix(prev, cur, kFov, kW, kH) : glm::mat4(1.f);
    const glm::quat r = reproject ? history_rotation(prev) : history_rotation(cur);
    return denoise_on_host(ctx, denoiser, second.colour, second.albedo, second.normal_depth, s, m, kFov, nullptr,
                           nullptr, r);
}

// Looking down at 80 degrees from 71 blocks: the lower and upper faces of a one-block step lie
// 1.02 blocks apart along a ray, within the 2% distance tolerance the history used to have.
const View kBefore{{0.0, 70.0, 12.0}, {0.0, 0.0, 0.0}};
const View kAfter{{1.3, 70.4, 11.3}, {0.5, 0.0, -0.3}}; // Moved 1.5 blocks, turned and pitched.

using DenoiserHistoryTest = test::RenderTest;

// Noise-free frames of the same floor: the mean of the second frame and its reprojected history
// is the second frame when the history shows the same points.
TEST_F(DenoiserHistoryTest, PitchedTurningCameraReprojectsTheSamePoints) {
    const Frame first = render_floor(kBefore, 0.0, 0.f), second = render_floor(kAfter, 0.0, 0.f);
    const double moved = inner_rmse(second_frame(*m_ctx, kBefore, first, kAfter, second, true), second.colour);
    const double scale = inner_rmse(second_frame(*m_ctx, kBefore, first, kAfter, second, false), second.colour);
    std::printf("pitched camera, second frame: RMSE %.4f (history not reprojected %.4f)\n", moved, scale);
    EXPECT_LT(moved, 0.1 * scale);
    EXPECT_LT(moved, 0.004);
}

// A layer of blocks placed on the floor between the frames: the same normal, one block nearer.
// Its pixels must not take the floor's history (brighter by 0.3 here): the output is the new
// frame.
TEST_F(DenoiserHistoryTest, HistoryOfAParallelPlaneOneBlockAwayIsNotTaken) {
    const Frame first = render_floor(kBefore, 0.0, 0.3f), second = render_floor(kAfter, 1.0, 0.f);
    const double error = inner_rmse(second_frame(*m_ctx, kBefore, first, kAfter, second, true), second.colour);
    std::printf("raised layer, second frame: RMSE %.4f against the new frame (history taken: ~%.3f)\n", error,
                0.5 * 0.3 * kAlbedo);
    EXPECT_LT(error, 0.004);
}

// Pixels of several samples under a moving camera weigh the history by what resampling it costs
// against their own noise (denoise_temporal.comp, moving_history_cap): where the light is uniform
// the bilinear taps are exact and the history counts fully (the second frame is the mean of
// both); where it varies over a few pixels they are not, and this frame counts most. The first
// frame is brighter by 0.2, so the output shows the history's share.
TEST_F(DenoiserHistoryTest, MovingCameraWeighsHistoryByItsResamplingError) {
    const auto history_share = [&](double detail) {
        const Frame first = render_floor(kBefore, 0.0, 0.2f, detail, 1e-5f);
        const Frame second = render_floor(kAfter, 0.0, 0.f, detail, 1e-5f);
        const ImageF out = second_frame(*m_ctx, kBefore, first, kAfter, second, true);
        double share = 0.0;
        size_t n = 0;
        for (uint32_t y = 6; y + 6 < kH; ++y)
            for (uint32_t x = 6; x + 6 < kW; ++x) {
                share += (double(out.at(x, y)[0]) - second.colour.at(x, y)[0]) / (0.2 * kAlbedo);
                ++n;
            }
        return share / double(n);
    };
    const double uniform = history_share(0.0), fine = history_share(6.0);
    std::printf("moving camera, history's share of the second frame: uniform light %.3f, fine detail %.3f\n",
                uniform, fine);
    EXPECT_NEAR(uniform, 0.5, 0.02);
    EXPECT_LT(fine, 0.25);
    EXPECT_GT(fine, 0.0);
}

// A floor seen by a moving camera whose left part (x < -8) falls into a sun shadow between the
// frames and whose right part (x > 8) leaves one (the sun flag: render/gbuffer.h, reflected
// a < 0). The light on the plane is the same in both frames but the first is brighter by 0.2,
// so the output shows the history's share: none where the sun flag changed (bilinear taps across
// a sun shadow's edge smeared the lit side's history into the dark one: docs/render_report.md,
// 2026-12-02), half elsewhere (two frames of one sample). Temporal pass only, no clamp: the flag
// alone decides. Points within 2 blocks of the bands' edges are not counted.
TEST_F(DenoiserHistoryTest, MovingCameraTakesNoHistoryAcrossASunShadowsEdge) {
    const Frame first = render_floor(kBefore, 0.0, 0.2f, 1.0, -1.f, SunShadow{-1e30, 8.0});
    const Frame second = render_floor(kAfter, 0.0, 0.f, 1.0, -1.f, SunShadow{-8.0, 1e30});
    DenoiseSettings s;
    s.iterations = 0;
    s.history_clamp = false;
    Denoiser denoiser(*m_ctx, kW, kH);
    const glm::dmat4 prev = kBefore.view_from_world(), cur = kAfter.view_from_world();
    denoise_on_host(*m_ctx, denoiser, first.colour, first.albedo, first.normal_depth, s, glm::mat4(1.f), kFov,
                    &first.reflected, nullptr, history_rotation(prev));
    const ImageF out =
        denoise_on_host(*m_ctx, denoiser, second.colour, second.albedo, second.normal_depth, s,
                        reprojection_matrix(prev, cur, kFov, kW, kH), kFov, &second.reflected, nullptr,
                        history_rotation(prev));
    double share[3] = {0, 0, 0};
    size_t n[3] = {0, 0, 0};
    for (uint32_t y = 6; y + 6 < kH; ++y)
        for (uint32_t x = 6; x + 6 < kW; ++x) {
            const double hx = second.hit[size_t(y) * kW + x].x;
            if (std::isnan(hx) || std::abs(std::abs(hx) - 8.0) < 2.0)
                continue; // Sky, or near a band's edge.
            const int band = hx < -8.0 ? 0 : hx < 8.0 ? 1 : 2;
            share[band] += (double(out.at(x, y)[0]) - second.colour.at(x, y)[0]) / (0.2 * kAlbedo);
            ++n[band];
        }
    for (int b = 0; b < 3; ++b) {
        ASSERT_GT(n[b], 20u);
        share[b] /= double(n[b]);
    }
    std::printf("sun flag, moving camera: history's share into the shadow %.3f, unchanged %.3f, out of the "
                "shadow %.3f\n",
                share[0], share[1], share[2]);
    EXPECT_NEAR(share[0], 0.0, 0.01);
    EXPECT_NEAR(share[1], 0.5, 0.02);
    EXPECT_NEAR(share[2], 0.0, 0.01);
}

// Floor pixels whose history taps are partly on a raised square (another plane) under a moving
// camera: the renormalised taps extrapolate, and their range bounds nothing. They weigh the
// history by its gap to this frame against their own noise (denoise_temporal.comp,
// moving_history_cap): a history within the noise counts about half (two frames), one far off
// it hardly counts. Which pixels have such taps is found here by projecting their floor point
// into the first view (the shader's bilinear footprint). Own variance 1e-4 (noise deviation 0.04
// in illumination over kStratifiedVarianceScale); the first frame brighter by `offset`.
TEST_F(DenoiserHistoryTest, MovingPixelsWithTapsOffThePlaneWeighHistoryByItsGap) {
    const glm::dmat4 prev = kBefore.view_from_world(), cur = kAfter.view_from_world();
    const double th = std::tan(glm::radians(double(kFov)) * 0.5), aspect = double(kW) / kH;
    const auto history_share = [&](float offset, size_t* counted) {
        const Frame first = render_floor(kBefore, 0.0, offset, 0.0, 1e-4f, {}, 6.0);
        const Frame second = render_floor(kAfter, 0.0, 0.f, 0.0, 1e-4f, {}, 6.0);
        DenoiseSettings s;
        s.iterations = 0;
        s.history_clamp = false;
        Denoiser denoiser(*m_ctx, kW, kH);
        denoise_on_host(*m_ctx, denoiser, first.colour, first.albedo, first.normal_depth, s, glm::mat4(1.f),
                        kFov, &first.reflected, nullptr, history_rotation(prev));
        const ImageF out =
            denoise_on_host(*m_ctx, denoiser, second.colour, second.albedo, second.normal_depth, s,
                            reprojection_matrix(prev, cur, kFov, kW, kH), kFov, &second.reflected, nullptr,
                            history_rotation(prev));
        double share = 0.0;
        size_t n = 0;
        for (uint32_t y = 6; y + 6 < kH; ++y)
            for (uint32_t x = 6; x + 6 < kW; ++x) {
                const size_t i = size_t(y) * kW + x;
                if (std::isnan(second.hit[i].x) || second.raised[i])
                    continue;
                const glm::dvec4 v = prev * glm::dvec4(second.hit[i], 1.0); // The first view's point.
                const glm::dvec2 ndc(v.x / (-v.z * th * aspect), -v.y / (-v.z * th));
                const glm::dvec2 pixel = (ndc + 1.0) * 0.5 * glm::dvec2(kW, kH) - 0.5;
                const glm::ivec2 base(int(std::floor(pixel.x)), int(std::floor(pixel.y)));
                int on_floor = 0;
                for (int t = 0; t < 4; ++t) {
                    const glm::ivec2 q = base + glm::ivec2(t & 1, t >> 1);
                    const size_t k = size_t(q.y) * kW + q.x;
                    on_floor += !first.raised[k] && !std::isnan(first.hit[k].x);
                }
                if (on_floor == 0 || on_floor == 4)
                    continue; // All taps on the floor or none: not the case tested here.
                share += (double(out.at(x, y)[0]) - second.colour.at(x, y)[0]) / (double(offset) * kAlbedo);
                ++n;
            }
        *counted = n;
        return n > 0 ? share / double(n) : -1.0;
    };
    size_t n_near = 0, n_far = 0;
    const double near = history_share(0.01f, &n_near), far = history_share(0.3f, &n_far);
    std::printf("taps partly off the plane, history's share: gap 0.01 %.3f, gap 0.3 %.3f (%zu pixels)\n",
                near, far, n_near);
    ASSERT_GT(n_near, 10u);
    EXPECT_GT(near, 0.35); // About 0.48 for the optimal blend; none at all before 2026-12-02.
    EXPECT_LT(near, 0.55);
    EXPECT_LT(far, 0.05);
}

using DenoiserTest = test::RenderTest;

// A wall 8 blocks in front of a camera looking down -z, its light varying along x (period about
// 6 pixels), its upper half a mirror whose picture is a surface 6 blocks behind it (path length
// 14; light and reflected part varying along that surface's x). Noise-free, camera at x.
// Marks every pixel as one sample (own variance unknown, render/gbuffer.h).
void set_one_sample(ImageF& colour) {
    for (uint32_t y = 0; y < colour.height; ++y)
        for (uint32_t x = 0; x < colour.width; ++x)
            colour.at(x, y)[3] = -1.f;
}

struct MovedView {
    ImageF colour, albedo, normal_depth, reflected, mirror_light, mirror_albedo, mirror_nd;
};

constexpr uint32_t kMoveW = 64, kMoveH = 32;
constexpr float kMoveFov = 60.f;

MovedView moved_view(double camera_x) {
    const auto make = [] { return ImageF::make(kMoveW, kMoveH); };
    MovedView v{make(), make(), make(), make(), make(), make(), make()};
    const double th = std::tan(glm::radians(double(kMoveFov)) * 0.5), aspect = double(kMoveW) / kMoveH;
    const double kWall = 8.0, kPath = 14.0, kPi = 3.14159265358979;
    for (uint32_t y = 0; y < kMoveH; ++y)
        for (uint32_t x = 0; x < kMoveW; ++x) {
            const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / glm::dvec2(kMoveW, kMoveH) * 2.0 - 1.0;
            const glm::dvec3 dir(ndc.x * th * aspect, -ndc.y * th, -1.0); // View depth 1.
            const glm::dvec3 on_wall = glm::dvec3(camera_x, 0, 0) + kWall * dir;
            const glm::dvec3 seen = glm::dvec3(camera_x, 0, 0) + kPath * dir; // The mirror's virtual image.
            const bool mirror = on_wall.y > 0.0;
            const float light = float(0.6 + 0.3 * std::sin(2.0 * kPi * on_wall.x / 1.7));
            const float albedo = mirror ? 0.3f : 0.8f;
            const float mirror_light = mirror ? float(0.5 + 0.3 * std::sin(2.0 * kPi * seen.x / 2.5)) : 0.f;
            const float reflected = mirror ? float(0.2 + 0.1 * std::cos(2.0 * kPi * seen.x / 2.0)) : 0.f;
            for (int c = 0; c < 3; ++c) {
                v.colour.at(x, y)[c] = albedo * light + reflected + mirror_light;
                v.albedo.at(x, y)[c] = albedo;
                v.reflected.at(x, y)[c] = reflected;
                v.mirror_light.at(x, y)[c] = mirror_light;
                v.mirror_albedo.at(x, y)[c] = 1.f;
            }
            v.albedo.at(x, y)[3] = v.mirror_albedo.at(x, y)[3] = 1.f;
            v.colour.at(x, y)[3] = v.mirror_light.at(x, y)[3] = 0.f; // Noise-free.
            const float nd[4] = {0.f, 0.f, 1.f, float(kWall * glm::length(dir))};
            std::copy(nd, nd + 4, v.normal_depth.at(x, y));
            if (mirror) {
                const float mnd[4] = {0.f, 0.f, 1.f, float(kPath * glm::length(dir))};
                std::copy(mnd, mnd + 4, v.mirror_nd.at(x, y));
            }
        }
    return v;
}

// RMSE over the pixels of the wall (mirror: false) or the mirror (true), away from the left and
// right edges (what comes into view has no history).
double region_rmse(const ImageF& test, const ImageF& reference, bool mirror) {
    double sum = 0.0;
    size_t n = 0;
    for (uint32_t y = 0; y < kMoveH; ++y)
        for (uint32_t x = 4; x + 4 < kMoveW; ++x) {
            if ((y < kMoveH / 2) != mirror)
                continue;
            for (int c = 0; c < 3; ++c) {
                const double d = double(test.at(x, y)[c]) - reference.at(x, y)[c];
                sum += d * d;
                ++n;
            }
        }
    return std::sqrt(sum / double(n));
}

// Issue 18's fly-over: the moving camera's reprojected history must be the previous frame's
// picture of the same points. Two noise-free frames, the camera moved 1.37 pixels (at the wall)
// sideways, temporal pass only and no history clamp (nothing is dropped): the second frame's
// output is the mean of its input and the reprojected history, so it equals its input when the
// reprojection is right. On the mirror what moves is its virtual image (0.78 pixels), not the
// mirror. The same pair without reprojection (the history read at the same pixel) is the scale.
TEST_F(DenoiserTest, MovedCameraReprojectsTheHistoryOfTheSamePoints) {
    const double pixel = 2.0 * std::tan(glm::radians(double(kMoveFov)) * 0.5) * 8.0 / kMoveH; // At the wall.
    const double step = 1.37 * pixel;
    MovedView before = moved_view(0.0), after = moved_view(step);
    // One sample per pixel (own variance unknown): a moving camera's noise-free pixels of several
    // samples take no illumination history (MovingCameraWithSeveralSamplesTakesNoIlluminationHistory).
    set_one_sample(before.colour);
    set_one_sample(after.colour);
    const glm::dmat4 prev = glm::lookAt(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    const glm::dmat4 cur = glm::lookAt(glm::dvec3(step, 0, 0), glm::dvec3(step, 0, -1), glm::dvec3(0, 1, 0));
    DenoiseSettings s;
    s.iterations = 0;
    s.history_clamp = false;
    const auto second_frame = [&](const glm::mat4& reproject) {
        Denoiser denoiser(*m_ctx, kMoveW, kMoveH);
        const MirrorImagesF m0{before.mirror_light, before.mirror_albedo, before.mirror_nd};
        const MirrorImagesF m1{after.mirror_light, after.mirror_albedo, after.mirror_nd};
        denoise_on_host(*m_ctx, denoiser, before.colour, before.albedo, before.normal_depth, s, glm::mat4(1.f),
                        kMoveFov, &before.reflected, &m0);
        return denoise_on_host(*m_ctx, denoiser, after.colour, after.albedo, after.normal_depth, s, reproject,
                               kMoveFov, &after.reflected, &m1);
    };
    const ImageF moved = second_frame(reprojection_matrix(prev, cur, kMoveFov, kMoveW, kMoveH));
    const ImageF unmoved = second_frame(glm::mat4(1.f));
    const double wall = region_rmse(moved, after.colour, false), mirror = region_rmse(moved, after.colour, true);
    const double wall_scale = region_rmse(unmoved, after.colour, false);
    const double mirror_scale = region_rmse(unmoved, after.colour, true);
    std::printf("moved camera, second frame: wall RMSE %.4f (not reprojected %.4f), mirror %.4f (%.4f)\n", wall,
                wall_scale, mirror, mirror_scale);
    EXPECT_LT(wall, 0.2 * wall_scale);
    EXPECT_LT(mirror, 0.2 * mirror_scale);
    EXPECT_LT(wall, 0.02); // Bilinear taps of the 6-pixel period: 0.011; a nearest tap: more.
    EXPECT_LT(mirror, 0.025);
}

// Under a moving camera, pixels of several samples weigh reprojected illumination history by its
// resampling error against their own noise (tests/render/denoiser_history_test.cpp); these are
// noise-free (variance 0), so history can only cost: they start again. One sample still
// accumulates. The first frame here is half as bright: history shows as an error on the wall.
TEST_F(DenoiserTest, MovingCameraWithSeveralSamplesTakesNoIlluminationHistory) {
    const double pixel = 2.0 * std::tan(glm::radians(double(kMoveFov)) * 0.5) * 8.0 / kMoveH; // At the wall.
    const double step = 1.37 * pixel;
    const glm::dmat4 prev = glm::lookAt(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    const glm::dmat4 cur = glm::lookAt(glm::dvec3(step, 0, 0), glm::dvec3(step, 0, -1), glm::dvec3(0, 1, 0));
    DenoiseSettings s;
    s.iterations = 0;
    s.history_clamp = false;
    const auto wall_error = [&](bool one_sample) {
        MovedView before = moved_view(0.0), after = moved_view(step);
        for (uint32_t y = 0; y < kMoveH; ++y)
            for (uint32_t x = 0; x < kMoveW; ++x)
                for (int c = 0; c < 3; ++c)
                    before.colour.at(x, y)[c] *= 0.5f;
        if (one_sample) {
            set_one_sample(before.colour);
            set_one_sample(after.colour);
        }
        Denoiser denoiser(*m_ctx, kMoveW, kMoveH);
        denoise_on_host(*m_ctx, denoiser, before.colour, before.albedo, before.normal_depth, s, glm::mat4(1.f),
                        kMoveFov, &before.reflected, nullptr);
        const ImageF out = denoise_on_host(*m_ctx, denoiser, after.colour, after.albedo, after.normal_depth, s,
                                           reprojection_matrix(prev, cur, kMoveFov, kMoveW, kMoveH), kMoveFov,
                                           &after.reflected, nullptr);
        return region_rmse(out, after.colour, false);
    };
    const double several = wall_error(false), one = wall_error(true);
    std::printf("moved camera after a darker frame: wall RMSE %.4f (several samples), %.4f (one)\n", several, one);
    EXPECT_LT(several, 0.005);
    EXPECT_GT(one, 10.0 * several + 0.01);
}

TEST(DenoiserReprojection, StillCameraIsIdentityAndMovedCameraShiftsPixels) {
    const glm::dmat4 view = glm::lookAt(glm::dvec3(1, 2, 3), glm::dvec3(1, 2, -5), glm::dvec3(0, 1, 0));
    const glm::mat4 still = reprojection_matrix(view, view, 60.f, 64, 32);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(still[c][r], c == r ? 1.f : 0.f, 1e-5);
    // The camera moved 1 block right since the previous frame (looking down -z, fov 90 degrees,
    // 64x64): a point at depth 4 seen at the centre pixel column 32 was seen by the previous
    // camera 1 block to its right, i.e. at 32 + (1 / (4 tan 45)) * 32 = 40.
    const glm::dmat4 prev = glm::lookAt(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    const glm::dmat4 cur = glm::lookAt(glm::dvec3(1, 0, 0), glm::dvec3(1, 0, -1), glm::dvec3(0, 1, 0));
    const glm::mat4 m = reprojection_matrix(prev, cur, 90.f, 64, 64);
    const float d = 4.f;
    const glm::vec4 p = m * glm::vec4(32.f * d, 32.f * d, d, 1.f);
    EXPECT_NEAR(p.x / p.z, 40.f, 1e-3);
    EXPECT_NEAR(p.y / p.z, 32.f, 1e-3);
    EXPECT_NEAR(p.z, d, 1e-4);
}

} // namespace
} // namespace vx::render
