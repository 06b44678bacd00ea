// Hot and cold chunks, and edits as slices. A chunk loaded whole is built cold (exact size,
// compacted two frames later, no vertices kept); its first edit rebuilds it hot (spare slots,
// ALLOW_UPDATE); later edits upload only the changed slices and refit; a hot chunk left alone for
// hot_frames frames is rebuilt cold. Every stage must render the bytes a scratch load renders,
// and the memory tally must add up.
#include <algorithm>

#include "render/chunk_geometry.h"
#include "scene_util.h"

namespace vx::render {
namespace {

constexpr uint64_t kSlotBytes = kSlotVertexBytes + kSlotQuadBytes; // 48 + 8 per slot.
const world::BlockPos kOnGround(10, 9, 10); // Air on the ground of chunk (0,0,0), not on a border.
const Camera kCamera = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});

RenderSettings flat() {
    RenderSettings s;
    s.mode = ShadingMode::Flat;
    return s;
}

struct ChunkResidencyTest : ::testing::Test {
    void SetUp() override {
        RendererCreateInfo ci;
        ci.hot_frames = 3;
        r = test::make_renderer(ci);
        ASSERT_NE(r, nullptr);
        meshes = test::mesh_world(w);
        test::load_meshes(*r, meshes);
    }
    void TearDown() override {
        if (r) {
            EXPECT_EQ(r->validation_errors(), 0u);
        }
    }
    // Applies one block edit and hands each touched chunk's mesh and slices to the renderer.
    world::SliceUpdate edit(world::BlockPos p, world::BlockId id) {
        const world::EditResult e = em.apply(w, p, id, meshes);
        EXPECT_EQ(e.updates.size(), 1u); // kOnGround touches no neighbour chunk.
        for (const world::SliceUpdate& u : e.updates)
            r->set_chunk(u.chunk, meshes[u.chunk].mesh, test::changed_slices(u));
        return e.updates.at(0);
    }
    // The same world loaded from scratch (leaves the renderer holding cold chunks).
    RenderImage scratch() {
        r->clear_chunks();
        test::load_meshes(*r, test::mesh_world(w));
        return r->render(flat(), kCamera);
    }
    uint64_t quads_in_scene() const {
        uint64_t n = 0;
        for (const auto& [c, mc] : meshes)
            n += mc.mesh.quad_count();
        return n;
    }

    world::World w = test::hills();
    world::EditMesher em;
    world::MeshMap meshes;
    std::unique_ptr<Renderer> r;
};

// The most a driver adds to a buffer's size in its memory requirements (lavapipe: nothing; an
// H100: up to 256 bytes), over the usages of a chunk's three buffers, and at least the
// allocator's 16.
VkDeviceSize size_granularity(Context& ctx) {
    VkDeviceSize most = 16;
    for (VkBufferUsageFlags usage :
         {VkBufferUsageFlags(VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR),
          VkBufferUsageFlags(VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT),
          VkBufferUsageFlags(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT)}) {
        VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        ci.size = 1;
        ci.usage = usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
        VkBuffer b = VK_NULL_HANDLE;
        if (vkCreateBuffer(ctx.device(), &ci, nullptr, &b) != VK_SUCCESS)
            continue;
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(ctx.device(), b, &req);
        vkDestroyBuffer(ctx.device(), b, nullptr);
        most = std::max(most, req.size);
    }
    return most;
}

// The tally: total is the sum of its parts, B/quad is per-chunk memory over real quads, and the
// allocator's scene (budgeted) bytes are those buffers, each rounded up to the driver's size
// granularity (its memory requirements) and the allocator's 16 bytes.
void expect_memory_consistent(Renderer& r, uint64_t quads, uint32_t chunks) {
    const GpuMemoryStats m = r.last_stats().memory;
    EXPECT_EQ(m.total(), m.blas + m.vertices + m.quads + m.tlas + m.scratch + m.indices);
    EXPECT_EQ(m.quad_count, quads);
    EXPECT_DOUBLE_EQ(m.bytes_per_quad(), double(m.blas + m.vertices + m.quads) / double(quads));
    r.context().wait_idle(); // Frees retired buffers, so the allocator holds only live ones.
    const uint64_t live = r.context().allocator().stats().budgeted_bytes;
    const uint64_t parts = m.blas + m.vertices + m.quads;
    EXPECT_GE(live, parts);
    // At most 3 buffers per chunk.
    EXPECT_LE(live, parts + 3 * size_granularity(r.context()) * uint64_t(chunks));
}

TEST_F(ChunkResidencyTest, ColdChunksCompactTurnHotOnEditAndCoolDown) {
    const uint32_t chunks = uint32_t(meshes.size());
    const RenderImage first = r->render(flat(), kCamera);
    RenderStats st = r->last_stats();
    EXPECT_EQ(st.blas_builds, chunks);
    EXPECT_EQ(st.hot_chunks, 0u);
    EXPECT_EQ(st.memory.vertices, 0u); // Cold chunks drop their vertices after the build.
    EXPECT_EQ(st.memory.quads, quads_in_scene() * kSlotQuadBytes); // Exact size: no spare slot.
    EXPECT_EQ(st.upload_bytes, quads_in_scene() * kSlotBytes);
    const uint64_t built_blas = st.memory.blas;

    // Compacted-size queries are read when the frame slot comes round (kFramesInFlight = 2).
    uint32_t compactions = 0;
    for (int i = 0; i < 2; ++i) {
        const RenderImage img = r->render(flat(), kCamera);
        compactions += r->last_stats().blas_compactions;
        EXPECT_EQ(r->last_stats().blas_builds + r->last_stats().blas_refits, 0u);
        EXPECT_EQ(test::differing_bytes(img, first), 0) << "compacted BLASes trace like the originals";
    }
    EXPECT_EQ(compactions, chunks);
    EXPECT_LE(r->last_stats().memory.blas, built_blas);
    expect_memory_consistent(*r, quads_in_scene(), chunks);

    // First edit: the cold chunk is rebuilt hot, the whole hot layout uploaded.
    edit(kOnGround, test::block_id("stone"));
    r->render(flat(), kCamera);
    st = r->last_stats();
    EXPECT_EQ(st.blas_builds, 1u);
    EXPECT_EQ(st.blas_refits, 0u);
    EXPECT_EQ(st.hot_chunks, 1u);
    const world::ChunkMesh& hot_mesh = meshes[world::ChunkCoord(0)].mesh;
    const SlotLayout layout = SlotLayout::for_mesh(hot_mesh);
    EXPECT_EQ(st.upload_bytes, layout.total * kSlotBytes);
    EXPECT_EQ(st.memory.vertices, layout.total * kSlotVertexBytes);

    // Second edit (remove the block): a refit that uploads the six slices bounding the block.
    // Each slice s has capacity[s] = n + n/4 + 2 slots of 56 bytes (n: its quads at the hot
    // build), so the upload is at most the sum over those six of capacity[s] * 56: six of 99
    // slices, far below the chunk's layout.total * 56.
    const world::SliceUpdate u = edit(kOnGround, world::kAir);
    ASSERT_FALSE(u.full);
    ASSERT_EQ(u.count, 6);
    uint64_t bound = 0;
    for (int i = 0; i < u.count; ++i)
        bound += layout.capacity[u.slices[i]] * kSlotBytes;
    const RenderImage hot = r->render(flat(), kCamera);
    st = r->last_stats();
    EXPECT_EQ(st.blas_refits, 1u);
    EXPECT_EQ(st.blas_builds, 0u);
    EXPECT_GT(st.upload_bytes, 0u);
    EXPECT_LE(st.upload_bytes, bound);
    EXPECT_LT(st.upload_bytes * 4, layout.total * kSlotBytes);
    const uint32_t edit_frame_stats_hot = st.hot_chunks;
    EXPECT_EQ(edit_frame_stats_hot, 1u);

    // Left alone, the hot chunk cools down: rebuilt cold within hot_frames (3) frames of its last
    // edit, then compacted two frames later.
    int cooled_at = -1;
    uint32_t cooled_compactions = 0;
    for (int i = 1; i <= 6; ++i) {
        r->render(flat(), kCamera);
        if (r->last_stats().blas_builds == 1 && cooled_at < 0)
            cooled_at = i;
        cooled_compactions += r->last_stats().blas_compactions;
    }
    EXPECT_GE(cooled_at, 1);
    EXPECT_LE(cooled_at, 3);
    EXPECT_EQ(cooled_compactions, 1u);
    const RenderImage cooled = r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().hot_chunks, 0u);
    EXPECT_EQ(r->last_stats().memory.vertices, 0u);
    expect_memory_consistent(*r, quads_in_scene(), chunks);

    const RenderImage ref = scratch();
    EXPECT_EQ(test::differing_bytes(hot, ref), 0) << "hot refit with slice uploads";
    EXPECT_EQ(test::differing_bytes(cooled, ref), 0) << "cooled down and compacted";
}

// A cool-down rebuild (an optimisation) that runs out of memory keeps the chunk hot and drawn
// and tries again later. It once dropped the chunk's good hot BLAS and mesh: the chunk stayed
// missing until the game sent it again, which the engine never does.
TEST_F(ChunkResidencyTest, AFailedCoolDownKeepsTheHotChunkDrawn) {
    r->render(flat(), kCamera);
    edit(kOnGround, test::block_id("stone"));
    const RenderImage hot = r->render(flat(), kCamera);
    ASSERT_EQ(r->last_stats().hot_chunks, 1u);
    r->fail_allocations("chunk quads");
    for (int i = 1; i <= 6; ++i) { // Past hot_frames (3): the cool-down is due and fails.
        const RenderImage img = r->render(flat(), kCamera);
        const RenderStats& st = r->last_stats();
        EXPECT_EQ(st.failed_chunks, 0u) << "frame " << i;
        EXPECT_EQ(st.instances, meshes.size()) << "frame " << i;
        EXPECT_EQ(st.hot_chunks, 1u) << "frame " << i;
        EXPECT_EQ(test::differing_bytes(img, hot), 0) << "frame " << i;
    }
    r->fail_allocations("");
    bool cooled = false;
    for (int i = 0; i < 6 && !cooled; ++i) {
        r->render(flat(), kCamera);
        cooled = r->last_stats().hot_chunks == 0;
    }
    EXPECT_TRUE(cooled) << "the cool-down is tried again once memory is back";
    const RenderImage after = r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().failed_chunks, 0u);
    EXPECT_EQ(test::differing_bytes(after, scratch()), 0);
}

// A mesh sent again unchanged (Renderer::render(scene) re-sends every chunk) costs nothing.
TEST_F(ChunkResidencyTest, UnchangedMeshIsNotUploadedAgain) {
    r->render(flat(), kCamera);
    test::load_meshes(*r, meshes);
    r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().blas_builds + r->last_stats().blas_refits, 0u);
    EXPECT_EQ(r->last_stats().upload_bytes, 0u);
}

// With allow_refit off every chunk stays cold and every edit is a cold rebuild.
TEST(ChunkResidency, NoRefitKeepsEveryChunkCold) {
    RendererCreateInfo ci;
    ci.allow_refit = false;
    std::unique_ptr<Renderer> r = test::make_renderer(ci);
    ASSERT_NE(r, nullptr);
    world::World w = test::hills();
    world::MeshMap meshes = test::mesh_world(w);
    test::load_meshes(*r, meshes);
    r->render(flat(), kCamera);
    world::EditMesher em;
    const world::EditResult e = em.apply(w, kOnGround, test::block_id("stone"), meshes);
    r->set_chunk(e.updates.at(0).chunk, meshes[e.updates.at(0).chunk].mesh, test::changed_slices(e.updates.at(0)));
    const RenderImage edited = r->render(flat(), kCamera);
    EXPECT_EQ(r->last_stats().blas_builds, 1u);
    EXPECT_EQ(r->last_stats().hot_chunks, 0u);
    r->clear_chunks();
    test::load_meshes(*r, test::mesh_world(w));
    EXPECT_EQ(test::differing_bytes(edited, r->render(flat(), kCamera)), 0);
    EXPECT_EQ(r->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
