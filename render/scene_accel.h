#pragma once
// The acceleration structures of a scene of chunks: one BLAS per non-empty chunk mesh (see
// chunk_geometry.h for the slot layout that allows refits, and below for hot and cold chunks),
// and a TLAS rebuilt every frame from instances kept across frames (render/tlas_instances.h: only
// changed instances are written, translations relative to a render origin that follows the
// camera in steps, computed in 64-bit on the CPU, so a world at 2^24 blocks renders like one at
// the origin). All BLAS builds and refits of a frame go into one
// vkCmdBuildAccelerationStructuresKHR call, followed by one barrier and the TLAS build. A frame
// builds the pending chunks, oldest first, up to a staging and a scratch budget (2 GiB each,
// less after allocations fail); the rest wait, still drawn as before, for the next frames.
// A frame's CPU work follows what changed (pending chunks, hot chunks cooling down, compactions),
// never every chunk: counts and memory are kept as chunks change.
// Main thread only.

#include <array>
#include <bitset>
#include <memory>
#include <deque>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "render/chunk_geometry.h"
#include "render/slot_map.h"
#include "render/commands.h"
#include "render/renderer.h"
#include "render/tlas_instances.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

struct AccelStats {
    uint32_t blas_builds = 0;      // BLASes built from scratch in the last record().
    uint32_t blas_refits = 0;      // BLASes updated in place in the last record().
    uint32_t blas_compactions = 0; // Cold BLASes copied into their compacted size in the last record().
    uint32_t instances = 0;        // TLAS instances (drawn chunks).
    uint32_t hot_chunks = 0;       // Chunks kept refittable (edited lately).
    uint32_t failed_chunks = 0;    // Chunks not drawn: their GPU memory could not be allocated.
    uint64_t triangles = 0;        // Triangles in the drawn chunks' BLASes, degenerate spares included.
    uint64_t upload_bytes = 0;     // Chunk vertices + quad records staged and copied in the last record().
    uint32_t instance_writes = 0;  // TLAS instances written into the frame slot's buffer in the last record().
    uint64_t rebases = 0;          // Render-origin moves that rewrote every instance, since creation.
    // Per level (world/lod/lod_coords.h): TLAS instances, and device memory (BLAS + vertices +
    // quad records) of that level's chunks; kept as chunks change, copied once per frame.
    std::array<uint32_t, world::kMaxLodLevel + 1> level_instances{};
    std::array<uint64_t, world::kMaxLodLevel + 1> level_gpu_bytes{};
};

// Device memory by kind: GpuMemoryStats (render/renderer.h).
using AccelMemory = GpuMemoryStats;

struct SceneAccelCreateInfo {
    // Edited chunks are built with spare slots and ALLOW_UPDATE so fitting edits refit; false:
    // every chunk is built cold and every edit rebuilds.
    bool allow_refit = true;
    // Frames after its last edit a hot chunk stays refittable before it is rebuilt cold.
    uint32_t hot_frames = 600;
    // Refits of a hot chunk in a row; the next fitting edit rebuilds it (a refit keeps the old
    // tree, whose boxes loosen). 0: every edit rebuilds (hot layout, ALLOW_UPDATE kept).
    uint32_t max_refits = 8;
};

// What a chunk's blocks are, beside its mesh (Renderer::set_chunk reads them off the registry).
struct ChunkTraits {
    bool opaque = false; // Only opaque blocks: OPAQUE geometry.
};

// The traits of a chunk whose quads hold blocks `ids`, under `registry`. Any thread.
ChunkTraits chunk_traits(std::span<const world::BlockId> ids, const world::BlockRegistry& registry);

// Chunks are "cold" (built exact-size, PREFER_FAST_TRACE, without ALLOW_UPDATE, then compacted;
// their vertices are dropped after the build, so they hold only the BLAS and the quad records)
// or "hot" (spare slots per slice, ALLOW_UPDATE, vertices kept: an edit whose slices fit uploads
// just those slices and refits). A new chunk is cold; an edit (set_chunk with changed slices)
// makes it hot with a rebuild; a hot chunk not edited for hot_frames frames is rebuilt cold.
// Compaction runs kFramesInFlight frames after the build, once the compacted-size query of that
// frame slot has completed.
class SceneAccel {
public:
    SceneAccel(Context& ctx, const SceneAccelCreateInfo& info);
    ~SceneAccel();
    SceneAccel(const SceneAccel&) = delete;
    SceneAccel& operator=(const SceneAccel&) = delete;

    // Sets chunk `c`'s mesh (chunk-local cell units: cells of 2^c.level blocks; level 0 is
    // blocks); applied at the next record(), or a later one when that frame's build budget is
    // spent (the old mesh is drawn meanwhile). Chunks of different levels are different entries,
    // whatever their chunk coordinates. An empty
    // mesh removes the chunk. `changed_slices` (slice_index() values) marks an edit: the chunk
    // turns hot and, when it is hot already and every slice still fits its slots, only those
    // slices are uploaded before a refit. Empty: the whole mesh is new (a hot chunk refits with
    // a full upload when it fits, a cold one is rebuilt; a mesh equal to the current one is
    // ignored). A chunk whose GPU memory (its own buffers, or its staging or build scratch even
    // alone) cannot be allocated is not drawn and is counted in AccelStats::failed_chunks until
    // it is set again or removed.
    void set_chunk(world::LodCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices = {},
                   ChunkTraits traits = {});
    void remove_chunk(world::LodCoord c);
    void clear();
    // Removes every chunk not in `keep` (O(chunks): for whole-scene calls).
    void retain_only(const std::unordered_set<world::LodCoord, world::LodCoordHash>& keep);
    size_t chunk_count() const { return m_chunks.size(); }

    // Records the frame's uploads, BLAS builds/refits and the TLAS build into `cmd` (between
    // Context::begin_frame and end_frame). Afterwards the TLAS and the chunk table may be read by
    // ray-tracing shaders. `camera_block` is the world block the camera is in. False (logged)
    // when a frame resource (scratch, staging, the index pattern, the TLAS) cannot be allocated
    // even for one chunk: what was recorded may still be submitted, nothing may trace this frame,
    // and the chunks it could not build are built by the next call.
    bool record(VkCommandBuffer cmd, world::BlockPos camera_block) {
        return record_builds(cmd) && record_tlas_build(cmd, camera_block);
    }
    // The two halves of record(), so a caller can time them apart: uploads and BLAS builds and
    // refits, then (after a barrier) the TLAS build. Call both, in this order (the second only
    // when the first succeeded).
    bool record_builds(VkCommandBuffer cmd);
    bool record_tlas_build(VkCommandBuffer cmd, world::BlockPos camera_block);

    VkAccelerationStructureKHR tlas() const { return m_frames[m_ctx->frame_slot()].tlas.handle(); }
    // Address of uint64[instance]: the Quad slot buffer of each TLAS instance.
    VkDeviceAddress chunk_table() const { return m_frames[m_ctx->frame_slot()].table.address(); }
    // The chunks the last record_tlas_build() drew, in TLAS instance order (the raster
    // pipeline draws them from their quad records: render/raster_pipeline.h).
    using DrawChunk = render::DrawChunk;
    std::span<const DrawChunk> draw_list() const { return m_instances.draw_list(); }
    // The block the TLAS's translations are relative to (after record_tlas_build()): shaders
    // get every position relative to it (FrameParams, shaders/shared/render_types.h).
    world::BlockPos origin() const { return m_instances.origin(); }
    // The shared slot index pattern (chunk_geometry.h), uint32, at least as many slots as the
    // largest chunk's after record_builds(); also an index buffer for the raster pipeline.
    VkBuffer index_buffer() const { return m_indices.handle(); }
    const AccelStats& stats() const { return m_stats; }
    const AccelMemory& memory() const { return m_memory; }

private:
    enum class Pending : uint8_t { None, Build, Refit };
    struct ChunkGpu {
        SlotLayout layout;
        world::ChunkMesh mesh; // Hot chunks: the current mesh (to rebuild cold later); cold: until uploaded.
        std::bitset<world::kSliceCount> dirty; // Slices a pending refit uploads.
        SlotMap slots;         // Hot chunks: which quad each slot holds (stable across refits).
        Buffer vertices, quads;
        AccelStruct blas;
        VkDeviceSize update_scratch = 0;
        Pending pending = Pending::None;
        bool hot = false;
        bool opaque = false;           // Only opaque blocks: OPAQUE geometry (no any-hit calls,
                                       // and the builder may split primitives: faster traversal).
        bool failed = false;           // Out of memory at its last build: not drawn.
        uint8_t level = 0;             // Its LodCoord's level (which m_level_bytes entry it adds to).
        uint32_t refits_since_build = 0;
        uint32_t quad_count = 0;
        uint64_t last_edit_frame = 0;  // record() count at its last edit (hot chunks).
        uint64_t build_serial = 0;     // Which build its BLAS came from (stale compaction queries).
        uint64_t hash = 0;             // mesh_hash() of its latest mesh.
        uint32_t instance = TlasInstances::kNone; // Its TLAS instance (drawn chunks).
        bool queued = false;           // Listed in m_pending.
        // A cool-down rebuild is pending: the hot layout to go back to if it cannot be allocated.
        std::unique_ptr<SlotLayout> cooling_from;
        struct Tally {
            VkDeviceSize blas = 0, vertices = 0, quads = 0;
            uint64_t quad_count = 0, triangles = 0; // Drawn chunks only.
            uint32_t hot = 0, failed = 0;
        } counted;                     // What it adds to m_total.
    };
    struct FrameData {
        AccelStruct tlas;
        Buffer instances, table;
        uint32_t capacity = 0; // Instances the TLAS, instance and table buffers hold.
        VkDeviceSize tlas_scratch = 0;
    };
    // Compacted-size queries written in one frame slot, read when the slot comes round again.
    struct CompactionQueries {
        VkQueryPool pool = VK_NULL_HANDLE;
        uint32_t capacity = 0;
        std::vector<std::pair<world::LodCoord, uint64_t>> chunks; // Query i: chunk, build serial.
    };
    struct PendingBuild; // A pending chunk and its staging and scratch sizes.
    struct BuildBatch;   // Geometry and build infos of one frame's BLAS call.

    bool ensure_indices(uint32_t slots);
    void apply_mesh(world::LodCoord c, ChunkGpu& g, bool inserted, const world::ChunkMesh& mesh,
                    std::span<const int> changed_slices, ChunkTraits traits);
    void demote_idle_hot_chunks();
    VkDeviceSize staging_bytes(const ChunkGpu& g) const;
    bool allocate_chunk(world::LodCoord c, ChunkGpu& g, const VkAccelerationStructureBuildSizesInfoKHR& sizes);
    void cool_down_failed(world::LodCoord c, ChunkGpu& g);
    void fail_chunk(world::LodCoord c, ChunkGpu& g, VkDeviceSize bytes);
    void upload_chunk(ChunkGpu& g, bool whole);
    PendingBuild plan_chunk(world::LodCoord c, ChunkGpu& g) const;
    std::vector<PendingBuild> take_pending(std::vector<world::LodCoord>& later);
    bool allocate_batch(std::span<const PendingBuild> pending, size_t& first, size_t& count);
    void fail_alone(const PendingBuild& p);
    void prepare_chunk(const PendingBuild& p, BuildBatch& batch);
    void record_blas_builds(VkCommandBuffer cmd, BuildBatch& batch);
    void record_compactions(VkCommandBuffer cmd);
    void record_compaction_queries(VkCommandBuffer cmd);
    bool record_tlas(VkCommandBuffer cmd, world::BlockPos camera_block);
    void count_memory();
    void queue(world::LodCoord c, ChunkGpu& g); // Lists a pending chunk for the next record_builds().
    void retally(ChunkGpu& g);                    // Brings its share of m_total up to date.
    void sync_instance(world::LodCoord c, ChunkGpu& g); // Adds, updates or drops its TLAS instance.
    void drop_instance(ChunkGpu& g);
    void forget(ChunkGpu& g); // Before it is erased: its instance and tally go.
    VkDeviceAddress scratch(VkDeviceSize bytes); // 0: out of memory (logged).

    Context* m_ctx;
    std::unordered_map<world::LodCoord, ChunkGpu, world::LodCoordHash> m_chunks;
    Buffer m_indices;
    uint32_t m_index_slots = 0;
    StagingRing m_staging;
    Buffer m_scratch; // Shared by the frame's BLAS call and TLAS build (a barrier separates them).
    std::array<FrameData, kFramesInFlight> m_frames;
    std::array<CompactionQueries, kFramesInFlight> m_queries;
    std::vector<world::LodCoord> m_built_cold; // Chunks built cold this frame (to query).
    TlasInstances m_instances{kFramesInFlight};
    // Chunks with a pending build or refit (entries of chunks removed or re-added since are
    // skipped: ChunkGpu::queued), and hot chunks by the frame of their last edit (oldest first;
    // entries whose chunk was edited again since are stale).
    std::vector<world::LodCoord> m_pending;
    std::deque<std::pair<world::LodCoord, uint64_t>> m_hot_queue;
    ChunkGpu::Tally m_total;
    std::array<uint64_t, world::kMaxLodLevel + 1> m_level_bytes{}; // blas + vertices + quads by level.
    AccelStats m_stats;
    AccelMemory m_memory;
    SceneAccelCreateInfo m_info;
    // Staging and scratch bytes a frame's builds may take: kMaxFrameBuildBytes, halved at each
    // failed allocation and doubled back after each frame whose allocations succeed.
    VkDeviceSize m_staging_limit, m_scratch_limit;
    uint64_t m_frame = 0;       // record_builds() calls.
    uint64_t m_next_serial = 1;
    bool m_logged_failure = false;
};

} // namespace vx::render
