#pragma once
// Test scenes for the renderer: build a World by boxes, mesh it with the greedy mesher, load the
// meshes into a Renderer. Also a Renderer fixture that checks the validation layer stayed silent.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render_test_util.h"
#include "shaders/shared/tonemap.h"
#include "world/mesh/edit_mesher.h"
#include "world/world.h"

namespace vx::render::test {

inline world::BlockId block_id(const char* name) {
    auto id = world::BlockRegistry::default_registry().find(name);
    EXPECT_TRUE(id.has_value()) << name;
    return id.value_or(1);
}

// Fills the world box [lo, hi) (block coordinates) with `id`.
inline void fill_box(world::World& w, world::BlockPos lo, world::BlockPos hi, world::BlockId id) {
    for (int64_t z = lo.z; z < hi.z; ++z)
        for (int64_t y = lo.y; y < hi.y; ++y)
            for (int64_t x = lo.x; x < hi.x; ++x)
                w.set_block({x, y, z}, id);
}

// A pool in a stone basin: floor y in [0, 1), rim |x| or |z| in [12, 13) up to the surface (no way
// in for light through the water's sides), water x, z in [-12, 12), y in [1, 7).
inline world::World stone_basin() {
    world::World w;
    fill_box(w, {-13, 0, -13}, {13, 7, 13}, block_id("stone"));
    fill_box(w, {-12, 1, -12}, {12, 7, 12}, block_id("water"));
    return w;
}

// The default registry with a perfect mirror added (reflectivity 1: no light of its own), set on
// `r`; its id.
inline world::BlockId set_perfect_mirror(Renderer& r) {
    world::BlockRegistry registry = world::BlockRegistry::default_registry();
    world::BlockInfo perfect;
    perfect.name = "perfect mirror";
    perfect.albedo = {1.f, 1.f, 1.f};
    perfect.reflectivity = 1.f;
    const world::BlockId id = registry.add(perfect).value();
    r.set_registry(registry);
    return id;
}

// Hilly ground over 2 x 1 x 2 chunks (x, z in [-32, 32), y in [0, 32)); the ground at column
// (10, 10) is 9 blocks high.
inline world::World hills() {
    world::World w;
    const world::BlockId grass = block_id("grass"), dirt = block_id("dirt");
    for (int64_t z = -32; z < 32; ++z)
        for (int64_t x = -32; x < 32; ++x) {
            const int64_t h = 6 + int64_t(4 * std::sin(double(x) * 0.2) + 3 * std::cos(double(z) * 0.15));
            for (int64_t y = 0; y < h; ++y)
                w.set_block({x, y, z}, y + 1 == h ? grass : dirt);
        }
    return w;
}

// Greedy meshes of every chunk of `w`.
inline world::MeshMap mesh_world(const world::World& w) {
    world::EditMesher mesher;
    world::MeshMap meshes;
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) { mesher.mesh_chunk(w, c, meshes); });
    return meshes;
}

inline void load_meshes(Renderer& r, const world::MeshMap& meshes) {
    for (const auto& [c, mc] : meshes)
        r.set_chunk(c, mc.mesh);
}

// The slices an edit changed, as set_chunk takes them (empty when the mesh was made whole).
inline std::span<const int> changed_slices(const world::SliceUpdate& u) {
    return u.full ? std::span<const int>{} : std::span<const int>(u.slices.data(), size_t(u.count));
}

// The byte a linear value in 0..1 becomes in an R8G8B8A8_UNORM image (round to nearest).
inline int unorm8(float v) { return int(std::lround(std::clamp(v, 0.f, 1.f) * 255.f)); }

inline ::testing::AssertionResult rgb_near(glm::u8vec4 px, glm::vec3 expected, int tolerance = 1) {
    for (int i = 0; i < 3; ++i)
        if (std::abs(int(px[i]) - unorm8(expected[i])) > tolerance)
            return ::testing::AssertionFailure() << "pixel (" << int(px.r) << "," << int(px.g) << "," << int(px.b)
                                                 << ") expected (" << unorm8(expected.r) << "," << unorm8(expected.g)
                                                 << "," << unorm8(expected.b) << ")";
    return ::testing::AssertionSuccess();
}

// Writes `img` to $VX_TEST_PNG_DIR/<name>.png when that variable is set (for looking at failures).
inline void maybe_save(const RenderImage& img, const char* name) {
    if (const char* dir = std::getenv("VX_TEST_PNG_DIR")) {
        EXPECT_TRUE(write_png(std::string(dir) + "/" + name + ".png", img).ok());
    }
}

// The mean of `frames` accumulated frames of `s` at `spp` shadow samples, no filter and no
// history clamp unless `clamp`: a converged reference as the bench makes it
// (tools/bench_render_frames.h). The seed and the rest of `s` as given.
inline RenderImage accumulated(Renderer& r, RenderSettings s, const Camera& cam, uint32_t frames, uint32_t spp,
                               bool clamp = false) {
    s.shadow_samples = spp;
    s.accumulate = frames;
    s.denoise = false;
    s.history_clamp = clamp;
    RenderImage img;
    for (uint32_t i = 0; i < frames; ++i)
        img = r.render(s, cam);
    return img;
}

// Full mode's output for linear radiance c at the default exposure.
inline glm::vec3 full_output(glm::vec3 c) { return gpu::vx_display(c, gpu::vx_exposure_scale(Exposure{}.ev100)); }

// Linear radiance from Full mode's display byte (the tone curve and the sRGB encoding inverted by
// bisection: both rise), at exposure `ev100` (the default's unless given).
inline float linear_of(uint8_t byte, float ev100 = Exposure{}.ev100) {
    const float scale = gpu::vx_exposure_scale(ev100);
    float lo = 0.f, hi = 1e3f;
    for (int i = 0; i < 60; ++i) {
        const float mid = 0.5f * (lo + hi);
        (gpu::vx_display(glm::vec3(mid), scale).x * 255.f < float(byte) ? lo : hi) = mid;
    }
    return 0.5f * (lo + hi);
}

// The index of refraction of a see-through block of normal-incidence reflectance r: the n with
// ((n - 1) / (n + 1))^2 = r.
inline double index_of(double r) {
    const double s = std::sqrt(std::max(r, 0.0));
    return (1.0 + s) / (1.0 - s);
}

// The share of light an interface into a medium of relative index n >= 1 mirrors, met at angle
// acos(cos_i) to its normal: Fresnel's equations in their angle form (Born & Wolf 1.5.3; the
// shaders use the cosine form, shaders/shared/optics.glsl), with Snell's law for the refracted
// angle.
inline double fresnel_eta(double n, double cos_i) {
    if (n == 1.0)
        return 0.0;
    if (cos_i >= 1.0)
        return (n - 1.0) * (n - 1.0) / ((n + 1.0) * (n + 1.0));
    if (cos_i <= 0.0)
        return 1.0;
    const double ti = std::acos(cos_i), tt = std::asin(std::sin(ti) / n);
    const double perp = std::sin(ti - tt) / std::sin(ti + tt), par = std::tan(ti - tt) / std::tan(ti + tt);
    return 0.5 * (perp * perp + par * par);
}

// The share of light a see-through block of reflectivity r (its reflectance at normal incidence)
// mirrors at angle acos(cos_i) to the face's normal, met from air: fresnel_eta at its index n,
// ((n - 1) / (n + 1))^2 = r.
inline double fresnel(double r, double cos_i) { return r <= 0.0 ? 0.0 : fresnel_eta(index_of(r), cos_i); }

// The cosine of the refracted ray's angle to the normal where a ray from air meets a block of
// reflectivity r at cosine cos_i (Snell's law: sin_t = sin_i / n).
inline double refracted_cos(double r, double cos_i) {
    const double sin_t = std::sqrt(std::max(1.0 - cos_i * cos_i, 0.0)) / index_of(r);
    return std::sqrt(1.0 - sin_t * sin_t);
}

// Full mode, 32x32, `samples` per pixel (shadow rays of each light, sky rays), no reflections,
// no area light: sun, sky and emitters only.
inline RenderSettings daylight(uint32_t samples = 8) {
    RenderSettings s;
    s.width = 32;
    s.height = 32;
    s.mode = ShadingMode::Full;
    s.shadow_samples = samples;
    s.max_bounces = 0;
    s.light.emission = glm::vec3(0.f);
    return s;
}

// Full mode at 48x48, 4 samples, lit by the sun alone from `sun` (no sky term, no area light, no
// haze, no reflections).
inline RenderSettings sun_alone(glm::vec3 sun) {
    RenderSettings s = daylight(4);
    s.width = 48;
    s.height = 48;
    s.haze.enabled = false;
    s.sky_light = 0.f;
    s.sun.direction = sun;
    return s;
}

// A renderer on the test device with the validation layer on; `ci`'s other fields as given.
inline std::unique_ptr<Renderer> make_renderer(RendererCreateInfo ci = {}) {
    ci.validation = true;
    ci.sync_validation = ci.sync_validation || std::getenv("VX_SYNC_VALIDATION") != nullptr;
    ci.device = test_device_choice();
    auto r = Renderer::create(ci);
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? std::move(*r) : nullptr;
}

// The frame of `s` from `cam` that a new renderer (the test device, validation on) holding
// `meshes` renders: what a renderer that has met a failure should render again. Empty (with a
// test failure) when it cannot.
inline RenderImage fresh_render(const world::MeshMap& meshes, const RenderSettings& s, const Camera& cam) {
    std::unique_ptr<Renderer> fresh = make_renderer();
    if (!fresh)
        return {};
    load_meshes(*fresh, meshes);
    Result<RenderImage> img = fresh->try_render(s, cam);
    EXPECT_TRUE(img) << img.error();
    EXPECT_EQ(fresh->validation_errors(), 0u);
    return img ? std::move(*img) : RenderImage{};
}

// The mean of an image's bytes (alpha included): how two renders of one view compare in light
// where their noise differs.
inline double mean_byte(const RenderImage& img) {
    double m = 0;
    for (uint8_t b : img.rgba)
        m += b / double(img.rgba.size());
    return m;
}

// Bytes that differ between two images of the same size.
inline int differing_bytes(const RenderImage& a, const RenderImage& b) {
    EXPECT_EQ(a.rgba.size(), b.rgba.size());
    int diff = 0;
    for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i)
        diff += a.rgba[i] != b.rgba[i];
    return diff;
}

// The largest difference of two images of the same size in 8-bit steps (any channel of any pixel):
// where a cell's float sums may take their hits in another order (the light cache), a step.
inline int largest_step(const RenderImage& a, const RenderImage& b) {
    EXPECT_EQ(a.rgba.size(), b.rgba.size());
    int worst = 0;
    for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i)
        worst = std::max(worst, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
    return worst;
}

// Out of memory for each of `resources` in turn (Context::fail_allocations) in a new renderer
// holding `meshes`: the frame of `s` from `cam` fails with a one-line error holding `message`; the
// next renders as a renderer that never failed does.
inline void expect_frame_failure_then_recovery(const world::MeshMap& meshes, const RenderSettings& s,
                                               const Camera& cam, std::initializer_list<const char*> resources,
                                               const std::string& message) {
    const RenderImage expected = fresh_render(meshes, s, cam);
    for (const char* resource : resources) {
        std::unique_ptr<Renderer> r = make_renderer();
        ASSERT_NE(r, nullptr);
        load_meshes(*r, meshes);
        r->fail_allocations(resource);
        Result<RenderImage> failed = r->try_render(s, cam);
        ASSERT_FALSE(failed) << resource;
        EXPECT_NE(failed.error().find(message), std::string::npos) << failed.error();
        EXPECT_EQ(failed.error().find('\n'), std::string::npos);
        r->fail_allocations("");
        Result<RenderImage> img = r->try_render(s, cam);
        ASSERT_TRUE(img) << img.error();
        EXPECT_EQ(differing_bytes(*img, expected), 0) << resource;
        EXPECT_EQ(r->validation_errors(), 0u) << resource;
    }
}

// The camera's eye in world blocks (Camera: a block and an offset in it).
inline glm::dvec3 eye_of(const Camera& c) { return glm::dvec3(c.block) + glm::dvec3(c.offset); }

// The unit direction of pixel (x, y)'s primary ray in a w x h image, as raygen_common.glsl's
// primary_dir() makes it from the camera's basis (render/renderer_frame.cpp, write_params).
inline glm::dvec3 primary_dir(const Camera& c, uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
    const glm::dvec3 f = glm::normalize(glm::dvec3(c.forward));
    const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(c.up)));
    const glm::dvec3 u = glm::cross(r, f);
    const double th = std::tan(glm::radians(double(c.fov_y_degrees)) * 0.5), aspect = double(w) / h;
    const double nx = (x + 0.5) / w * 2 - 1, ny = (y + 0.5) / h * 2 - 1;
    return glm::normalize(f + nx * th * aspect * r - ny * th * u);
}

// What d blocks of path through a see-through block of albedo a pass (Beer-Lambert: its albedo is
// one block's transmittance; shaders/shared/rt_common.glsl, vx_absorb), channel by channel.
inline glm::vec3 absorbed(glm::vec3 a, double d) {
    return {float(std::pow(double(a.r), d)), float(std::pow(double(a.g), d)), float(std::pow(double(a.b), d))};
}

// The length of the segment from p to q inside the box [lo, hi) (slab method; 0: it misses).
inline double path_in_box(glm::dvec3 p, glm::dvec3 q, glm::dvec3 lo, glm::dvec3 hi) {
    const glm::dvec3 d = q - p;
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (p[k] < lo[k] || p[k] > hi[k])
                return 0.0;
            continue;
        }
        const double a = (lo[k] - p[k]) / d[k], b = (hi[k] - p[k]) / d[k];
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
    }
    return t1 > t0 ? (t1 - t0) * glm::length(d) : 0.0;
}

// The share of an even sky's light on an upward face at `p` (its irradiance over pi L) that a box
// of a see-through block of albedo a, [lo, hi), lets through when p lies in it: the cosine-weighted
// mean over the hemisphere of a^(path to the box's side), by the midpoint rule in (cos^2, azimuth)
// (n x n cells; each cell is an equal share of the cosine-weighted hemisphere).
inline glm::vec3 sky_through_box(glm::dvec3 p, glm::dvec3 lo, glm::dvec3 hi, glm::vec3 a, int n = 400) {
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double u = (i + 0.5) / n, phi = 2.0 * 3.14159265358979 * (j + 0.5) / n;
            const double sin_t = std::sqrt(u), cos_t = std::sqrt(1.0 - u);
            const glm::dvec3 d(sin_t * std::cos(phi), cos_t, sin_t * std::sin(phi));
            double t = 1e30;
            for (int k = 0; k < 3; ++k)
                if (d[k] != 0.0)
                    t = std::min(t, ((d[k] > 0.0 ? hi[k] : lo[k]) - p[k]) / d[k]);
            sum += glm::dvec3(absorbed(a, t));
        }
    return glm::vec3(sum / double(n * n));
}

class RendererTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_renderer = make_renderer();
        ASSERT_NE(m_renderer, nullptr);
    }
    void TearDown() override {
        if (m_renderer) {
            EXPECT_EQ(m_renderer->validation_errors(), 0u);
            m_renderer.reset();
        }
    }
    std::unique_ptr<Renderer> m_renderer;
};

} // namespace vx::render::test
