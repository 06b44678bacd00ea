#pragma once
// Chunk streaming around a viewer: a world much larger than memory, loaded from a store (or
// generated) and meshed as the viewer approaches, saved and dropped as it leaves.
//
// Radii, in chunks, measured from the viewer's chunk (Chebyshev horizontally, separately
// vertically): chunks within the view radius are meshed and handed to the MeshSink; their face
// neighbours (view radius + 1) are loaded too, so every mesh sees its real neighbours and none is
// ever remeshed because a neighbour arrived late. Chunks beyond the unload radius (view radius +
// 1 + margin) for longer than the unload delay are saved if dirty, then dropped; the margin and
// delay are the hysteresis that keeps chunks at the edge from thrashing. The same radii also apply
// around where the viewer will be in `lookahead_s` at its current velocity, so the chunks it
// flies into are meshed before they enter the view.
//
// Threads: the streamer lives on one thread (the main thread): construct it, call update() once
// per frame, edit, flush and destroy it there. Loads and saves run on the job system's serial I/O
// lane, generation and meshing on its pool; results are applied in update() within the budget.
// Saving: request_save() hands every edited chunk to the store and queues a flush behind them,
// returning a sequence number that save_state()/wait_saved() report on (engine/save_tracker.h).
//
// Time: every delay (save, unload, retries, store ticks) is measured on the clock the caller
// passes to update(), and edits are stamped with the last update's time, so a game clock at any
// offset from the steady clock (or a synthetic one) works; it must not run backwards. Only the
// frame budget is real time.
//
// A failed generation (a game's generator threw) leaves its chunk without data: nothing is
// drawn there and its neighbours mesh as if it were air (a visible hole, never invented
// terrain). It is logged and generated again after a back-off (1 s, doubling to 60 s, update
// time) while it stays in the loaded ring; settled() does not wait for it.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/job_system.h"
#include "engine/mesh_sink.h"
#include "engine/save_tracker.h"
#include "engine/stream_jobs.h"
#include "world/base/result.h"
#include "world/store/chunk_store.h"
#include "world/mesh/edit_mesher.h"
#include "world/gen/chunk_generator.h"
#include "world/world.h"

namespace vx::engine {

struct StreamingSettings {
    int view_radius = 12;          // Chunks meshed horizontally around the viewer's chunk.
    int view_radius_vertical = 4;  // Chunks meshed vertically.
    int unload_margin = 2;         // Extra chunks kept beyond the loaded ring before unloading.
    double unload_delay_s = 3.0;   // Time outside the unload radius before a chunk is dropped.
    double save_delay_s = 1.0;     // Edited chunks are handed to the store within this time.
    double store_tick_s = 0.5;     // How often the store is asked to commit (its own bound: 1 s).
    double lookahead_s = 1.5;      // Also mesh the view around where the viewer will be this soon.
    size_t memory_cap_bytes = 0;   // Block data cap (0: none). Never evicts inside the view radius.
    std::chrono::nanoseconds frame_budget{std::chrono::milliseconds(2)}; // Main-thread work per update().
    int worker_count = 0;          // Pool workers (0: cores - 1, at least 1).
};

struct StreamingMetrics {
    size_t loaded = 0;          // Chunks whose block data is in memory.
    size_t meshed = 0;          // Chunks in the view radius with a current mesh handed out.
    size_t wanted_meshes = 0;   // Chunks in the view radius (meshed when == meshed).
    size_t pending_data = 0;    // Loads/generations requested, not applied yet.
    size_t pending_meshes = 0;  // Mesh jobs requested, not applied yet.
    size_t dirty = 0;           // Edited chunks not yet handed to the store.
    size_t block_bytes = 0;     // Memory of loaded block data.
    uint64_t unloaded = 0, evicted = 0, saves = 0, regenerated_corrupt = 0;
    uint64_t reloaded = 0;      // Chunks reloaded because another process changed them.
    uint64_t load_failures = 0; // Loads the store could not answer (retried; nothing generated).
    size_t generate_failed = 0;      // Chunks whose generation failed, waiting for their retry.
    uint64_t generate_failures = 0;  // Generations that failed (a game's generator threw), in all.
    world::StoreHealth store;   // The store's connection and queue (shared stores).
    JobMetrics jobs;
    std::chrono::nanoseconds last_update_time{0}; // Wall time of the last update().
    std::chrono::nanoseconds last_update_cpu{0};  // Main-thread CPU time of it (excludes preemption).
};

// Block data arriving and leaving, for game logic (meshes go to the MeshSink). Main thread only:
// called from update() and edits, on the streamer's thread.
class StreamObserver {
public:
    virtual ~StreamObserver() = default;
    // Chunk `c`'s block data is now in the world (loaded from the store or generated).
    virtual void on_chunk_loaded(world::ChunkCoord c) = 0;
    // Chunk `c` was dropped (unloaded or evicted); its mesh, if any, left the sink just before.
    virtual void on_chunk_unloaded(world::ChunkCoord c) = 0;
};

class ChunkStreamer final : private StreamJobEvents {
public:
    // Main thread. `store` may be null (generate only, nothing persists); a read-only store
    // (VDB) keeps edits in memory only. Blocks mesh with `registry` (copied): its transparent
    // blocks mesh as transparent. The store, generator and sink must outlive the streamer; the
    // generator is called from pool workers (thread-safe const).
    ChunkStreamer(const world::ChunkGenerator& generator, world::ChunkStore* store, MeshSink& sink,
                  const StreamingSettings& settings = {},
                  const world::BlockRegistry& registry = world::BlockRegistry::default_registry());
    // Main thread. Saves dirty chunks and flushes the store (skipped when request_save() or
    // flush() ran and nothing was handed to the store since: one flush, not two; a request whose
    // flush has not run yet is waited for), then stops the jobs.
    ~ChunkStreamer();
    ChunkStreamer(const ChunkStreamer&) = delete;
    ChunkStreamer& operator=(const ChunkStreamer&) = delete;

    // Main thread, once per frame. `position` and `forward` in world block units; a position
    // closer than 2^17 blocks to the world's edge (world::inside_edge_margin) is clamped to it.
    void update(const glm::dvec3& position, const glm::dvec3& forward, std::chrono::steady_clock::time_point now);
    // The same with the viewer's velocity (blocks per second) given instead of estimated from
    // the positions of past frames.
    void update(const glm::dvec3& position, const glm::dvec3& forward, const glm::dvec3& velocity,
                std::chrono::steady_clock::time_point now);
    // Main thread. Null: none. The observer must outlive the streamer or be reset first.
    void set_observer(StreamObserver* observer) { m_observer = observer; }

    // Main thread. Sets a block of a loaded chunk; meshes update through the six-slice path.
    // Fails (nothing changes) when the chunk is not loaded. The edit is stamped with the last
    // update()'s time: it is handed to the store save_delay_s after that, in update() time.
    Status set_block(world::BlockPos p, world::BlockId id);
    // Main thread. Air for chunks not loaded.
    world::BlockId get_block(world::BlockPos p) const { return m_world.get_block(p); }

    // Main thread. Hands every edited chunk to the store and waits until the store has made
    // everything acknowledged so far durable. Blocks; call rarely (e.g. on save or quit).
    Status flush();
    // Main thread; does not block. Hands every edited chunk to the I/O lane and queues a store
    // flush behind them; returns its sequence number (with no store: one already durable).
    uint64_t request_save();
    // Thread-safe. Where save `sequence` stands; wait_saved() blocks until it is durable or failed.
    SaveState save_state(uint64_t sequence) const { return m_saves_done->state(sequence); }
    Status wait_saved(uint64_t sequence) const { return m_saves_done->wait(sequence); }
    // Thread-safe. The tracker of request_save()'s sequences; may outlive the streamer.
    std::shared_ptr<const SaveTracker> save_tracker() const { return m_saves_done; }

    // Main thread. True when every chunk the view needs is loaded and meshed and no chunk is due
    // to be unloaded: nothing is left to do until the viewer moves (or time passes).
    bool settled() const;
    StreamingMetrics metrics() const;
    const world::World& world() const { return m_world; }
    // Main thread. The job system the streamer's jobs run on (the LodStreamer's run there too).
    JobSystem& jobs() { return *m_jobs; }
    // Main thread. The mesh of chunk c, or null.
    const world::ChunkMesh* mesh(world::ChunkCoord c) const;
    // Main thread. Calls fn(coord, mesh) for every chunk whose current (non-empty) mesh was
    // handed to the sink: what a new sink or renderer needs to show the world as it is.
    template <class F> void for_each_mesh(F&& fn) const {
        for (const auto& [c, s] : m_chunks)
            if (s.has_mesh && s.mesh)
                fn(c, *s.mesh);
    }

private:

    enum class Data : uint8_t {
        Requested, // A load or generation is in flight.
        Present,   // Block data in m_world.
        Failed,    // Generation failed; requested again at retry_at.
    };
    struct ChunkState {
        Data data = Data::Requested;
        bool has_mesh = false;      // `mesh` is current and was handed to the sink.
        // The sink holds a mesh of this chunk (maybe an outdated one: has_mesh is cleared when a
        // neighbour's change asks for a new mesh, but the old one stays drawn until it comes, or
        // until the chunk goes: then the sink is told, whatever has_mesh says).
        bool in_sink = false;
        // Another process changed it while its load was in flight (a shared store's feed): the
        // load may have read the older version, so it is read again once present.
        bool changed_while_requested = false;
        bool mesh_pending = false;  // A mesh job is in flight.
        bool mesh_stale = false;    // The in-flight mesh job's snapshot is out of date.
        bool dirty = false;         // Edited since it was last handed to the store.
        bool outside = false;       // Beyond the unload radius since `outside_since` (queued then).
        bool evict_listed = false;  // In m_evict (memory cap candidates).
        std::chrono::steady_clock::time_point outside_since{}, dirty_since{};
        std::chrono::steady_clock::time_point retry_at{}; // Failed: when to generate again.
        uint8_t failures = 0;       // Generations failed in a row (the back-off doubles with each).
        size_t bytes = 0;           // Block data memory accounted for.
        std::unique_ptr<world::ChunkMesh> mesh; // Null while the mesh is empty (air, buried).
        // Block edits not yet handed to the store, oldest first (a shared store re-applies them
        // when another process wrote the chunk meanwhile; a reload keeps them on top).
        std::vector<world::BlockEdit> edits;
        // The store's version of the chunk (world::ChunkLoad::version) under `edits`: what its
        // saves replace (0: absent, generated here, or a store with one writer).
        uint64_t store_version = 0;
    };

    // StreamJobEvents: results from jobs (main thread, via complete()).
    void on_loaded(world::ChunkCoord c, std::optional<world::Chunk> chunk, uint64_t version,
                   const std::string& problem, bool store_failed) override;
    void on_reloaded(world::ChunkCoord c, std::optional<world::Chunk> chunk, uint64_t version) override;
    void on_generated(world::ChunkCoord c, world::Chunk chunk) override;
    void on_generate_failed(world::ChunkCoord c, const std::string& error) override;
    void retry_failed(std::chrono::steady_clock::time_point now);
    void on_meshed(world::ChunkCoord c, world::ChunkMesh mesh) override;
    void on_saved(world::ChunkCoord c, const std::string& error, size_t edits_saved) override;
    void on_store_commit(const Status& status) override;
    void poll_store_changes();
    void remesh_around(world::ChunkCoord c);
    StreamJobEvents& events() { return *this; } // What jobs report to (a private base).
    void update_viewer(const glm::dvec3& position, const glm::dvec3& forward, const glm::dvec3* velocity,
                       std::chrono::steady_clock::time_point now);

    void refresh_region(world::ChunkCoord old_center, world::ChunkCoord old_lead, bool first,
                        std::chrono::steady_clock::time_point now);
    void note_left(world::ChunkCoord c, std::chrono::steady_clock::time_point now);
    void note_evictable(world::ChunkCoord c, ChunkState& s);
    std::unique_ptr<Job> request_data(world::ChunkCoord c);
    void put_chunk(world::ChunkCoord c, world::Chunk chunk);
    bool neighbours_settled(world::ChunkCoord c) const; // Present, or failed (meshed as air).
    void queue_mesh(world::ChunkCoord c); // A mesh candidate, if it wants a mesh now.
    void schedule_meshes(std::chrono::steady_clock::time_point deadline);
    std::unique_ptr<Job> request_mesh(world::ChunkCoord c, ChunkState& s); // Null: no job needed.
    void set_mesh_flags(world::ChunkCoord c, ChunkState& s, bool has_mesh, bool pending);
    void unload_far(std::chrono::steady_clock::time_point now, std::chrono::steady_clock::time_point deadline);
    void drop(world::ChunkCoord c, ChunkState& s);
    void save_dirty(std::chrono::steady_clock::time_point now, bool all);
    void enforce_memory_cap(std::chrono::steady_clock::time_point deadline);
    bool near(world::ChunkCoord c, world::ChunkCoord center, int extra) const;
    bool in_view(world::ChunkCoord c) const;        // The view radius around the viewer.
    bool wants_mesh(world::ChunkCoord c) const;     // ... or around where it is heading.
    bool in_loaded_ring(world::ChunkCoord c) const; // Either of those, plus one chunk.
    bool beyond_unload(world::ChunkCoord c) const;

    const world::ChunkGenerator& m_generator;
    world::ChunkStore* m_store;
    MeshSink& m_sink;
    StreamObserver* m_observer = nullptr;
    StreamingSettings m_settings;
    world::World m_world;
    world::EditMesher m_edits;
    std::unordered_map<world::ChunkCoord, ChunkState, world::ChunkCoordHash> m_chunks;
    // Chunks that may be ready to mesh: in the view (meshed first), and around the lookahead
    // point only. Chunks that want no mesh are never queued (queue_mesh()), so a frame's walk
    // visits only chunks it may mesh, not every chunk of the loaded ring's edge again and again.
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> m_mesh_candidates, m_ahead_candidates;
    // Per-frame work follows what changed, never every loaded chunk: chunks that left the unload
    // radius wait in m_outside by the time they left, edited chunks in m_dirty by edit time (both
    // oldest first), memory-cap candidates (outside the loaded ring) in m_evict.
    struct Since {
        world::ChunkCoord chunk;
        std::chrono::steady_clock::time_point time;
    };
    std::deque<Since> m_outside, m_dirty;
    std::vector<world::ChunkCoord> m_evict; // Nearest first once sorted (evicted from the back).
    bool m_evict_sorted = false;            // Sorted for m_center, nothing appended since.
    world::ChunkCoord m_center{INT32_MIN};
    world::ChunkCoord m_lead{INT32_MIN}; // Chunk the viewer reaches in lookahead_s at its velocity.
    bool m_have_center = false;
    glm::dvec3 m_prev_position{0.0}, m_velocity{0.0}; // Blocks/s, smoothed over frames.
    std::chrono::steady_clock::time_point m_prev_time{}, m_last_now{};
    std::chrono::steady_clock::time_point m_last_tick{};
    size_t m_block_bytes = 0;
    // Counts kept as states change, so metrics() costs O(1) (a frame loop may call it every frame).
    size_t m_requested = 0, m_present = 0, m_mesh_pending = 0, m_dirty_count = 0;
    size_t m_view_meshed = 0; // Chunks in the view radius with a current mesh.
    uint64_t m_unloaded = 0, m_evicted = 0, m_saves = 0, m_regenerated = 0;
    uint64_t m_reloaded = 0, m_load_failures = 0;
    size_t m_failed = 0;              // Chunks in Data::Failed.
    uint64_t m_generate_failures = 0; // Since construction.
    // Failed generations, retried from their time on (entries of chunks dropped or re-failed since
    // are stale: their state's retry_at differs).
    std::vector<std::pair<world::ChunkCoord, std::chrono::steady_clock::time_point>> m_failed_retry;
    uint64_t m_saves_at_request = UINT64_MAX; // m_saves at the last request_save() (never: max).
    uint64_t m_last_request = 0;              // Its sequence, with a flush queued (0: none).
    bool m_store_failing = false; // Loads are failing (logged once until one succeeds).
    bool m_commits_failing = false; // Periodic commits are failing (logged once until one succeeds).
    // Loads the store could not answer, asked again from this time on (oldest first).
    std::deque<std::pair<world::ChunkCoord, std::chrono::steady_clock::time_point>> m_retry;
    std::vector<world::ChunkCoord> m_changed; // Scratch for the store's change feed.
    std::chrono::nanoseconds m_last_update{0}, m_last_update_cpu{0};
    // Shared with flush jobs (which report to it) and with whoever asks after the streamer is gone.
    std::shared_ptr<SaveTracker> m_saves_done = std::make_shared<SaveTracker>();
    // Declared last: destroyed first, so no job outlives the state it reports to.
    std::unique_ptr<JobSystem> m_jobs;
};

} // namespace vx::engine
