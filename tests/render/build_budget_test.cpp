// A frame's chunk builds too large to allocate at once (Context::fail_allocations with a size:
// the frame staging buffer or the build scratch can hold only part of the pending chunks): the
// builds spread over frames, each frame renders, and once every chunk is drawn the image is a
// fresh renderer's. A chunk too large alone fails for itself; the others are drawn. The whole
// batch was retried every frame and failed every time, so nothing was ever drawn.
#include <algorithm>
#include <cmath>

#include "render/chunk_geometry.h"
#include "render/commands.h"
#include "render/context.h"
#include "scene_util.h"

namespace vx::render {
namespace {

const Camera kCamera = Camera::look_at({80.3, 70.6, 85.1}, {0.0, 4.0, 0.0});

RenderSettings flat() {
    RenderSettings s;
    s.width = 48;
    s.height = 32;
    s.mode = ShadingMode::Flat;
    return s;
}

// Hills over 4 x 1 x 4 chunks (x, z in [-64, 64)): 16 chunks of different sizes.
world::World wide_hills() {
    world::World w;
    const world::BlockId grass = test::block_id("grass"), dirt = test::block_id("dirt");
    for (int64_t z = -64; z < 64; ++z)
        for (int64_t x = -64; x < 64; ++x) {
            const int64_t h = 8 + int64_t(5 * std::sin(double(x) * 0.13) + 4 * std::cos(double(z) * 0.21));
            for (int64_t y = 0; y < h; ++y)
                w.set_block({x, y, z}, y + 1 == h ? grass : dirt);
        }
    return w;
}

// What SceneAccel asks of the shared buffers for building one cold chunk: its staging (vertices
// and quad records of every slot, plus 32 bytes of copy alignment) and its build scratch
// (aligned to minAccelerationStructureScratchOffsetAlignment).
struct Need {
    uint64_t staging = 0, scratch = 0;
};

Need need(Context& ctx, const world::ChunkMesh& mesh) {
    const uint32_t slots = SlotLayout::exact(mesh).total;
    Need n;
    n.staging = slots * (kSlotVertexBytes + kSlotQuadBytes) + 32;
    VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.geometry.triangles.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    g.geometry.triangles.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    g.geometry.triangles.vertexStride = 3 * sizeof(float);
    g.geometry.triangles.maxVertex = 4 * slots - 1;
    g.geometry.triangles.indexType = VK_INDEX_TYPE_UINT32;
    VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                 VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &g;
    const uint32_t triangles = 2 * slots;
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    vkGetAccelerationStructureBuildSizesKHR(ctx.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
                                            &triangles, &sizes);
    n.scratch = align_up(sizes.buildScratchSize, ctx.as_properties().minAccelerationStructureScratchOffsetAlignment);
    return n;
}

// The size each chunk asks of the injected buffer ("frame staging" or "AS scratch").
std::vector<uint64_t> needs(Renderer& r, const world::MeshMap& meshes, bool staging) {
    std::vector<uint64_t> out;
    for (const auto& [c, mc] : meshes) {
        const Need n = need(r.context(), mc.mesh);
        out.push_back(staging ? n.staging : n.scratch);
    }
    return out;
}

// Renders until every chunk is drawn or failed (at most `frames` frames; each must render).
// Returns the frames it took, or 0 when they were not enough.
int render_until_settled(Renderer& r, size_t chunks, int frames) {
    for (int i = 1; i <= frames; ++i) {
        Result<RenderImage> img = r.try_render(flat(), kCamera);
        EXPECT_TRUE(img) << "frame " << i << ": " << (img ? "" : img.error());
        if (!img)
            return 0;
        if (r.last_stats().instances + r.last_stats().failed_chunks == chunks)
            return i;
    }
    return 0;
}

class BuildBudget : public ::testing::TestWithParam<const char*> {};

// Each chunk fits alone; the injected limit is under a third of the whole batch (plus the scratch
// buffer's alignment slack): at least three frames build them all, at most one per chunk.
TEST_P(BuildBudget, ABatchTooLargeSpreadsOverFramesAndDrawsEveryChunk) {
    const bool staging = std::string(GetParam()) == "frame staging";
    const world::World w = wide_hills();
    const world::MeshMap meshes = test::mesh_world(w);
    ASSERT_EQ(meshes.size(), 16u);
    const RenderImage expected = test::fresh_render(meshes, flat(), kCamera);
    ASSERT_FALSE(expected.rgba.empty());

    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    const std::vector<uint64_t> n = needs(*r, meshes, staging);
    uint64_t total = 0;
    for (uint64_t b : n)
        total += b;
    const uint64_t slack = r->context().as_properties().minAccelerationStructureScratchOffsetAlignment;
    const uint64_t limit = std::max(*std::max_element(n.begin(), n.end()), total / 3) + slack;
    ASSERT_LT(limit, total);
    r->fail_allocations(GetParam(), limit);
    test::load_meshes(*r, meshes);
    const int frames = render_until_settled(*r, meshes.size(), int(meshes.size()));
    ASSERT_GT(frames, 0) << "chunks still pending after " << meshes.size() << " frames";
    EXPECT_GE(frames, 2); // The limit did bite.
    EXPECT_EQ(r->last_stats().failed_chunks, 0u);
    EXPECT_EQ(r->last_stats().instances, meshes.size());
    Result<RenderImage> img = r->try_render(flat(), kCamera);
    ASSERT_TRUE(img) << img.error();
    EXPECT_EQ(test::differing_bytes(*img, expected), 0);
    EXPECT_EQ(r->validation_errors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(EachBuildBuffer, BuildBudget, ::testing::Values("frame staging", "AS scratch"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                             return std::string(p.param) == "frame staging" ? "staging" : "scratch";
                         });

// The largest chunk alone is over the staging limit (every other chunk fits): it fails for
// itself, counted as a failed chunk, and the rest are drawn: the image of a renderer without it.
// Staging only: lavapipe asks the same 64 bytes of build scratch for every chunk.
TEST(BuildBudgetAlone, AChunkTooLargeAloneFailsForItselfOnly) {
    const world::World w = wide_hills();
    const world::MeshMap meshes = test::mesh_world(w);
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    const std::vector<uint64_t> n = needs(*r, meshes, true);
    std::vector<uint64_t> sorted = n;
    std::sort(sorted.rbegin(), sorted.rend());
    ASSERT_GT(sorted[0], sorted[1]) << "two chunks share the largest size";
    const uint64_t limit = sorted[1]; // Room for the second largest, not the largest.
    world::MeshMap rest = meshes;
    size_t i = 0;
    for (const auto& [c, mc] : meshes) // needs() went in this order.
        if (n[i++] == sorted[0])
            rest.erase(c);
    ASSERT_EQ(rest.size() + 1, meshes.size());
    const RenderImage expected = test::fresh_render(rest, flat(), kCamera);
    ASSERT_FALSE(expected.rgba.empty());

    r->fail_allocations("frame staging", limit);
    test::load_meshes(*r, meshes);
    const int frames = render_until_settled(*r, meshes.size(), int(meshes.size()) + 1);
    ASSERT_GT(frames, 0) << "chunks still pending after " << meshes.size() + 1 << " frames";
    EXPECT_EQ(r->last_stats().failed_chunks, 1u);
    EXPECT_EQ(r->last_stats().instances, rest.size());
    Result<RenderImage> img = r->try_render(flat(), kCamera);
    ASSERT_TRUE(img) << img.error();
    EXPECT_EQ(test::differing_bytes(*img, expected), 0);
    EXPECT_EQ(r->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
