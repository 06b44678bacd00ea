// The snapshot pattern (style guide §5): a mesh job copies its chunk and apron on the main thread
// at submission, meshes the copy on a worker while the main thread keeps editing the live World,
// and complete() re-checks that its chunk still exists. Under ThreadSanitizer any read of the
// live World from the worker would be reported as a race with the edits.

#include <optional>

#include <gtest/gtest.h>

#include "job_test_util.h"
#include "world/mesh/apron.h"
#include "world/mesh/mesher.h"
#include "world/world.h"

using namespace vx::engine;
using namespace vx::engine::test;
using vx::world::BlockPos;
using vx::world::ChunkCoord;

namespace {

// What the main thread keeps per chunk: the mesh's quad count once a mesh job applied.
using MeshTable = std::unordered_map<ChunkCoord, uint32_t, vx::world::ChunkCoordHash>;

class SnapshotMeshJob final : public Job {
public:
    // Main thread: copies everything run() reads. The World is not referenced again off-thread.
    SnapshotMeshJob(const vx::world::World& world, ChunkCoord c, MeshTable& table, Gate* hold = nullptr)
        : Job(JobKey{c, JobKind::Mesh}), m_world(world), m_chunk(*world.find_chunk(c)),
          m_apron(vx::world::make_apron(world, c)), m_registry(world.registry()), m_table(table), m_hold(hold) {}

    void run(JobContext& ctx) override {
        if (m_hold)
            m_hold->wait();
        if (ctx.is_cancelled())
            return;
        vx::world::GreedyMesher mesher; // Per job here; a real job keeps one per worker.
        mesher.mesh({m_chunk, m_apron, m_registry}, m_mesh);
    }
    void complete() override {
        // The chunk may have been unloaded since submission (godot_voxel apply_result).
        if (m_world.find_chunk(key().chunk) == nullptr)
            return;
        m_table[key().chunk] = m_mesh.quad_count();
    }

private:
    const vx::world::World& m_world; // Main thread only: complete() re-checks its target.
    vx::world::Chunk m_chunk;
    vx::world::Apron m_apron;
    vx::world::BlockRegistry m_registry;
    vx::world::ChunkMesh m_mesh;
    MeshTable& m_table;
    Gate* m_hold;
};

void fill_chunk(vx::world::World& world, ChunkCoord c, vx::world::BlockId id) {
    const BlockPos o = vx::world::chunk_origin(c);
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                world.set_block(o + BlockPos(x, y, z), id);
}

} // namespace

TEST(JobSnapshot, WorkerMeshesItsCopyWhileTheMainThreadEdits) {
    vx::world::World world;
    const vx::world::BlockId stone = *world.registry().find("stone");
    fill_chunk(world, ChunkCoord(0, 0, 0), stone);
    fill_chunk(world, ChunkCoord(5, 0, 0), stone);
    MeshTable table;
    Gate hold;
    JobSystem jobs(test_info(2));
    jobs.submit(std::make_unique<SnapshotMeshJob>(world, ChunkCoord(0, 0, 0), table, &hold));
    jobs.submit(std::make_unique<SnapshotMeshJob>(world, ChunkCoord(5, 0, 0), table, &hold));
    // While the jobs hold their snapshots: carve the live chunk (0,0,0), unload (5,0,0).
    for (int x = 0; x < 32; x += 2)
        world.set_block(BlockPos(x, 31, 5), vx::world::kAir);
    EXPECT_TRUE(world.remove_chunk(ChunkCoord(5, 0, 0)));
    hold.open();
    drain(jobs);
    // The snapshot was a solid 32³ cube with air around it: greedy meshing gives one quad per face.
    ASSERT_EQ(table.count(ChunkCoord(0, 0, 0)), 1u);
    EXPECT_EQ(table[ChunkCoord(0, 0, 0)], 6u);
    // The unloaded chunk's result was computed but not applied.
    EXPECT_EQ(table.count(ChunkCoord(5, 0, 0)), 0u);
    EXPECT_EQ(jobs.metrics().completed, 2u); // complete() ran; it chose to do nothing.

    // A fresh snapshot of the edited chunk sees the edits: more quads than the plain cube.
    jobs.submit(std::make_unique<SnapshotMeshJob>(world, ChunkCoord(0, 0, 0), table));
    drain(jobs);
    EXPECT_GT(table[ChunkCoord(0, 0, 0)], 6u);
}
