#pragma once
// The acceleration structures of a scene of chunks: one BLAS per non-empty chunk mesh (see
// chunk_geometry.h for the slot layout that allows refits), and a TLAS rebuilt every frame with
// camera-relative instance transforms computed in 64-bit on the CPU, so a world at 2^24 blocks
// renders exactly like one at the origin. All BLAS builds and refits of a frame go into one
// vkCmdBuildAccelerationStructuresKHR call, followed by one barrier and the TLAS build.
// Main thread only.

#include <array>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "render/chunk_geometry.h"
#include "render/commands.h"
#include "world/coords.h"

namespace vx::render {

struct AccelStats {
    uint32_t blas_builds = 0;  // BLASes built from scratch in the last record().
    uint32_t blas_refits = 0;  // BLASes updated in place in the last record().
    uint32_t instances = 0;    // TLAS instances (non-empty chunks).
    uint64_t triangles = 0;    // Triangles in all BLASes, degenerate spares included.
};

class SceneAccel {
public:
    // allow_refit: BLASes are built with ALLOW_UPDATE so fitting edits refit; false builds them
    // without it (drivers may then build a better BVH) and every edit rebuilds.
    explicit SceneAccel(Context& ctx, bool allow_refit = true);

    // Sets chunk `c`'s mesh. A mesh whose slices fit the chunk's slot layout becomes a refit at
    // the next record(); otherwise the BLAS is rebuilt. An empty mesh removes the chunk.
    void set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh);
    void remove_chunk(world::ChunkCoord c);
    void clear();
    // Removes every chunk not in `keep`.
    void retain_only(const std::unordered_set<world::ChunkCoord, world::ChunkCoordHash>& keep);
    size_t chunk_count() const { return m_chunks.size(); }

    // Records the frame's uploads, BLAS builds/refits and the TLAS build into `cmd` (between
    // Context::begin_frame and end_frame). Afterwards the TLAS and the chunk table may be read by
    // ray-tracing shaders. `camera_block` is the world block the camera is in.
    void record(VkCommandBuffer cmd, world::BlockPos camera_block) {
        record_builds(cmd);
        record_tlas_build(cmd, camera_block);
    }
    // The two halves of record(), so a caller can time them apart: uploads and BLAS builds and
    // refits, then (after a barrier) the TLAS build. Call both, in this order.
    void record_builds(VkCommandBuffer cmd);
    void record_tlas_build(VkCommandBuffer cmd, world::BlockPos camera_block);

    VkAccelerationStructureKHR tlas() const { return m_frames[m_ctx->frame_slot()].tlas.handle(); }
    // Address of uint64[instance]: the Quad slot buffer of each TLAS instance.
    VkDeviceAddress chunk_table() const { return m_frames[m_ctx->frame_slot()].table.address(); }
    const AccelStats& stats() const { return m_stats; }

private:
    enum class Pending : uint8_t { None, Build, Refit };
    struct ChunkGpu {
        SlotLayout layout;
        world::ChunkMesh mesh; // Waiting for upload; cleared once recorded.
        Buffer vertices, quads;
        AccelStruct blas;
        VkDeviceSize update_scratch = 0;
        Pending pending = Pending::None;
        uint32_t refits_since_build = 0;
    };
    struct FrameData {
        AccelStruct tlas;
        Buffer instances, table;
        uint32_t capacity = 0; // Instances the TLAS, instance and table buffers hold.
        VkDeviceSize tlas_scratch = 0;
    };
    struct BuildBatch; // Geometry and build infos of one frame's BLAS call.

    void ensure_indices(uint32_t slots);
    void prepare_chunk(world::ChunkCoord c, ChunkGpu& g, BuildBatch& batch);
    void record_blas_builds(VkCommandBuffer cmd, BuildBatch& batch);
    void record_tlas(VkCommandBuffer cmd, world::BlockPos camera_block);
    VkDeviceAddress scratch(VkDeviceSize bytes);

    Context* m_ctx;
    std::unordered_map<world::ChunkCoord, ChunkGpu, world::ChunkCoordHash> m_chunks;
    Buffer m_indices;
    uint32_t m_index_slots = 0;
    StagingRing m_staging;
    Buffer m_scratch; // Shared by the frame's BLAS call and TLAS build (a barrier separates them).
    std::array<FrameData, kFramesInFlight> m_frames;
    AccelStats m_stats;
    bool m_allow_refit = true;
    VkBuildAccelerationStructureFlagsKHR m_blas_flags = 0;
};

} // namespace vx::render
