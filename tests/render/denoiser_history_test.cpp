// The denoiser's history under a moving camera, on synthetic G-buffers of a floor seen from a
// pitched, turning camera: the history must be the previous frame's picture of the same points
// (reprojection with pitch and yaw, the plane test's rotation), and never that of another
// surface of the same orientation (a raised layer of blocks one block above the floor).
#include <cmath>
#include <cstdio>

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
};

// Light on the floor at world (x, z), `detail` times: 1, smooth with a period of many pixels;
// more: finer (a few pixels); 0: uniform.
float floor_light(double x, double z, float offset, double detail = 1.0) {
    return float(0.5 + 0.25 * std::sin(detail * x / 4.0) * std::cos(detail * z / 5.0)) + offset;
}

// The ray tracer's picture (shaders/raygen.rgen primary_dir) of the floor y = floor_y (normal
// +y) from `v`, no reflections; `variance`: the pixels' own (render/gbuffer.h; -1: one sample).
// Pixels that miss show black sky (no surface).
Frame render_floor(const View& v, double floor_y, float light_offset, double detail = 1.0, float variance = -1.f) {
    Frame f{ImageF::make(kW, kH), ImageF::make(kW, kH), ImageF::make(kW, kH)};
    const glm::dvec3 fwd = glm::normalize(v.target - v.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(0, 1, 0)));
    const glm::dvec3 up = glm::cross(right, fwd);
    const double th = std::tan(glm::radians(double(kFov)) * 0.5), aspect = double(kW) / kH;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const glm::dvec2 ndc = (glm::dvec2(x, y) + 0.5) / glm::dvec2(kW, kH) * 2.0 - 1.0;
            const glm::dvec3 dir = glm::normalize(fwd + ndc.x * th * aspect * right - ndc.y * th * up);
            const double t = (floor_y - v.eye.y) / dir.y;
            if (!(t > 0.0))
                continue;
            const glm::dvec3 hit = v.eye + t * dir;
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

} // namespace
} // namespace vx::render
