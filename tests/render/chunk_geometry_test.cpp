// Slot filling on the CPU: a slice written alone (the upload before a refit) holds the bytes the
// whole-chunk fill writes there, spares included, so a partial upload leaves the GPU buffers
// exactly as a full one would.
#include <cstring>
#include <random>

#include "render/chunk_geometry.h"
#include "scene_util.h"

namespace vx::render {
namespace {

TEST(ChunkGeometry, SliceFillMatchesTheWholeFill) {
    world::World w = test::hills();
    std::mt19937 rng(5);
    for (int i = 0; i < 200; ++i) // Holes and bumps, so slices differ in size and some are empty.
        w.set_block({int64_t(rng() % 32), int64_t(rng() % 14), int64_t(rng() % 32)},
                    rng() % 2 ? world::kAir : test::block_id("stone"));
    const world::MeshMap meshes = test::mesh_world(w);
    const world::ChunkMesh& mesh = meshes.at(world::ChunkCoord(0)).mesh;
    ASSERT_GT(mesh.quad_count(), 100u);
    for (const SlotLayout& layout : {SlotLayout::for_mesh(mesh), SlotLayout::exact(mesh)}) {
        std::vector<float> whole(size_t(layout.total) * 12);
        std::vector<world::Quad> whole_quads(layout.total);
        fill_slots(layout, mesh, whole.data(), whole_quads.data());
        for (int s = 0; s < world::kSliceCount; ++s) {
            const uint32_t n = layout.capacity[s];
            std::vector<float> v(size_t(n) * 12, -1.f);
            std::vector<world::Quad> q(n);
            fill_slice(layout, mesh, s, v.data(), q.data());
            EXPECT_EQ(std::memcmp(v.data(), whole.data() + size_t(layout.start[s]) * 12, v.size() * sizeof(float)), 0)
                << "slice " << s;
            EXPECT_TRUE(std::equal(q.begin(), q.end(), whole_quads.begin() + layout.start[s])) << "slice " << s;
        }
    }
}

TEST(ChunkGeometry, ExactLayoutHasNoSpareSlots) {
    const world::MeshMap meshes = test::mesh_world(test::hills());
    for (const auto& [c, mc] : meshes) {
        const SlotLayout exact = SlotLayout::exact(mc.mesh), hot = SlotLayout::for_mesh(mc.mesh);
        EXPECT_EQ(exact.total, mc.mesh.quad_count());
        EXPECT_TRUE(exact.fits(mc.mesh));
        // Hot: n + n/4 + 2 slots per slice, so at least 2 spares in each of the 99 slices.
        EXPECT_GE(hot.total, mc.mesh.quad_count() + 2 * world::kSliceCount);
    }
}

TEST(ChunkGeometry, MeshHashTellsMeshesApart) {
    world::World w = test::hills();
    world::MeshMap meshes = test::mesh_world(w);
    const world::ChunkMesh before = meshes.at(world::ChunkCoord(0)).mesh;
    EXPECT_EQ(mesh_hash(before), mesh_hash(meshes.at(world::ChunkCoord(0)).mesh));
    world::EditMesher em;
    em.apply(w, {10, 9, 10}, test::block_id("stone"), meshes);
    EXPECT_NE(mesh_hash(before), mesh_hash(meshes.at(world::ChunkCoord(0)).mesh));
    em.apply(w, {10, 9, 10}, world::kAir, meshes);
    EXPECT_EQ(mesh_hash(before), mesh_hash(meshes.at(world::ChunkCoord(0)).mesh)); // Same quads again.
}

} // namespace
} // namespace vx::render
