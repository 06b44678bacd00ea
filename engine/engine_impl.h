#pragma once
// The state behind vx::Engine (the pimpl), shared by engine.cpp (life cycle, streaming, edits,
// queries, saving) and engine_render.cpp (frames and stats). Main thread only, except `saves`
// (thread-safe).

#include <memory>
#include <optional>
#include <thread>
#include <unordered_set>

#include <vx/vx.h>

#include "engine/call_guard.h"
#include "engine/chunk_streamer.h"
#include "engine/engine_sink.h"
#include "engine/lod_jobs.h"
#include "engine/lod_streamer.h"
#include "engine/save_tracker.h"
#include "engine/sky_access.h"
#include "engine/world_setup.h"
#include "render/renderer.h"

namespace vx {

struct Engine::Impl {
    EngineCreateInfo info;
    engine::OpenedWorld world;                      // Registry, generator, store.
    std::unique_ptr<render::Renderer> renderer;     // Null without a GPU target.
    std::unique_ptr<engine::EngineSink> sink;
    std::shared_ptr<const engine::SaveTracker> saves; // Outlives the streamer (tickets after shutdown).
    Viewer viewer;
    RenderSettings render_settings;
    Stats frame;                                     // Timings of the last update and frame.
    glm::uvec2 window_frame_size{0};                 // Of the last presented frame (0: none yet).
    engine::SkyAccessCache sky;                      // render settings' sky_access (engine_render.cpp).
    bool shut_down = false;
    // Which thread is inside a call now (call_guard.h): a call from another meanwhile is refused.
    mutable engine::CallOwner calls;
    // The thread using the engine now: its creator, or the one a game moved it to (follow_thread).
    std::thread::id thread = std::this_thread::get_id();
    // Device loss (engine_render.cpp): the renderer's validation errors before recreations, and
    // whether the current renderer's loss was counted in frame.device_losses.
    uint32_t validation_errors_before = 0;
    bool loss_counted = false;
    // The game's UI and texture, sent again to a recreated renderer.
    UiDrawList ui;
    std::vector<uint8_t> ui_texture;
    uint32_t ui_texture_width = 0, ui_texture_height = 0;
    // Levels of detail (null without): the streamer's mesh sink. Declared before the streamer,
    // so it outlives the job system its jobs run on.
    std::unique_ptr<engine::LodStreamer> lod;
    // Declared last: destroyed first, while everything it points to still exists.
    std::unique_ptr<engine::ChunkStreamer> streamer;

    // The viewer's eye as a double position (exact below 2^52 blocks, far beyond the world).
    glm::dvec3 eye() const { return glm::dvec3(viewer.block) + viewer.offset; }
    // Fails with a message when the engine was shut down.
    Status alive() const {
        if (shut_down)
            return Error{"the engine has been shut down"};
        return {};
    }
    Status shutdown();
    // Edits without levels of detail: the coarse levels a store may keep are marked stale
    // (engine.cpp); the chunks marked this session.
    void mark_coarse_stale(world::ChunkCoord c);
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> coarse_marked;
    // A call on another thread than the last: the game moved the engine (vx.h, Threads); the job
    // system's completions follow it.
    void follow_thread() {
        if (std::this_thread::get_id() == thread)
            return;
        thread = std::this_thread::get_id();
        if (streamer)
            streamer->jobs().adopt_main_thread();
    }
    // The renderer's settings for this frame (engine_render.cpp): the game's, with sky_access
    // from the world around the viewer (kept while neither the eye's block nor the world moves).
    render::RenderSettings frame_settings(uint32_t width, uint32_t height);
    // Fails when there is no renderer or its device was lost (engine_render.cpp).
    Status renderer_usable();
    // A frame call's error: `why`, or the device-loss line (counted once per renderer).
    Status frame_failed(const std::string& why);
    // The game's UI and texture to a new renderer (engine_render.cpp).
    Status resend_ui();
};

} // namespace vx
