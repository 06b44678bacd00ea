// The GPU material table (render/material_table.h): each see-through block's optics, worked out
// once on upload, are the ones the shaders used to work out per ray. No GPU.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_util.h"

#include "render/material_table.h"
#include "world/block_registry.h"

namespace vx::render {
namespace {

// The index's defining relation, ((n - 1) / (n + 1))^2 = r, holds across the valid range; r = 0
// gives exactly 1, which the shaders' Fresnel takes as "no interface" (vx_fresnel_eta: eta == 1).
TEST(MaterialTable, TheIndexOfRefractionReproducesTheReflectanceAtNormalIncidence) {
    EXPECT_EQ(refractive_index(0.f), 1.f);
    EXPECT_NEAR(refractive_index(0.02f), 1.3294f, 1e-4f); // Water.
    EXPECT_FLOAT_EQ(refractive_index(0.04f), 1.5f);      // Glass: sqrt 0.2, 1.2 / 0.8.
    for (float r : {1e-6f, 0.001f, 0.02f, 0.04f, 0.1f, 0.25f, 0.5f, 0.9f, 0.999f}) {
        const double n = refractive_index(r);
        EXPECT_NEAR((n - 1) * (n - 1) / ((n + 1) * (n + 1)), r, 2e-6 * std::max(1.0, 1000.0 * r)) << r;
        if (r < 0.999f) { // Clamped there: 0.999f is a little above 0.999.
            EXPECT_EQ(refractive_index(r), float(test::index_of(r))) << "the tests' own formula, at " << r;
        }
    }
    // Out of range (material_problem rejects it on the way in; the table must not make NaN of it).
    EXPECT_EQ(refractive_index(-1.f), 1.f);
    EXPECT_TRUE(std::isfinite(refractive_index(1.f)));
    EXPECT_EQ(refractive_index(1.f), refractive_index(0.999f));
}

// exp(-sigma d) is albedo^d: one block passes the albedo; a clear channel absorbs nothing (0
// exactly, so the shaders' "no 0 x infinity" rule applies to it); a black one is finite and passes
// nothing of a block.
TEST(MaterialTable, TheAbsorptionCoefficientPassesTheAlbedoPerBlock) {
    for (glm::vec3 a : {glm::vec3(0.77f, 0.95f, 0.99f), glm::vec3(0.85f, 0.9f, 0.95f), glm::vec3(0.01f, 0.5f, 1.f)}) {
        const glm::vec3 sigma = absorption_coefficient(a);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(std::exp(-sigma[c]), a[c], 1e-6f * a[c] + 1e-9f) << c;
            EXPECT_NEAR(std::exp(-3.5f * sigma[c]), std::pow(a[c], 3.5f), 1e-6f) << c;
        }
    }
    EXPECT_EQ(absorption_coefficient(glm::vec3(1.f)), glm::vec3(0.f));
    const glm::vec3 black = absorption_coefficient(glm::vec3(0.f));
    EXPECT_TRUE(std::isfinite(black.x) && black.x > 60.f) << black.x;
    EXPECT_LT(std::exp(-black.x), 1e-25f);
    EXPECT_EQ(absorption_coefficient(glm::vec3(1.5f)), glm::vec3(0.f)) << "an albedo above 1 gains nothing";
}

// The table for the default palette: each id's albedo, reflectivity, emission and opacity as the
// registry says, and its optics from them; ids past the registry get its generated opaque colours.
TEST(MaterialTable, TheTableCarriesEachBlocksMaterialAndOptics) {
    const world::BlockRegistry& registry = world::BlockRegistry::default_registry();
    const uint32_t count = uint32_t(registry.size()) + 3;
    const std::vector<gpu::Material> table = material_table(registry, count);
    ASSERT_EQ(table.size(), count);
    for (uint32_t id = 0; id < count; ++id) {
        const world::BlockInfo b = registry.info(world::BlockId(id));
        const gpu::Material& m = table[id];
        EXPECT_EQ(glm::vec4(b.albedo, b.reflectivity), m.albedo_reflectivity) << id;
        EXPECT_EQ(glm::vec3(m.emission), b.emission) << id;
        EXPECT_EQ(m.emission.w, registry.is_opaque(world::BlockId(id)) ? 0.f : 1.f) << id;
        EXPECT_EQ(glm::vec3(m.optics), absorption_coefficient(b.albedo)) << id;
        EXPECT_EQ(m.optics.w, refractive_index(b.reflectivity)) << id;
    }
    const gpu::Material& water = table[test::block_id("water")];
    EXPECT_EQ(water.emission.w, 1.f);
    EXPECT_NEAR(water.optics.w, 1.33f, 0.01f);
    EXPECT_NEAR(water.optics.x, -std::log(0.77f), 1e-6f);
    EXPECT_EQ(table[test::block_id("glass")].optics.w, 1.5f);
    EXPECT_EQ(table[test::block_id("stone")].emission.w, 0.f);
    EXPECT_EQ(glm::vec3(table[count - 1].albedo_reflectivity), world::fallback_albedo(world::BlockId(count - 1)));
}

} // namespace
} // namespace vx::render
