// Secondary rays far from the camera: a flat slab seen from 2^13 to 2^20 blocks away, lit by an
// unoccluded light at a steep 60 degrees and a grazing 2 degrees, has no falsely shadowed pixel,
// and a mirror slab reflects only sky (no self-reflection). Camera-relative floats lose a bit per
// doubling of distance, so a fixed push-off of secondary-ray origins fails there (at 2^15 blocks
// one ulp is 2^-8, coarser than kSurfaceOffset); the shaders push off in ulps of the position.
#include <cmath>

#include "scene_util.h"
#include "shaders/shared/tonemap.h"

namespace vx::render {
namespace {

using test::RendererTest;

constexpr int64_t kHalf = 40; // The slab is 80 x 80 blocks across and one block thick.

// A slab whose lit face has outward normal `axis` * `sign`, centred on the world origin.
struct Slab {
    int axis;   // 0, 1, 2: x, y, z.
    int sign;   // +1 or -1.
    const char* block;

    glm::dvec3 normal() const {
        glm::dvec3 n(0.0);
        n[axis] = sign;
        return n;
    }
    // Two unit tangents of the face.
    glm::dvec3 tangent(int which) const {
        glm::dvec3 t(0.0);
        t[(axis + 1 + which) % 3] = 1.0;
        return t;
    }
    // The centre of the lit face (the slab occupies [0, 1) along the axis).
    glm::dvec3 face_centre() const {
        glm::dvec3 c(0.0);
        c[axis] = sign > 0 ? 1.0 : 0.0;
        return c;
    }
    world::World build() const {
        world::BlockPos lo(-kHalf), hi(kHalf);
        lo[axis] = 0;
        hi[axis] = 1;
        world::World w;
        test::fill_box(w, lo, hi, test::block_id(block));
        return w;
    }
};

// A camera `distance` blocks from the face centre, `view_deg` above the face (90: straight on),
// with a field of view that keeps every pixel on the slab: the view spans 10 sin(view) blocks each
// side of the centre across the tilt and 10 along it, inside the slab's 40.
Camera far_camera(const Slab& slab, double distance, double view_deg) {
    const double v = glm::radians(view_deg);
    const glm::dvec3 dir = std::sin(v) * slab.normal() + std::cos(v) * slab.tangent(0);
    const glm::dvec3 centre = slab.face_centre() + 0.3 * (slab.tangent(0) + slab.tangent(1));
    const float fov = float(glm::degrees(2.0 * std::atan(10.0 * std::sin(v) / distance)));
    const glm::vec3 up = view_deg == 90.0 ? glm::vec3(slab.tangent(1)) : glm::vec3(slab.normal());
    return Camera::look_at(centre + distance * dir, centre, up, fov);
}

// Visibility of a 2 x 2 light 1000 blocks from the face centre, `elevation_deg` above the face,
// seen from the side opposite the camera's tilt (so no ray runs along the view).
RenderSettings light_settings(const Slab& slab, double elevation_deg) {
    RenderSettings s;
    s.mode = ShadingMode::Visibility;
    s.shadow_samples = 16;
    s.max_bounces = 0;
    s.sky = {0.2f, 0.4f, 0.6f}; // Not grey: a pixel that misses the slab fails the test too.
    const double e = glm::radians(elevation_deg);
    const glm::dvec3 centre =
        slab.face_centre() + 1000.0 * (std::cos(e) * slab.tangent(1) + std::sin(e) * slab.normal());
    // Edges along tangent(0) and the normal: the light faces the slab; its lowest point is still
    // 1000 sin(2 deg) - 1 > 30 blocks above the face.
    const glm::dvec3 corner = centre - slab.tangent(0) - slab.normal();
    s.light.block = world::BlockPos(glm::floor(corner));
    s.light.offset = glm::vec3(corner - glm::floor(corner));
    s.light.edge_u = glm::vec3(2.0 * slab.tangent(0));
    s.light.edge_v = glm::vec3(2.0 * slab.normal());
    return s;
}

// Pixels not fully lit (visibility below 255, or not grey: a miss).
int shadowed_pixels(const RenderImage& img) {
    int n = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        n += img.rgba[i] != 255 || img.rgba[i + 1] != 255 || img.rgba[i + 2] != 255 ? 1 : 0;
    return n;
}

const Slab kSlabs[] = {{1, +1, "stone"}, {1, -1, "stone"}, {0, +1, "stone"}, {2, -1, "stone"}};

std::string where(const Slab& slab, int log2_distance, double view_deg) {
    return "face axis " + std::to_string(slab.axis) + (slab.sign > 0 ? "+" : "-") + ", 2^" +
           std::to_string(log2_distance) + " blocks, view " + std::to_string(int(view_deg)) + " deg";
}

TEST_F(RendererTest, FarSurfacesCastNoShadowOnThemselves) {
    for (const Slab& slab : kSlabs) {
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(slab.build()));
        for (int log2_distance = 13; log2_distance <= 20; ++log2_distance)
            for (double view_deg : {90.0, 30.0}) {
                const Camera cam = far_camera(slab, std::ldexp(1.0, log2_distance), view_deg);
                for (double elevation : {60.0, 2.0}) {
                    const RenderImage img = m_renderer->render(light_settings(slab, elevation), cam);
                    EXPECT_EQ(shadowed_pixels(img), 0)
                        << where(slab, log2_distance, view_deg) << ", light at " << elevation << " deg";
                }
            }
    }
}

// Control: the test sees shadows where they are. The light below the face lights nothing.
TEST_F(RendererTest, FarSurfaceLitFromBehindIsDark) {
    const Slab slab = kSlabs[0];
    test::load_meshes(*m_renderer, test::mesh_world(slab.build()));
    const Camera cam = far_camera(slab, std::ldexp(1.0, 17), 90.0);
    const RenderImage img = m_renderer->render(light_settings(slab, -2.0), cam);
    int dark = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        dark += img.rgba[i] == 0 && img.rgba[i + 1] == 0 && img.rgba[i + 2] == 0 ? 1 : 0;
    EXPECT_EQ(dark, int(img.width * img.height));
}

// Full mode's output of linear radiance c at the default exposure: exposed, tone-mapped, then
// sRGB encoded (the shaders' code).
float full_output(float c) {
    return gpu::vx_srgb_encode1(gpu::vx_tonemap1(c * gpu::vx_exposure_scale(Exposure{}.ev100)));
}

TEST_F(RendererTest, FarMirrorReflectsOnlySky) {
    for (const Slab& base : kSlabs) {
        Slab slab = base;
        slab.block = "mirror";
        m_renderer->clear_chunks();
        test::load_meshes(*m_renderer, test::mesh_world(slab.build()));
        RenderSettings s;
        s.mode = ShadingMode::Full;
        s.shadow_samples = 0;
        s.max_bounces = 1;
        // Only the reflected sky lights the mirror: no area light, no sun and no sky term (the
        // sky term would add 0.1 x albedo x sky through the mirror's diffuse part).
        s.light.emission = glm::vec3(0.f);
        s.sun.irradiance = glm::vec3(0.f);
        s.sky_light = 0.f;
        s.haze.enabled = false; // Exactly the sky, at any distance (haze_test.cpp has the haze).
        // Mirror reflectivity 0.9 (block_registry.cpp): a pixel is 0.9 x sky, exposed,
        // tone-mapped and sRGB encoded. A ray that
        // reflects off its own mirror gets 0.9 x (nothing after the last bounce): black.
        const glm::vec3 expected(full_output(0.9f * s.sky.r), full_output(0.9f * s.sky.g), full_output(0.9f * s.sky.b));
        for (int log2_distance = 13; log2_distance <= 20; ++log2_distance)
            for (double view_deg : {90.0, 30.0}) {
                const RenderImage img = m_renderer->render(s, far_camera(slab, std::ldexp(1.0, log2_distance), view_deg));
                int wrong = 0;
                for (uint32_t y = 0; y < img.height; ++y)
                    for (uint32_t x = 0; x < img.width; ++x)
                        wrong += test::rgb_near(img.at(x, y), expected) ? 0 : 1;
                EXPECT_EQ(wrong, 0) << where(slab, log2_distance, view_deg);
            }
    }
}

} // namespace
} // namespace vx::render
