// Watertightness: a wall of greedy quads of many sizes, crossing chunk seams, seen at grazing
// angles. Behind its front layer lies a marker layer; a ray that slips through a crack between
// front quads (T-junctions, chunk seams) would show the marker or the sky. Every pixel whose ray
// meets the front plane well inside the wall must show one of the front block colours.
#include <random>

#include "scene_util.h"

namespace vx::render {
namespace {

using test::RendererTest;

constexpr int64_t kX0 = -64, kX1 = 96, kY0 = -48, kY1 = 48; // Wall extent; front layer z = 0.

std::vector<world::BlockId> front_ids() {
    std::vector<world::BlockId> ids;
    for (const char* n : {"stone", "dirt", "grass", "sand", "snow", "wood"})
        ids.push_back(test::block_id(n));
    return ids;
}

world::World wall_world() {
    world::World w;
    const std::vector<world::BlockId> ids = front_ids();
    std::mt19937 rng(7);
    // Painter's rectangles of random sizes: greedy quads from 1x1 to 32-long strips.
    test::fill_box(w, {kX0, kY0, 0}, {kX1, kY1, 1}, ids[0]);
    for (int i = 0; i < 300; ++i) {
        const int64_t x = kX0 + int64_t(rng() % uint32_t(kX1 - kX0)), y = kY0 + int64_t(rng() % uint32_t(kY1 - kY0));
        const int64_t sx = 1 + rng() % 20, sy = 1 + rng() % 20;
        test::fill_box(w, {x, y, 0}, {std::min(x + sx, kX1), std::min(y + sy, kY1), 1}, ids[rng() % ids.size()]);
    }
    test::fill_box(w, {kX0, kY0, 1}, {kX1, kY1, 2}, test::block_id("lamp")); // The marker layer.
    return w;
}

void check_view(Renderer& r, const Camera& cam, const char* name) {
    RenderSettings s;
    s.width = s.height = 128;
    s.mode = ShadingMode::Flat;
    s.sky = {1.f, 1.f, 1.f};
    const RenderImage img = r.render(s, cam);
    test::maybe_save(img, name);
    const glm::dvec3 eye = test::eye_of(cam);
    int checked = 0, leaks = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const glm::dvec3 d = test::primary_dir(cam, x, y, img.width, img.height);
            if (d.z <= 0)
                continue;
            const glm::dvec3 p = eye + d * (-eye.z / d.z);
            const double m = 0.25;
            if (p.x < kX0 + m || p.x > kX1 - m || p.y < kY0 + m || p.y > kY1 - m)
                continue;
            ++checked;
            bool front = false;
            for (world::BlockId id : front_ids())
                front |= test::rgb_near(img.at(x, y), world::BlockRegistry::default_registry().info(id).albedo, 1);
            if (!front && ++leaks <= 5)
                ADD_FAILURE() << name << ": pixel " << x << "," << y << " is not a front block colour";
        }
    EXPECT_EQ(leaks, 0) << name;
    EXPECT_GT(checked, 1000) << name << ": the view must see much of the wall";
}

TEST_F(RendererTest, GreedyWallsAcrossChunkSeamsHaveNoCracks) {
    test::load_meshes(*m_renderer, test::mesh_world(wall_world()));
    // Grazing along x (across the x seams), along y (across the y seams), and straight down a seam.
    check_view(*m_renderer, Camera::look_at({-70.3, 0.37, -0.9}, {60.0, 3.1, 1.6}, {0, 1, 0}, 40.f), "cracks_x");
    check_view(*m_renderer, Camera::look_at({5.41, -60.2, -0.8}, {7.0, 60.0, 1.1}, {0, 0, 1}, 40.f), "cracks_y");
    check_view(*m_renderer, Camera::look_at({0.0, -20.0, -1.5}, {0.0, 40.0, 0.0}, {0, 0, 1}, 50.f), "cracks_seam");
    // Head-on with pixel centres landing on integer coordinates: every ray meets the wall on a
    // quad edge or corner (tan 45 deg * 64 = half the image width).
    check_view(*m_renderer, Camera::look_at({16.5, 0.5, -64.0}, {16.5, 0.5, 0.0}, {0, 1, 0}, 90.f), "cracks_edges");
}

} // namespace
} // namespace vx::render
