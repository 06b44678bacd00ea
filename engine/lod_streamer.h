#pragma once
// Levels of detail to the horizon (issue 16): coarse chunks around the viewer, and which level is
// drawn where, swapped so that no frame ever has a hole.
//
// What is drawn is a cut through the octree of levels (world/lod/lod_cut.h): every point under a
// root (a top-level chunk within the view distance) is covered by exactly one drawn chunk. The
// drawn cut follows LodView's target cut with a lag, by two atomic swaps only:
//   - refine: a drawn chunk the target refines is replaced by its 8 children once all 8 are
//     ready (meshed), in one update: the coarse chunk stays drawn until every finer chunk
//     replacing it is ready;
//   - coarsen: the drawn chunks under a target chunk are replaced by it once it is ready.
// A root is drawn (coarse first) as soon as it is ready, and nothing under a root is drawn
// before it: holes can only be roots not ready yet (the first frames), counted in holes().
// The boxes nest, and every box chunk is kept ready, so a coarsening never waits on data that is
// not coming. Where levels meet, coarse chunks are meshed with air around them (every border face
// drawn; engine/lod_jobs.h), and coarse cells are solid wherever a block under them is: seams
// are closed, and a ray may stop early by less than a cell, never pass through.
//
// Level 0 is the ChunkStreamer's: this class is its MeshSink, forwarding only the level-0 chunks
// of the drawn cut (edits' slices included) to the downstream sink, and keeping the pointers to
// the others' meshes (valid until the streamer's next call for the chunk) for when they are
// drawn. Coarse levels 1..top are kept here: loaded from the store (coarse levels of a stored
// world) or made by the generator (generate_lod: the terrain makes them directly), meshed on the
// pool. A block edit climbs the levels within the next update (world::refresh_octant), remeshes
// the coarse chunks that changed, and saves them (stores that keep coarse levels).
//
// Threads: main thread only, like the ChunkStreamer (jobs run on its job system and report here
// in its update()). Time: the caller's clock, as the ChunkStreamer's. Units: world blocks.

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/job_system.h"
#include "engine/lod_jobs.h"
#include "engine/mesh_sink.h"
#include "world/block_registry.h"
#include "world/lod/lod_cut.h"
#include "world/store/chunk_store.h"
#include "world/world.h"

namespace vx::engine {

// The downstream of the LodStreamer: level-0 meshes as MeshSink, coarse ones here. Main thread.
class LodMeshSink : public MeshSink {
public:
    // Coarse chunk `c` (level >= 1) is drawn with `mesh` (cells of 2^level blocks, chunk-local);
    // replaces what was drawn for `c`. `mesh` stays valid and unchanged until the next call for c.
    virtual void on_lod_mesh(world::LodCoord c, const world::ChunkMesh& mesh) = 0;
    // Coarse chunk `c` is no longer drawn.
    virtual void on_lod_unload(world::LodCoord c) = 0;
};

struct LodMetrics {
    int top_level = 0;
    // Per level (index = level, 0..kMaxLodLevel): chunks drawn, and coarse chunks kept (with
    // block data) and their block memory. Level 0's kept data is the ChunkStreamer's.
    std::array<uint32_t, world::kMaxLodLevel + 1> drawn{}, kept{};
    std::array<uint64_t, world::kMaxLodLevel + 1> block_bytes{};
    uint32_t holes = 0;          // Roots within the view distance with nothing drawn (last update).
    // Of those, roots whose data failed (a generator threw) and waits for its retry: settled()
    // does not wait for them, as ChunkStreamer's does not for failed generations.
    uint32_t failed_holes = 0;
    uint32_t root_chunks = 0;    // Roots within the view distance.
    uint64_t swaps = 0;          // Refines and coarsenings since construction.
    uint64_t forced_drops = 0;   // Level-0 chunks the streamer unloaded while drawn with no ready
                                 // ancestor to take their place (a hole until one is ready).
    size_t pending_data = 0, pending_meshes = 0; // Coarse jobs in flight.
    uint64_t data_failures = 0;  // Coarse chunks neither the store nor the generator could make.
    uint64_t edits_applied = 0;  // Coarse chunks rewritten by block edits.
};

class LodStreamer final : public MeshSink, private LodJobEvents {
public:
    // `settings`: radius0/vradius0 must be the ChunkStreamer's view radii (level 0's box). The
    // generator, store, registry and downstream must outlive this object. `store` may be null.
    LodStreamer(const world::ChunkGenerator& generator, world::ChunkStore* store, LodMeshSink& downstream,
                const world::LodViewSettings& settings, const world::BlockRegistry& registry);
    ~LodStreamer() override;
    LodStreamer(const LodStreamer&) = delete;
    LodStreamer& operator=(const LodStreamer&) = delete;

    // Main thread, once, before the first update(): the ChunkStreamer's job system and world
    // (both outlive every later call; the job system is stopped before this object goes).
    void attach(JobSystem& jobs, const world::World& blocks);

    // MeshSink, from the ChunkStreamer (level 0).
    void on_mesh(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) override;
    void on_unload(world::ChunkCoord c) override;
    // Passed down, whichever level draws the block: the light near it changed.
    void on_block_edited(world::BlockPos p) override { m_down.on_block_edited(p); }

    // Main thread. Level-0 chunk `c`'s blocks changed (an edit): its coarse ancestors follow in
    // the next update().
    void note_edit(world::ChunkCoord c);
    // Main thread. Applies the edits noted so far to the coarse levels kept here, while their
    // chunks are still in memory: call before the ChunkStreamer's update(), which may drop them
    // (update() applies what is left). An edited chunk already gone has its ancestors marked stale
    // instead: the stored ones and those kept here are derived from its saved blocks.
    void apply_edits();
    // Main thread. Applies the edits noted since the last update() now and submits their coarse
    // saves and stale marks, so a store flush requested next (Engine::save, shutdown) carries
    // them with the edits' own chunks: a coarse level saved or marked stale with its blocks,
    // neither without the other (chunk_store.h), also when no frame ran between.
    void flush_edits();

    // Main thread, once per frame after the ChunkStreamer's update(). `viewer` in world blocks.
    // Swaps and bookkeeping stop at `deadline` (a few always happen, so the cut keeps moving).
    void update(const glm::dvec3& viewer, std::chrono::steady_clock::time_point now,
                std::chrono::steady_clock::time_point deadline);

    // Main thread. Nothing left to do until the viewer moves: every root drawn (but those whose
    // data failed, until their retry) and the drawn cut equal to the target cut.
    bool settled() const;
    LodMetrics metrics() const;
    int top_level() const { return m_view ? m_view->top_level() : 0; }
    // Main thread. `c` is a root of the current view (a top-level chunk within the view distance).
    bool is_root(world::LodCoord c) const { return m_roots.contains(c); }
    // Main thread. Coarse chunk `c`'s cells when kept and present, else null (tests, tools).
    const world::Chunk* coarse_chunk(world::LodCoord c) const;
    // Main thread. Calls fn(coord, mesh) for every drawn chunk (a new renderer's scene).
    template <class F> void for_each_drawn(F&& fn) const {
        for (const world::LodCoord& c : m_drawn)
            if (const world::ChunkMesh* m = mesh_of(c))
                fn(c, *m);
    }

private:
    enum class Data : uint8_t { Requested, Present, Failed };
    struct Node {
        Data data = Data::Requested;
        bool kept = true;           // In its level's box (its data is wanted).
        bool meshed = false;        // `mesh` is current (null: nothing to draw).
        bool mesh_pending = false;  // A mesh job is in flight.
        bool mesh_stale = false;    // Its snapshot predates an edit: mesh again when it returns.
        bool submitted = false;     // Requested: its load/generate job was submitted.
        bool reload_on_arrival = false; // Requested: made stale meanwhile; load again when it lands.
        bool merge_children = false;    // Reloaded: its children held here refresh it on arrival.
        uint8_t failures = 0;       // Data failures in a row (retry back-off).
        std::chrono::steady_clock::time_point retry_at{};
        world::Chunk chunk;         // Present: the cells.
        std::unique_ptr<world::ChunkMesh> mesh;
    };

    // LodJobEvents.
    void on_lod_data(world::LodCoord c, std::optional<world::Chunk> chunk, const std::string& error) override;
    void on_lod_meshed(world::LodCoord c, world::ChunkMesh mesh) override;
    void on_lod_saved(world::LodCoord c, const std::string& error) override;

    LodJobEvents& events() { return *this; } // What jobs report to (a private base).
    void move_view(const glm::dvec3& viewer);
    void keep(world::LodCoord c);
    void release(world::LodCoord c);
    void request_data(world::LodCoord c, Node& n);
    std::unique_ptr<const world::LodOverlay> edited_under(world::LodCoord c) const;
    void mark_stale(world::ChunkCoord edited, int from);
    void reload(world::LodCoord c, Node& n);
    void merge_children(world::LodCoord c, Node& n);
    void request_mesh(world::LodCoord c, Node& n);
    void retry_failed(std::chrono::steady_clock::time_point now);

    bool ready(world::LodCoord c) const;
    const world::ChunkMesh* mesh_of(world::LodCoord c) const;
    bool drawn(world::LodCoord c) const { return m_drawn.contains(c); }
    int below(world::LodCoord c) const;
    bool under_root(world::LodCoord c) const;
    bool target_leaf(world::LodCoord c) const;
    void enqueue(world::LodCoord c);
    void became_ready(world::LodCoord c);
    void process(world::LodCoord c);
    void draw(world::LodCoord c);
    void undraw(world::LodCoord c);
    void clear_below(world::LodCoord c);
    void count_holes();

    const world::ChunkGenerator& m_generator;
    world::ChunkStore* m_store;
    LodMeshSink& m_down;
    world::LodViewSettings m_settings;
    world::BlockRegistry m_registry;
    JobSystem* m_jobs = nullptr;
    const world::World* m_blocks = nullptr;

    std::optional<world::LodView> m_view; // Built at the centre of the viewer's level-0 chunk.
    glm::dvec3 m_viewer{0.0};
    std::unordered_map<world::LodCoord, Node, world::LodCoordHash> m_coarse;
    std::unordered_map<world::ChunkCoord, const world::ChunkMesh*, world::ChunkCoordHash> m_fine;
    std::unordered_set<world::LodCoord, world::LodCoordHash> m_drawn;
    // Drawn chunks strictly below each chunk that has any (coverage and subtree walks).
    std::unordered_map<world::LodCoord, int, world::LodCoordHash> m_below;
    std::unordered_set<world::LodCoord, world::LodCoordHash> m_roots;
    std::deque<world::LodCoord> m_queue;
    std::deque<world::LodCoord> m_to_request; // Kept chunks whose data is not requested yet.
    std::deque<world::LodCoord> m_to_release; // Chunks that left their box, to drop.
    std::unordered_set<world::LodCoord, world::LodCoordHash> m_queued;
    // Edited level-0 chunks not yet applied to the kept levels, each with the level it waits for
    // to load (0: none; applied on arrival, climbing every kept level above; negative: that level,
    // marked stale by flush_edits).
    std::unordered_map<world::ChunkCoord, int, world::ChunkCoordHash> m_edited;
    std::vector<std::pair<world::LodCoord, std::chrono::steady_clock::time_point>> m_retry;
    std::vector<std::unique_ptr<Job>> m_batch; // Jobs made this update, submitted at its end.
    std::chrono::steady_clock::time_point m_last_now{};
    // Coarse chunks the store marked stale when this object was made, and those marked since
    // (mark_stale): derived on load. Copied on change: jobs in flight hold the set they began with.
    std::shared_ptr<const world::LodDirtySet> m_stale;
    // Marked stale in this session (mark_stale): derived without saving, as level-0 edits under
    // them may not be saved yet; the marks stay for the next session.
    world::LodDirtySet m_marked_here;
    // Level-0 chunks edited in this session, while in memory (the overlay of derivations: the
    // store may not have their edits yet). Those dropped since, and so saved, are pruned by
    // note_edit as the set doubles.
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> m_edited_here;
    size_t m_prune_edited_at = 1024; // Its size at which note_edit() prunes it next (amortised).
    int m_draws = 0; // Chunks drawn in this update (the queue's budget).
    bool m_holes_dirty = true;
    LodMetrics m_metrics;
};

} // namespace vx::engine
