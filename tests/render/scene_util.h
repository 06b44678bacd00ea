#pragma once
// Test scenes for the renderer: build a World by boxes, mesh it with the greedy mesher, load the
// meshes into a Renderer. Also a Renderer fixture that checks the validation layer stayed silent.

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render_test_util.h"
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

class RendererTest : public ::testing::Test {
protected:
    void SetUp() override {
        RendererCreateInfo ci;
        ci.validation = true;
        ci.sync_validation = std::getenv("VX_SYNC_VALIDATION") != nullptr;
        ci.device = test_device_choice();
        auto r = Renderer::create(ci);
        ASSERT_TRUE(r.ok()) << r.error();
        m_renderer = std::move(*r);
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
