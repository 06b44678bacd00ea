#pragma once
// vx: a streaming voxel world with a ray-traced renderer, embedded in a game through one object.
//
//   auto engine = vx::Engine::create(info);           // world source, blocks, radii, render target
//   each frame: engine->set_viewer(v); engine->update(); engine->render_to_image(img);
//   edits:      engine->set_block(p, id);  queries: get_block, raycast;  engine->save();
//
// Threads. An Engine is used by one thread at a time, the "main thread": the one that created it,
// or any other the game moves it to between calls (created on a loading thread, then updated by
// the game loop), ordering the two with its own synchronisation (a join, a mutex). Every member
// function is "main thread only" unless its comment says "thread-safe". A call made while another
// thread is inside the engine is refused, touching nothing: it returns an error (nullopt, false,
// empty or zero stats where there is no Status) and the first such refusal is logged. (A window
// target's GLFW calls keep GLFW's own rule: the process's main thread.) Inside, the engine runs
// worker threads (generation, meshing; StreamingDesc::worker_threads) and one I/O thread (the
// store); a game's Generator is called on the workers. update() applies their results within a
// time budget; nothing else calls back into the game from another thread, except a log handler
// the game sets (<vx/log.h>).
// Units: world block units (one block = 1), seconds, milliseconds where a name ends in _ms,
// bytes where it ends in _bytes. Coordinates: see <vx/types.h>.
// Errors: recoverable failures return vx::Status / vx::Result<T> with a one-line message;
// failures inside the engine's threads (a chunk, a save) are logged: see <vx/log.h> to take the
// log (vx::set_log_handler), else it goes to stderr.
// The structs are plain values (copy them; not thread-safe to share while one thread writes).
// Nothing here exposes Vulkan, SQLite or OpenVDB.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include <vx/log.h>
#include <vx/render_settings.h>
#include <vx/result.h>
#include <vx/types.h>

namespace vx {

// A game's own world generator. Called on worker threads, several chunks at once: it must be
// thread-safe through const (no unsynchronised mutable state). Deterministic output is expected:
// an unedited chunk that was unloaded is generated again when the viewer returns, and its
// neighbours were meshed against the first result.
// Failure: generate() or uniform() may throw (anything). The engine catches it on the worker and
// nothing of that chunk is used (never a half-filled one): the chunk stays unloaded (get_block
// nullopt, set_block fails, raycast stops there as Unloaded), nothing is drawn in its place and
// its neighbours are drawn as if it were air, so the game sees a hole, never invented terrain.
// One log line names the chunk and what() (LogLevel::Error); Stats::chunks_generate_failed and
// generate_failures count it. The chunk is generated again after 1 s, then 2, 4, ... up to 60 s
// of update() time while it stays within the loaded radius; settled() does not wait for it.
// Levels of detail: a coarse chunk (cells of 2^k blocks) comes from generate_coarse() below, or
// else from generated blocks, 8^k generate() calls per level-k chunk; one whose blocks fail is a
// hole (Stats::holes, a top-level chunk) or leaves the coarser chunk above drawn, retried alike.
class Generator {
public:
    virtual ~Generator() = default;
    // Worker threads. Fills `blocks` (kChunkVolume ids, chunk-local index chunk_index(x, y, z);
    // local (0,0,0) is world chunk_origin(chunk)) with ids of the engine's blocks. `blocks`
    // arrives all air. Ids beyond the registered blocks render with a generated colour.
    virtual void generate(ChunkCoord chunk, std::span<BlockId> blocks) const = 0;
    // Worker threads. Optional fast path: when chunk `chunk` is all one id (open sky, deep rock),
    // return it and generate() is not called for that chunk. Default: never.
    virtual std::optional<BlockId> uniform(ChunkCoord) const { return std::nullopt; }
    // Worker threads. Optional, for levels of detail (StreamingDesc::view_distance): fills `cells`
    // (kChunkVolume ids, chunk_index order, arriving all air) with the level-`level` chunk at
    // `chunk` and returns true. Level k has cells of 2^k blocks: cell (x, y, z) covers blocks
    // chunk * 32 * 2^k + 2^k * (x, y, z) ... + 2^k - 1 on each axis. A cell must be non-air
    // wherever any block under it would be (coarse ground may rise by less than a cell, never
    // sink: a ray must never pass through it); its id is what the surface shows from afar.
    // Returning false (the default) or throwing: the engine builds that chunk by generating the
    // blocks under it and downsampling them (8^level generate() calls).
    virtual bool generate_coarse(int level, ChunkCoord chunk, std::span<BlockId> cells) const {
        (void)level;
        (void)chunk;
        (void)cells;
        return false;
    }
    // Any thread. The highest level generate_coarse() makes (0: none). Without coarse chunks the
    // engine keeps to levels 1 and 2 (cells of 2 and 4 blocks, 64 generate() calls per level-2
    // chunk), so the view reaches about lod_ring * 128 blocks, not view_distance.
    virtual int coarse_levels() const { return 0; }
    // Any thread. The generator's identity. A stored world (WorldSource::sqlite) records the
    // generator that made it and refuses to reopen with another one (another name or version,
    // or the built-in terrain), whose unedited chunks would not meet the stored ones. Put what
    // changes the output in the name (e.g. "waves seed=7") and raise version() when the code's
    // output changes. Defaults: "game", version 1 (one generator per game, never changed).
    virtual std::string_view name() const { return "game"; }
    virtual uint32_t version() const { return 1; }
};

// Where the world's chunks come from. Use the helpers below.
struct WorldSource {
    enum class Kind : uint8_t {
        Terrain,   // The built-in terrain of `seed`. Nothing persists.
        Generator, // The game's `generator`. Nothing persists.
        Sqlite,    // A stored world, read-write, created if missing: `path` is a SQLite file, or a
                   // PostgreSQL URI (postgresql://[user@]host[:port]/db?...) for a world several
                   // processes share (their edits of one chunk merge; changes by others reload
                   // within ~100 ms; a lost server is retried, edits kept; a server that stops
                   // answering fails a call after vx_query_timeout_ms=N in the URI, default
                   // 15000, edits kept: docs/embedding.md). Chunks it lacks come
                   // from `generator` if set, else the built-in terrain of `seed`. The world
                   // remembers which (Generator::name and version, or the terrain and its seed):
                   // create() refuses to reopen it with another.
        Vdb,       // A vx VDB world file at `path` (vx export-vdb). Its edits persist in an
                   // overlay store (`overlay`; default "<path>.edits.sqlite", created if
                   // missing), read before the file: save(), unloads and crashes behave as for
                   // Sqlite, the file is never written, and `vx export-vdb <path>` writes the
                   // merged world. An overlay made for another file (size, xxh64 of its bytes)
                   // is refused. With `read_only`, no overlay: edits stay in memory (lost when
                   // their chunk unloads) and save() fails. The file is read in a forked child
                   // with memory and CPU caps, so a damaged file is an error from create(), not a
                   // crash (create() must then be called while the process has no other thread
                   // inside OpenVDB or TBB). Chunks outside the file come from `generator` if
                   // set, else are air. Needs vx::vdb linked into the program
                   // (find_package(vx COMPONENTS vdb)); else create() says so.
    };
    Kind kind = Kind::Terrain;
    uint64_t seed = 1;
    std::shared_ptr<const Generator> generator; // Shared with the engine's workers until shutdown.
    std::string path;
    std::string overlay;    // Vdb: the edit store (SQLite path or PostgreSQL URI); "": beside `path`.
    bool read_only = false; // Vdb: no overlay, edits are not kept (see Kind::Vdb).
    // Set by sqlite(path, generator): create() refuses a null `generator` rather than fall back
    // to the terrain of `seed`, which the stored world would then remember for good.
    bool generator_required = false;

    static WorldSource terrain(uint64_t seed);
    static WorldSource custom(std::shared_ptr<const Generator> generator);
    static WorldSource sqlite(std::string path, uint64_t seed);
    static WorldSource sqlite(std::string path, std::shared_ptr<const Generator> generator);
    static WorldSource vdb(std::string path, std::shared_ptr<const Generator> generator = nullptr);
};

// Levels of detail 0..kLodLevels-1 (level k: cells of 2^k blocks; level 0 is the blocks).
inline constexpr int kLodLevels = 11;

// The streamed world: a viewer's block lies in [-kStreamedWorldExtent, kStreamedWorldExtent - 1]
// on every axis (Engine::set_viewer refuses others), so the box loaded around it stays inside the
// world's 32-bit chunk coordinates. Blocks.
inline constexpr int64_t kStreamedWorldExtent = (int64_t(1) << 36) - (int64_t(1) << 17);

// How much of the world is kept around the viewer. Radii in chunks from the viewer's chunk
// (square horizontally, separately vertically). Chunks within the view radius are meshed (and
// drawn); one more ring is loaded so meshes see their neighbours; beyond view + 1 + margin for
// unload_delay_s they are saved (if edited) and dropped.
struct StreamingDesc {
    int view_radius = 8;
    int view_radius_vertical = 4;
    int unload_margin = 2;        // Chunks, 0..64 (the radii too).
    double unload_delay_s = 3.0;  // Seconds outside before a chunk is dropped (>= 0; infinity: never).
    double save_delay_s = 1.0;    // Edited chunks reach the store within this (not yet durable;
                                  // >= 0; infinity: only save() and shutdown write them).
    size_t memory_cap_bytes = 0;  // Block data cap (0: none); never evicts inside the view.
    // Main-thread time update() may spend applying results, (0, 1000]; a few are applied in
    // every update whatever it is. Not bounded by it: listing the chunks a new view needs, on the
    // first update and after a teleport, in time that grows with the view's volume (2 cores:
    // about 3 ms at radius 8/4, 30 ms at 16/8, 0.3 s at 32/16).
    double update_budget_ms = 2.0;
    int worker_threads = 0;       // Generation/meshing threads, 0..256 (0: cores - 1, at least 1).
    // Levels of detail: terrain is drawn to `view_distance` blocks (horizontal, 0..65536): full
    // detail within view_radius, then levels with cells of 2, 4, 8, ... blocks, each reaching
    // lod_ring of its own chunks (chunks of 32 cells) around the viewer. Coarse levels are
    // generated directly (the built-in terrain; a Generator with generate_coarse) or loaded from
    // a stored world's coarse levels; edits reach them within the next update. Swaps between
    // levels never leave a hole: a coarse chunk stays drawn until all finer chunks replacing it
    // are meshed. 0 (or a distance within view_radius): full detail only, as without LOD.
    int64_t view_distance = 0;
    int lod_ring = 12;                 // 1..64; larger: finer far away, more chunks (R = 12:
                                       // a cell spans about 2.3 pixels at each level's edge, 1080p).
    int64_t lod_vertical_reach = 256;  // Blocks above and below the viewer coarse levels cover.
    // Together the level boxes may hold at most 2^20 coarse chunks (create() says how many);
    // the defaults hold about 12,500, lod_ring 64 to 65536 blocks about 380,000.
};

// What the engine draws into.
struct RenderTarget {
    enum class Kind : uint8_t {
        None,     // No GPU at all (a server, a tool): streaming, edits and queries only.
        Headless, // Render to an image in memory of width × height pixels (render_to_image).
        Window,   // Present to a GLFW window (render_to_window): `window` is its GLFWwindow*, not
                  // owned. The game calls glfwInit, creates it with GLFW_CLIENT_API =
                  // GLFW_NO_API, polls its events, and keeps it alive until the engine is gone.
                  // The frame follows the window's framebuffer size.
    };
    Kind kind = Kind::None;
    uint32_t width = 0, height = 0; // Headless: image size in pixels, 1..16384.
    void* window = nullptr;         // Window: a GLFWwindow*.

    static RenderTarget none() { return {}; }
    static RenderTarget headless(uint32_t width, uint32_t height) { return {Kind::Headless, width, height, nullptr}; }
    static RenderTarget glfw_window(void* glfw_window) { return {Kind::Window, 0, 0, glfw_window}; }
};

struct RenderDesc {
    RenderTarget target;
    std::string device = "auto"; // "auto", "cpu" (lavapipe), "gpu", or a device index (`vx info`).
    bool validation = false;     // Vulkan validation layer; errors counted in Stats.
    bool vsync = true;           // Window: wait for the display (FIFO); false: present at once
                                 // (MAILBOX, else IMMEDIATE). Change it later with set_vsync().
};

struct EngineCreateInfo {
    WorldSource world;
    // The game's blocks: id 0 is air, blocks[i] gets id i + 1. Empty: default_blocks().
    std::vector<BlockType> blocks;
    StreamingDesc streaming;
    RenderDesc render;
    // Record ChunkEvents for poll_events(). Off by default: an undrained queue grows without bound.
    bool chunk_events = false;
};

// The camera and the centre of streaming. Position = block + offset (64-bit exact anywhere).
struct Viewer {
    BlockPos block{0};                     // World block holding the eye.
    glm::dvec3 offset{0.5};                // Eye inside that block, blocks (|component| <= 2^40; whole
                                           // blocks are folded into `block`).
    glm::dvec3 forward{0.0, 0.0, -1.0};    // View direction (need not be unit).
    glm::dvec3 up{0.0, 1.0, 0.0};          // Approximate up; not parallel to forward.
    std::optional<glm::dvec3> velocity;    // Blocks per second; unset: estimated from positions.
    float fov_y_degrees = 60.f;            // Vertical field of view, degrees, in (0, 180).
};

// A ray in world space: from origin_block + origin_offset along `direction` (unit length), as
// Engine::raycast takes it.
struct ScreenRay {
    BlockPos origin_block{0};
    glm::dvec3 origin_offset{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

struct BlockEdit {
    BlockPos pos{0};
    BlockId id = kAir;
};

struct RayHit {
    enum class Kind : uint8_t {
        Hit,      // A non-air block: block, id, face, distance, previous are set.
        Miss,     // Only air within max_distance, all of it loaded.
        Unloaded, // The ray reached a chunk that is not loaded first: `block` is the first block
                  // of it on the ray and `distance` where the ray entered it. Nothing is known past.
    };
    Kind kind = Kind::Miss;
    bool inside = false;     // Hit: the origin was inside the block (distance 0).
    BlockPos block{0};
    BlockId id = kAir;
    Face face = Face::NegX;  // Hit: the face of `block` the ray entered through.
    double distance = 0.0;   // Blocks along the normalized direction.
    BlockPos previous{0};    // Hit: block + face_normal(face), where a placed block goes.
};

struct ChunkEvent {
    enum class Kind : uint8_t {
        Loaded,   // Block data arrived (store or generator); get_block answers for it now.
        Meshed,   // Its mesh is new or changed (by streaming or an edit); drawn from the next frame.
        Unloaded, // Block data and mesh dropped (saved first if edited).
    };
    Kind kind = Kind::Loaded;
    ChunkCoord chunk{0};
};

// Figures of the last update() and the last rendered frame, and gauges now.
struct Stats {
    double update_cpu_ms = 0;    // Main-thread CPU time of the last update().
    double update_wall_ms = 0;   // Its wall time.
    double render_cpu_ms = 0;    // CPU time recording the last frame (render_to_image).
    double render_wall_ms = 0;   // Wall time of that call (includes waiting for the GPU).
    double gpu_ms = 0;           // Submit to fence of the last frame (-1 for windowed frames).
    double frame_ms = -1;        // Window: time between the starts of the last two frames.
    double wait_ms = -1;         // Window: of it, blocked on the GPU or the display.
    double present_ms = -1;      // Window: time in the present call.
    double gpu_blas_ms = -1, gpu_tlas_ms = -1, gpu_trace_ms = -1; // GPU timestamps; -1: none.
    uint32_t blas_builds = 0, blas_refits = 0; // In the last frame.
    uint32_t instances = 0;      // Chunks drawn in the last frame.
    uint32_t failed_chunks = 0;  // Chunks not drawn: out of GPU memory (see the log).
    uint64_t upload_bytes = 0;   // Chunk geometry uploaded in the last frame (edits: slices only).
    uint64_t triangles = 0;      // Their triangles (spare slots included).
    float ev100 = 0;             // The exposure the last frame was drawn with (Exposure).
    size_t chunks_loaded = 0;    // Chunks with block data in memory.
    size_t chunks_queued = 0;    // Requested (load or generate), not arrived yet.
    size_t chunks_meshed = 0;    // In the view radius with a current mesh.
    size_t chunks_in_view = 0;   // In the view radius (all meshed when equal to chunks_meshed,
                                 // short by those of chunks_generate_failed in the view).
    size_t meshes_queued = 0;    // Mesh jobs in flight.
    size_t dirty_chunks = 0;     // Edited, not yet handed to the store.
    size_t chunks_generate_failed = 0; // Not loaded: the game's Generator threw for them (retried).
    uint64_t generate_failures = 0;    // Generator calls that threw, since creation (see the log).
    uint64_t chunks_unloaded = 0; // Since creation.
    size_t block_memory_bytes = 0; // Block data in memory.
    uint64_t gpu_memory_bytes = 0; // Device memory the renderer holds (0 without a GPU).
    uint64_t gpu_memory_used_bytes = 0; // Of it, in use.
    uint32_t validation_errors = 0; // Vulkan validation errors so far (validation on).
    // The GPU device was lost (a hang, a driver reset): frames fail until recreate_renderer().
    bool device_lost = false;
    uint32_t device_losses = 0;  // Losses seen since creation (each renderer's counted once).
    bool vsync = false;          // Window: the swapchain's present mode waits for the display.
    // Stored worlds: the store's state. A shared (PostgreSQL) world can lose its server: edits
    // then wait in memory (store_pending_edits) and are retried; nothing acknowledged is lost.
    bool store_connected = true;
    size_t store_pending_edits = 0; // Handed to the store, not yet committed.
    uint64_t store_conflicts = 0;   // Writes that met another process's and merged.
    uint64_t store_reconnects = 0;
    // A shared world hears other processes' changes late: its change listener is down (they
    // reload once it is back and has caught up).
    bool store_listener_down = false;
    uint64_t chunks_reloaded = 0;   // Reloaded because another process changed them.
    // Levels of detail (StreamingDesc::view_distance; index = level, cells of 2^level blocks).
    int lod_top_level = 0;          // Coarsest level in use (0: full detail only).
    std::array<uint32_t, kLodLevels> level_chunks_drawn{}; // Chunks drawn per level (empty ones too).
    std::array<uint32_t, kLodLevels> level_chunks_kept{};  // Coarse chunks kept per level (level 0: loaded).
    std::array<uint64_t, kLodLevels> level_block_bytes{};  // Their block data.
    std::array<uint64_t, kLodLevels> level_gpu_bytes{};    // GPU memory of the chunks drawn (BLAS + quads).
    // Holes: top-level chunks within the view distance that nothing drawn covers (a coarse chunk
    // not generated yet as it comes into view, or one whose generation failed, until its
    // retry works). Without LOD: chunks in the view radius not meshed yet. 0 once the view is
    // filled: level swaps never open one.
    uint32_t holes = 0;
    uint64_t lod_swaps = 0;         // Refinements and coarsenings since creation.
};

// A game's 2D UI (HUD, menus) over the rendered frames, without exposing a graphics API: each
// frame (or when it changes) the game hands the engine a list of textured, coloured triangles,
// e.g. Dear ImGui's ImDrawData converted (docs/embedding.md shows how), and once a texture (the
// font atlas). The engine draws the list over every later frame, after the trace and the
// denoiser, with alpha blending (straight alpha: colour * a + frame * (1 - a), blended on the
// bytes the screen shows, as Dear ImGui expects) and a scissor rectangle per command. Both
// render_to_image and render_to_window draw it, and captures include it.
// Pixels: framebuffer coordinates, (0, 0) the top-left corner of the top-left pixel, y down.
struct UiVertex {
    glm::vec2 pos{0.f}; // Pixels.
    glm::vec2 uv{0.f};  // 0..1 over the UI texture (bilinear, clamped to the edge).
    uint32_t rgba = 0;  // Colour, R in the low byte (as Dear ImGui's IM_COL32), straight alpha.
};
// Triangles indices[index_offset, index_offset + index_count), drawn only inside clip_rect =
// (x0, y0, x1, y1) in pixels (x1, y1 exclusive; clamped to the frame).
struct UiDrawCmd {
    uint32_t index_offset = 0, index_count = 0;
    glm::ivec4 clip_rect{0};
};
struct UiDrawList {
    std::vector<UiVertex> vertices;
    std::vector<uint32_t> indices; // Into vertices, three per triangle.
    std::vector<UiDrawCmd> cmds;   // Drawn in order, each over the ones before.
};

// A save in flight: poll save_state() or block in wait().
struct SaveTicket {
    uint64_t sequence = 0;
};
enum class SaveState : uint8_t {
    Pending, // Handed to the I/O thread; not durable yet.
    Durable, // Committed and synced: survives a crash of the process.
    Failed,  // Its flush failed (the message: wait()); a later save() may still cover it.
    Unknown, // Not a ticket this engine's save() returned (wait() says so).
};

class Engine {
public:
    // Main thread (becomes the engine's thread). Opens the world, starts the threads and the
    // renderer. Errors: a bad description, a store that cannot open, no usable GPU (with a
    // render target), a window target without a GLFWwindow*, a headless target whose frame
    // resources (about 240 bytes a pixel, the denoiser's included) cannot fit the device's
    // largest memory heap (the line names both), a block whose material is out of range (see
    // BlockType), a stored world made by another generator (see Generator::name), levels of detail
    // whose boxes would hold more than 2^20 coarse chunks (lod_ring, lod_vertical_reach).
    static Result<std::unique_ptr<Engine>> create(const EngineCreateInfo& info);
    // Main thread. shutdown() if not done (errors are logged).
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    // Main thread. Where the camera is and where streaming centres; takes effect at update().
    // Fails, keeping the previous viewer, on non-finite values, a position outside the streamed
    // world (|coordinate| < 2^36 - 2^17 blocks: the loaded box stays inside the world's 32-bit
    // chunk coordinates), an offset past 2^40 blocks, a zero forward or up, forward parallel to up,
    // or a field of view outside (0, 180) degrees.
    Status set_viewer(const Viewer& viewer);
    // Main thread, once per frame. Streams around the viewer, applies finished loads and meshes
    // (within update_budget_ms), unloads, saves edited chunks after save_delay_s. `now` is the
    // game's clock: every delay the engine keeps (save_delay_s, unload_delay_s, retries) is
    // measured on it and edits are stamped with the last update's `now`, so it may run at any
    // offset from the steady clock, or be synthetic (deterministic tests); it must not go back.
    // Only update_budget_ms is real time. Failures inside (a chunk that fails to load or
    // generate, a background save that fails) are logged and counted in Stats; the game goes on.
    void update(std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now());
    // Main thread. True when every chunk the view needs is loaded and meshed and nothing is due
    // to unload: the view is complete until the viewer moves. Chunks and coarse chunks whose
    // generation failed are not waited for (they are retried; Stats counts them).
    bool settled() const;

    // Main thread. Sets one block; its chunk and neighbours remesh at once (six slices). Fails,
    // changing nothing, when shut down, the position is outside the world, the chunk is not
    // loaded (or its generation failed) or the id is not a registered block. Stored worlds: the
    // edit is stamped with the last update()'s `now` and handed to the store by the first
    // update() at least save_delay_s later; a background save that fails is logged. save()
    // makes it durable and reports a failure through its ticket.
    Status set_block(BlockPos pos, BlockId id);
    // Main thread. All or nothing: checks every edit first (as set_block), then applies them in
    // order (a later edit of the same block wins). Fails on the first bad edit, changing nothing.
    Status set_blocks(std::span<const BlockEdit> edits);
    // Main thread. The block at `pos`, kAir for air; nullopt when its chunk is not loaded.
    std::optional<BlockId> get_block(BlockPos pos) const;
    // Main thread. First non-air block along the ray from origin_block + origin_offset in
    // `direction` (need not be unit; any finite length) within max_distance blocks; see
    // RayHit::Kind. Errors: zero or non-finite direction, negative or non-finite max distance, an
    // origin block outside the world or an offset past 2^40.
    Result<RayHit> raycast(BlockPos origin_block, glm::dvec3 origin_offset, glm::dvec3 direction,
                           double max_distance) const;
    // Thread-safe (after create). The id of a block by name, or nullopt.
    std::optional<BlockId> find_block(std::string_view name) const;
    // Thread-safe (after create). The block type registered at `id` (1..block_count()), or
    // nullopt for air (0) and ids past the registry.
    std::optional<BlockType> block_type(BlockId id) const;
    // Thread-safe (after create). How many block types are registered (air not counted): their
    // ids are 1..block_count().
    size_t block_count() const;
    // Main thread. The ray the renderer traces through `pixel` of the current frame (see
    // vx::screen_ray): mouse picking with raycast(). The frame size is the headless target's, or
    // for a window the last presented frame's. Errors: no render target (use vx::screen_ray
    // with the size), no frame presented yet, a non-finite pixel, shut down.
    Result<ScreenRay> screen_ray(glm::dvec2 pixel) const;

    // Main thread. Rendering options for later frames. Fails, keeping the previous settings, on
    // non-finite or negative light values, shadow samples over 1024, max_bounces over 16,
    // accumulate outside 1..1024, a sun radius outside 0..90 degrees, or a non-finite exposure.
    Status set_render_settings(const RenderSettings& settings);
    // Main thread. Headless target: traces the viewer's view and reads it into `out` (resized to
    // the target size). Blocks until the GPU is done. Errors: no GPU target, shut down; out of
    // GPU memory for a frame resource (target, G-buffer, read-back, TLAS, scratch, denoiser, UI):
    // `out` untouched, nothing else lost, the next call tries again; the device was lost:
    // Stats::device_lost, and every frame call fails until recreate_renderer().
    Status render_to_image(Image& out);
    // Main thread. Window target: traces the viewer's view and presents it. Two frames are in
    // flight: the call waits only for the GPU frame two back, so the stats' GPU figures are those
    // of that frame. A minimised window presents nothing (ok). `capture`, if given, receives the
    // presented image (RGBA8; the call then waits for this frame): screenshots, tests.
    // Errors: as render_to_image's (out of memory: nothing presented this call; device lost).
    Status render_to_window(Image* capture = nullptr);
    // Main thread. Window target: vsync on (FIFO) or off (MAILBOX, else IMMEDIATE, else FIFO);
    // the swapchain is recreated at the next render_to_window (Stats::vsync tells the mode).
    // Nothing else changes. Errors: not a window target, shut down.
    Status set_vsync(bool vsync);
    // Main thread. A new renderer for the same target, e.g. after the device was lost: every
    // chunk meshed now is uploaded again, and the UI and its texture are set again; the world,
    // the streaming, saves and edits are untouched. Errors: no GPU target, shut down, no usable
    // GPU (then frames fail until a later call succeeds).
    Status recreate_renderer();
    // Main thread. The UI drawn over later frames (see UiDrawList; copied; an empty list removes
    // it). Errors: no GPU target, shut down, an index past the vertices, a command past the
    // indices or not whole triangles (the previous UI stays), the device was lost.
    Status set_ui(const UiDrawList& ui);
    // Main thread. The UI's texture: width x height RGBA8 texels (straight alpha, sRGB encoded:
    // what the screen shows), row 0 at the top; uv (0, 0) is its top-left corner. Set it once
    // (e.g. Dear ImGui's font atlas) or when it changes; until then it is one white texel.
    // Errors: no GPU target, shut down, a size of 0 or over 16384 a side, rgba not w * h * 4
    // bytes, out of GPU memory for it (the previous texture stays), the device was lost.
    Status set_ui_texture(uint32_t width, uint32_t height, std::span<const uint8_t> rgba);

    // Main thread. Figures of the last frame and gauges now (see Stats).
    Stats stats() const;
    // Main thread. Chunk events since the last call, in order (needs chunk_events).
    std::vector<ChunkEvent> poll_events();

    // Main thread; does not block. Hands every edited chunk to the I/O thread and queues a
    // commit behind them; the ticket turns Durable once that commit is synced. Errors (nothing
    // is handed over): the world does not persist (terrain, generator) or is read-only (a VDB
    // opened read_only), shut down. A commit that fails later turns the ticket Failed (its
    // message: wait()); the edits stay queued in the store, and a later save() or background
    // commit retries them.
    Result<SaveTicket> save();
    // Thread-safe. Unknown for a ticket save() never returned.
    SaveState save_state(SaveTicket ticket) const;
    // Thread-safe (not from a Generator). Blocks until the ticket is durable (ok) or failed: the
    // store's message, or "flush cancelled" when the engine shut down before the commit ran; an
    // unknown ticket fails at once, saying so.
    Status wait(SaveTicket ticket) const;

    // Main thread. Saves and syncs every edit (persistent worlds), stops the threads and
    // releases the world and the GPU. Afterwards only stats(), save_state(), wait() and the
    // destructor may be called; other calls fail or do nothing. Idempotent. Errors: the final
    // save failed (the store's message, also logged): edits not durable by then may be lost
    // with the engine (a save() ticket that turned Durable never is); everything is still
    // stopped and released.
    Status shutdown();

private:
    Engine();
    struct Impl;
    std::unique_ptr<Impl> m;
    friend struct EngineTesting; // Fault injection for vx's own tests (engine/engine_testing.h).
};

// Thread-safe. The ray the renderer traces through `pixel` of a frame_size (width, height) frame
// seen by `viewer`: from the viewer's eye, with the vertical field of view over the frame's
// height and the width following the aspect ratio. `pixel` is in framebuffer coordinates: (0, 0)
// the top-left corner of the top-left pixel, y down; pixel (x, y) is traced through its centre
// (x + 0.5, y + 0.5), so the frame's centre is the forward direction. Errors: a viewer set_viewer
// would refuse, a frame size of 0, a non-finite pixel (pixels outside the frame are fine).
Result<ScreenRay> screen_ray(const Viewer& viewer, glm::dvec2 pixel, glm::uvec2 frame_size);
// Writes an image as PNG. Errors: a malformed image, a file that cannot be opened, a failed
// write (a full disk; the cut file is removed). Thread-safe.
Status write_png(const std::string& path, const Image& image);
// The built-in terrain's surface height (world y of the topmost terrain block, before caves) at
// column (x, z) for `seed`: where to put a player. A column outside the world (|x| or |z| past
// 2^36 blocks) has the height of the nearest column at its edge. Thread-safe.
int64_t terrain_height(uint64_t seed, int64_t x, int64_t z);

} // namespace vx
