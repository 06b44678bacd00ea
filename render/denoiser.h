#pragma once
// The guided denoiser: temporal accumulation with reprojection (bilinear history taps, each
// tested for the same plane; a mirror's picture follows its virtual image and, while the
// camera moves, keeps at most 2 frames; while it moves, pixels of several samples weigh their
// illumination history by its resampling error against their own noise) and luminance moments
// for the variance, then an
// edge-avoiding a-trous wavelet filter guided by normal, depth and luminance variance, on
// albedo-demodulated illumination (SVGF: Schied et al. 2017; a-trous: Dammertz et
// al. 2010). The primary hit's diffuse lighting is filtered with the primary hit's guides, the
// first mirror bounce's diffuse lighting (when given) the same way with the reflected surface's
// own guides (its normal, the path's length; demodulated by its albedo); the rest of the
// reflected part (emission, sky, haze, deeper bounces) is accumulated over frames and added back
// unfiltered, so it stays sharp. The running means are 32-bit floats (a half float's mantissa
// loses a long mean's updates: docs/render_report.md, stop 21). All histories are clamped
// (DenoiseSettings::history_clamp) so changed light leaves no ghost. The luminance weight's variance
// is the pixels' own (from their light samples, render/gbuffer.h; averaged over 5x5 pixels of the
// surface and over the history), so the filter fades as samples grow; at 1 sample it is unknown:
// the 3x3 spatial estimate, which also counts pixel-sized detail as noise
// (docs/render_report.md), then from 4 frames of history SVGF's temporal moments. The first pass
// compares neighbours with the centre's 3x3-blurred luminance, not its own noisy one, so an
// outlier pixel is filtered too. The ray tracer's occluder distance and sun flag (reflected's
// a, render/gbuffer.h) steer the primary filter: where the nearest occluders are many pixels
// away the first passes trust the variance less (the light is smooth), and no tap crosses a sun
// shadow's edge. Compute shaders shaders/denoise_temporal.comp and shaders/denoise_atrous.comp.
//
// Inputs are the G-buffer of a frame (any producer: the ray tracer, or an image uploaded by
// denoise_on_host): storage images in VK_IMAGE_LAYOUT_GENERAL, written before record() with a
// barrier to compute-shader reads the caller records:
//   colour        RGBA16F  noisy linear HDR radiance (rgb) and the variance of the luminance of
//                          its diffuse part (colour - reflected) over albedo (a; < 0: unknown,
//                          estimated from the 3x3 neighbourhood),
//   reflected     RGBA16F  the part of colour not filtered with the primary hit's guides
//                          (emission, mirror bounces; rgb): accumulated over frames only,
//                          except mirror light x mirror albedo; a: the occluder distance and
//                          sun flag of render/gbuffer.h (0: no guide, the filter as without),
//   mirror_light, mirror_albedo, mirror_normal_depth (optional, all or none): the first
//                          mirror bounce's diffuse lighting over its surface's albedo (RGBA16F,
//                          a: variance as colour's), that albedo (RGBA8) and that surface's
//                          normal and path length (RGBA16F; w <= 0: none), render/gbuffer.h
//                          bindings 7-9. Without them the reflected part is not filtered.
//   albedo        RGBA8    linear albedo of the primary hit (UNORM),
//   normal_depth  RGBA16F  world-space unit normal (xyz) and the distance along the primary
//                          ray to the hit in blocks (w); w <= 0 marks a miss (sky: passed
//                          through). The ray tracer's G-buffer (render/gbuffer.h) as is.
// Outputs, in GENERAL layout, written by compute shaders (the caller barriers before reading):
// output(), RGBA16F linear HDR radiance, and the 8-bit image as the ray tracer would write it
// (vx_display: exposure, tone curve, sRGB; shaders/shared/tonemap.h) into
// DenoiseInputs::ldr_target, or ldr().
// Main thread only.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "render/image_metrics.h"
#include "render/resources.h"

namespace vx::render {

struct DenoiseSettings {
    uint32_t iterations = 5;        // A-trous passes (steps 1, 2, 4, 8, 16 pixels); 0: temporal only.
    float sigma_normal = 128.f;     // Exponent of the normal weight.
    float sigma_depth = 1.f;        // Scale of the depth weight against the depth gradient.
    float sigma_luminance = 4.f;    // Scale of the luminance weight against the std deviation.
    // The same from gpu::kDenoiseManySamples first-hit shadow samples per pixel. SVGF's 4 is for
    // a variance from a sample or two; from 16 the variance is measured well, and a wide stop
    // takes light detail a few deviations deep (a block's own shade) for noise. Denoised over
    // raw RMSE at 16 / 25 spp, lavapipe terrain 0.925 -> 0.880 / 1.043 -> 0.945; H200 seed
    // scene, mirror blocks 1.013 -> 0.976 / 1.038 -> 0.992, glazed under the thesis's light
    // 1.124 -> 1.036 / 1.127 -> 1.043 (docs/render_report.md, stop 41).
    float sigma_luminance_many = 2.5f;
    // Frames averaged at most by the temporal pass (a still camera converges to a running mean
    // of this many frames, then an exponential average with alpha 1/max_history). 1: no
    // temporal accumulation.
    uint32_t max_history = 32;
    // Drop illumination history that this frame's neighbourhood says is stale (its mean leaves
    // the history's by 4.5 standard errors) and clamp the reflected part's history to this
    // frame's neighbourhood (shaders/denoise_temporal.comp): a light change (an edit's new
    // shadow, a reflection sliding over a mirror) is gone within a frame instead of fading over
    // max_history. Costs 9-15% of a still camera's 8-frame RMSE (docs/render_report.md). Off:
    // SVGF's plain accumulation.
    bool history_clamp = true;
};

// Image views of one frame's G-buffer (see the file comment for formats and layouts).
struct DenoiseInputs {
    VkImageView colour = VK_NULL_HANDLE;
    VkImageView albedo = VK_NULL_HANDLE;
    VkImageView normal_depth = VK_NULL_HANDLE;
    VkImageView reflected = VK_NULL_HANDLE;
    VkImageView mirror_light = VK_NULL_HANDLE;
    VkImageView mirror_albedo = VK_NULL_HANDLE;
    VkImageView mirror_normal_depth = VK_NULL_HANDLE;
    // Maps (x d, y d, d, 1) of this frame's pixel centre (x, y) (pixels, row 0 at the top) at
    // view depth d to (x' d', y' d', d', 1) of the previous frame: identity for a still camera.
    // See reprojection_matrix().
    glm::mat4 reproject{1.f};
    // The rotation from world to the previous frame's view space (history_rotation()): the
    // history's plane test compares world normals there. Identity: that view looks down -z
    // with +y up.
    glm::quat history_rotation{1.f, 0.f, 0.f, 0.f};
    float fov_y_degrees = 60.f; // The camera's (with the image's aspect: distances to depths).
    // RGBA8 UNORM storage view (GENERAL layout) for the 8-bit output; null: ldr().
    VkImageView ldr_target = VK_NULL_HANDLE;
    // Scale from radiance to the tone curve's input for the 8-bit output (vx_exposure_scale,
    // shaders/shared/tonemap.h). The HDR output() is not scaled.
    float exposure = 1.f;
    // Shadow samples per pixel at every primary hit (RenderSettings::shadow_samples); 0: unknown
    // or not the same everywhere (samples by weight), filtered as a few. From
    // gpu::kDenoiseManySamples (shaders/shared/denoise_types.h) a pixel's own light is trusted.
    uint32_t first_hit_samples = 0;
};

class Denoiser {
public:
    // Images for width x height frames. When memory runs out (logged) ready() is false: call
    // resize() again before record().
    Denoiser(Context& ctx, uint32_t width, uint32_t height);
    // Only once no frame that recorded it is in flight (e.g. after Context::wait_idle): its
    // descriptor sets are freed at once.
    ~Denoiser();
    Denoiser(const Denoiser&) = delete;
    Denoiser& operator=(const Denoiser&) = delete;

    // New images for width x height frames (the old ones retire with the frame); drops the history.
    void resize(uint32_t width, uint32_t height);
    uint32_t width() const { return m_width; }
    uint32_t height() const { return m_height; }
    // Every image was allocated (record() may be called).
    bool ready() const { return m_ready; }
    // Its pipelines and descriptor sets were made; false (out of memory, logged): destroy it.
    bool valid() const { return m_valid; }

    // Records the temporal pass and settings.iterations a-trous passes into `cmd` (a frame's
    // command buffer: descriptor sets are per frame slot, so at most kFramesInFlight frames may
    // be in flight). The inputs must stay alive until the frame completes.
    void record(VkCommandBuffer cmd, const DenoiseInputs& inputs, const DenoiseSettings& settings);
    // The next record() starts without history (a cut, a new scene).
    void reset_history() { m_history_valid = false; }
    const Image& output() const { return m_output; }
    const Image& ldr() const { return m_ldr; }

private:
    void create_images();
    bool create_pipelines();
    bool allocate_set(const VkDescriptorSetAllocateInfo& ai, VkDescriptorSet& set);
    bool m_ready = false;
    bool m_valid = false;
    void write_sets(const DenoiseInputs& inputs, uint32_t slot);

    Context* m_ctx;
    uint32_t m_width, m_height;
    // Ping-pong: read [m_parity], write the other. Moments: luminance m1, m2 (SVGF's variance).
    // Reflected: the reflected part's running mean; mirror: the mirror light's.
    std::array<Image, 2> m_history, m_history_nd, m_moments, m_history_reflected, m_history_mirror;
    std::array<Image, 2> m_ping, m_mirror_ping;   // A-trous iterations alternate between these.
    Image m_reflected; // This frame's accumulated reflected part (temporal pass -> last pass).
    Image m_output, m_ldr;
    uint32_t m_parity = 0;
    bool m_history_valid = false;
    bool m_initialised = false; // Images moved to GENERAL.
    VkDescriptorSetLayout m_temporal_layout = VK_NULL_HANDLE, m_atrous_layout = VK_NULL_HANDLE;
    VkPipelineLayout m_temporal_pl = VK_NULL_HANDLE, m_atrous_pl = VK_NULL_HANDLE;
    VkPipeline m_temporal = VK_NULL_HANDLE, m_atrous = VK_NULL_HANDLE;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    // Per frame slot: temporal set for each history parity, a-trous set for each ping direction.
    std::array<std::array<VkDescriptorSet, 2>, kFramesInFlight> m_temporal_sets{}, m_atrous_sets{};
};

// Reprojection for a pinhole camera: `prev_view_from_world` and `view_from_world` are the
// cameras' view matrices (right-handed, looking down -z, any common world frame, e.g. relative
// to the current camera's block), fov_y in degrees, images width x height.
glm::mat4 reprojection_matrix(const glm::dmat4& prev_view_from_world, const glm::dmat4& view_from_world,
                              float fov_y_degrees, uint32_t width, uint32_t height);

// The rotation part of a view matrix (DenoiseInputs::history_rotation).
glm::quat history_rotation(const glm::dmat4& prev_view_from_world);

// The first mirror bounce's G-buffer images for denoise_on_host (DenoiseInputs says what they hold).
struct MirrorImagesF {
    const ImageF& light;
    const ImageF& albedo;
    const ImageF& normal_depth;
};

// Host round trip for tests and benchmarks: uploads the images (colour, normal_depth,
// reflected and the mirror's light and normal_depth as RGBA16F, albedos as RGBA8 from 0..1
// floats; no `reflected`: zero; no `mirror`: the reflected part is not filtered), runs
// `denoiser` once (it keeps its history between calls) and reads the output back. Waits for
// the GPU. Sizes must match the denoiser. `first_hit_samples`: DenoiseInputs's.
ImageF denoise_on_host(Context& ctx, Denoiser& denoiser, const ImageF& colour, const ImageF& albedo,
                       const ImageF& normal_depth, const DenoiseSettings& settings,
                       const glm::mat4& reproject = glm::mat4(1.f), float fov_y_degrees = 60.f,
                       const ImageF* reflected = nullptr, const MirrorImagesF* mirror = nullptr,
                       const glm::quat& history_rotation = glm::quat(1.f, 0.f, 0.f, 0.f),
                       uint32_t first_hit_samples = 0);

} // namespace vx::render
