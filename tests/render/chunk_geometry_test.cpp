// Slot filling on the CPU: a slice written alone (the upload before a refit) holds the bytes the
// whole-chunk fill writes there, spares included, so a partial upload leaves the GPU buffers
// exactly as a full one would.
#include <cstring>
#include <random>

#include "render/chunk_geometry.h"
#include "render/slot_map.h"
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

// The slot map of a hot chunk: assigned, it writes fill_slots' bytes; after edits every live slot
// holds one quad of the new slice (each once), unchanged quads keep their slots, unused slots are
// degenerate (four equal vertices) and hold Quad{}.
TEST(SlotMap, EditsKeepUnchangedQuadsInTheirSlots) {
    world::World w = test::hills();
    world::MeshMap meshes = test::mesh_world(w);
    const world::ChunkCoord c(0);
    const SlotLayout layout = SlotLayout::for_mesh(meshes.at(c).mesh);
    SlotMap map;
    map.assign(layout, meshes.at(c).mesh);
    std::vector<float> v(size_t(layout.total) * 12), ref(v.size());
    std::vector<world::Quad> q(layout.total), ref_q(layout.total);
    map.write_all(layout, v.data(), q.data());
    fill_slots(layout, meshes.at(c).mesh, ref.data(), ref_q.data());
    EXPECT_EQ(std::memcmp(v.data(), ref.data(), v.size() * sizeof(float)), 0);
    EXPECT_TRUE(std::equal(q.begin(), q.end(), ref_q.begin()));

    world::EditMesher em;
    std::mt19937 rng(11);
    size_t kept = 0, slots_checked = 0;
    for (int edit = 0; edit < 60; ++edit) {
        const world::BlockPos p{int64_t(1 + rng() % 30), int64_t(4 + rng() % 10), int64_t(1 + rng() % 30)};
        const world::EditResult r = em.apply(w, p, rng() % 2 ? world::kAir : test::block_id("stone"), meshes);
        const world::ChunkMesh& mesh = meshes.at(c).mesh;
        if (!layout.fits(mesh))
            break; // A hot chunk would be rebuilt with a new layout here.
        std::vector<world::Quad> before = q;
        for (const world::SliceUpdate& u : r.updates)
            if (u.chunk == c) {
                if (u.full)
                    for (int s = 0; s < world::kSliceCount; ++s)
                        map.update_slice(layout, mesh, s);
                for (int i = 0; i < u.count; ++i)
                    map.update_slice(layout, mesh, u.slices[size_t(i)]);
            }
        map.write_all(layout, v.data(), q.data());
        for (int s = 0; s < world::kSliceCount; ++s) {
            std::vector<uint64_t> want, got;
            for (const world::Quad& x : mesh.slice(s))
                want.push_back(uint64_t(x.packed) << 32 | x.block);
            for (uint32_t k = layout.start[s]; k < layout.start[s] + layout.capacity[s]; ++k) {
                const float* sv = v.data() + size_t(k) * 12;
                if (q[k].block == world::kAir) { // Unused: degenerate.
                    for (int i = 1; i < 4; ++i)
                        for (int j = 0; j < 3; ++j)
                            ASSERT_EQ(sv[i * 3 + j], sv[j]) << "slot " << k;
                    continue;
                }
                got.push_back(uint64_t(q[k].packed) << 32 | q[k].block);
                glm::ivec3 corners[4];
                world::quad_corners(q[k], corners);
                for (int i = 0; i < 4; ++i)
                    for (int j = 0; j < 3; ++j)
                        ASSERT_EQ(sv[i * 3 + j], float(corners[i][j])) << "slot " << k;
                const auto in_new = std::find_if(mesh.slice(s).begin(), mesh.slice(s).end(), [&](const world::Quad& x) {
                    return x.packed == before[k].packed && x.block == before[k].block;
                });
                if (before[k].block != world::kAir && in_new != mesh.slice(s).end()) {
                    EXPECT_EQ(q[k].packed, before[k].packed) << "an unchanged quad moved, slot " << k;
                    ++kept;
                }
                ++slots_checked;
            }
            std::sort(want.begin(), want.end());
            std::sort(got.begin(), got.end());
            ASSERT_EQ(got, want) << "slice " << s << " after edit " << edit;
        }
    }
    EXPECT_GT(kept, slots_checked / 2); // Most quads survive an edit in place.
}

} // namespace
} // namespace vx::render
