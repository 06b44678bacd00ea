// vx::Engine: the facade's life cycle, streaming, edits, queries and saving. Rendering and stats
// are in engine_render.cpp; the world description is made real in world_setup.cpp.
#include <cmath>

#include <vx/vx.h>

#include "engine/cpu_time.h"
#include "engine/engine_impl.h"
#include "world/base/log.h"
#include "world/coords.h"
#include "world/lod/lod_cut.h"
#include "world/raycast.h"

namespace vx {

// The public types mirror world's: same values, so conversions are plain casts.
static_assert(int(Face::NegX) == int(world::Face::NegX) && int(Face::PosX) == int(world::Face::PosX));
static_assert(int(Face::NegY) == int(world::Face::NegY) && int(Face::PosY) == int(world::Face::PosY));
static_assert(int(Face::NegZ) == int(world::Face::NegZ) && int(Face::PosZ) == int(world::Face::PosZ));
static_assert(kLodLevels == world::kMaxLodLevel + 1);
static_assert(kChunkSize == world::kChunkSize && kChunkVolume == world::kChunkVolume);
static_assert(chunk_index(1, 2, 3) == world::local_index(1, 2, 3));

namespace {

constexpr double kMaxUpdateBudgetMs = 1000; // A second of main-thread work a frame.

Status validate(const EngineCreateInfo& info) {
    const StreamingDesc& s = info.streaming;
    if (s.view_radius < 0 || s.view_radius_vertical < 0 || s.unload_margin < 0)
        return Error{"streaming radii must be >= 0"};
    if (s.view_radius > 64 || s.view_radius_vertical > 64 || s.unload_margin > 64)
        return Error{"streaming radii and the unload margin above 64 chunks are not supported"};
    if (!(s.unload_delay_s >= 0) || !(s.save_delay_s >= 0)) // NaN fails; infinity: only on save().
        return Error{"streaming delays must be >= 0 seconds (infinity: never)"};
    // The budget becomes integer nanoseconds: infinity or 1e30 would overflow the conversion.
    if (!(s.update_budget_ms > 0 && s.update_budget_ms <= kMaxUpdateBudgetMs))
        return Error{"update_budget_ms must be in (0, " + std::to_string(int(kMaxUpdateBudgetMs)) + "], got " +
                     std::to_string(s.update_budget_ms)};
    if (s.worker_threads < 0 || s.worker_threads > engine::kMaxWorkerThreads)
        return Error{"worker_threads must be 0.." + std::to_string(engine::kMaxWorkerThreads) + " (0: cores - 1), got " +
                     std::to_string(s.worker_threads)};
    if (s.view_distance < 0 || s.view_distance > 65536)
        return Error{"view_distance must be 0..65536 blocks, got " + std::to_string(s.view_distance)};
    if (s.lod_ring < 1 || s.lod_ring > 64)
        return Error{"lod_ring must be 1..64 chunks, got " + std::to_string(s.lod_ring)};
    if (s.lod_vertical_reach < 0 || s.lod_vertical_reach > world::kMaxLodVerticalReach)
        return Error{"lod_vertical_reach must be 0.." + std::to_string(world::kMaxLodVerticalReach) + " blocks"};
    const RenderTarget& t = info.render.target;
    if (t.kind == RenderTarget::Kind::Window && !t.window)
        return Error{"a window target needs a GLFWwindow* (RenderTarget::glfw_window)"};
    if (t.kind == RenderTarget::Kind::Headless && (t.width == 0 || t.height == 0 || t.width > 16384 || t.height > 16384))
        return Error{"a headless target needs a size of 1..16384 pixels per side, got " + std::to_string(t.width) +
                     "x" + std::to_string(t.height)};
    return {};
}

engine::StreamingSettings streaming_settings(const StreamingDesc& d) {
    engine::StreamingSettings s;
    s.view_radius = d.view_radius;
    s.view_radius_vertical = d.view_radius_vertical;
    s.unload_margin = d.unload_margin;
    s.unload_delay_s = d.unload_delay_s;
    s.save_delay_s = d.save_delay_s;
    s.memory_cap_bytes = d.memory_cap_bytes;
    s.frame_budget = std::chrono::nanoseconds(int64_t(d.update_budget_ms * 1e6));
    s.worker_count = d.worker_threads;
    return s;
}

// The levels of detail around the viewer, or nullopt when the view distance stays within the
// full-detail radius. A generator without coarse chunks keeps to levels 1 and 2 (vx.h).
std::optional<world::LodViewSettings> lod_settings(const StreamingDesc& d, const world::ChunkGenerator& gen) {
    world::LodViewSettings s;
    s.radius0 = d.view_radius;
    s.vradius0 = d.view_radius_vertical;
    s.ring = d.lod_ring;
    s.vertical_reach = d.lod_vertical_reach;
    s.view_distance = d.view_distance;
    s.max_level = std::min(world::kMaxLodLevel, std::max(gen.coarse_levels(), 2));
    if (world::LodView(glm::dvec3(0.0), s).top_level() == 0)
        return std::nullopt;
    return s;
}

Result<std::unique_ptr<render::Renderer>> make_renderer(const RenderDesc& desc, const world::BlockRegistry& registry) {
    auto choice = render::parse_device_choice(desc.device);
    if (!choice)
        return Error{choice.error()};
    render::RendererCreateInfo rci;
    rci.device = *choice;
    rci.validation = desc.validation;
    if (desc.target.kind == RenderTarget::Kind::Window) {
        rci.glfw_window = desc.target.window;
        rci.vsync = desc.vsync;
    }
    auto renderer = render::Renderer::create(rci);
    if (!renderer)
        return Error{renderer.error()};
    // A headless target too large for the device fails here, not at its first frame.
    if (desc.target.kind == RenderTarget::Kind::Headless)
        if (Status s = (*renderer)->check_frame_size(desc.target.width, desc.target.height); !s)
            return Error{s.error()};
    (*renderer)->set_registry(registry);
    return std::move(*renderer);
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Whether a position's offset from its block is past 2^40 on some axis: the caller is to put the
// position in the block (the float camera and the raycast's anchor need a small offset).
bool offset_too_far(const glm::dvec3& offset) {
    return glm::any(glm::greaterThan(glm::abs(offset), glm::dvec3(double(int64_t(1) << 40))));
}

// Why the renderer could not make a camera of `v` (render::Renderer builds its basis from
// normalize(cross(forward, up))), or success. Checked where the viewer arrives.
Status check_viewer(const Viewer& v) {
    if (!finite(v.offset) || !finite(v.forward) || !finite(v.up) || (v.velocity && !finite(*v.velocity)) ||
        !std::isfinite(v.fov_y_degrees))
        return Error{"viewer: offset, forward, up, velocity and fov must be finite"};
    if (v.forward == glm::dvec3(0.0))
        return Error{"viewer: forward is zero (it gives the view direction)"};
    if (v.up == glm::dvec3(0.0))
        return Error{"viewer: up is zero (give the world's up, e.g. 0, 1, 0)"};
    if (offset_too_far(v.offset))
        return Error{"viewer: keep the offset small and put the position in `block`"};
    // The same bound the renderer's float basis tolerates (sine of the angle between them), on
    // the unit vectors it gets (any length of forward and up is fine: world::unit_direction).
    if (!(glm::length(glm::cross(world::unit_direction(v.forward), world::unit_direction(v.up))) > 1e-6))
        return Error{"viewer: forward is parallel to up (looking straight up or down needs another up, e.g. 0, 0, -1)"};
    if (!(v.fov_y_degrees > 0.f && v.fov_y_degrees < 180.f))
        return Error{"viewer: fov_y_degrees must be in (0, 180), got " + std::to_string(v.fov_y_degrees)};
    return {};
}

// The viewer's block with the offset's whole blocks folded in (so the float camera stays exact),
// or why it cannot be streamed. The streamer's boxes reach 2 view radii + the unload margin + 2
// chunks (at most 194) past the viewer's chunk, in 32-bit chunk coordinates; a box ending at
// INT32_MAX once looped forever. The margin (2^17 blocks) keeps every box inside. `block` is
// checked before the fold: near 2^63 the sum overflowed. Call after check_viewer.
static_assert(world::kWorldMinBlock + world::kEdgeMarginBlocks == -kStreamedWorldExtent &&
              world::kWorldMaxBlock - world::kEdgeMarginBlocks == kStreamedWorldExtent - 1);
Result<BlockPos> viewer_block(const Viewer& v, const glm::dvec3& whole) {
    if (!world::in_world(v.block) || !world::inside_edge_margin(v.block + BlockPos(whole)))
        return Error{"viewer: position outside the streamed world (|coordinate| < 2^36 - 2^17 blocks)"};
    return v.block + BlockPos(whole);
}

} // namespace

Result<ScreenRay> screen_ray(const Viewer& viewer, glm::dvec2 pixel, glm::uvec2 frame_size) {
    if (Status s = check_viewer(viewer); !s)
        return Error{s.error()};
    if (frame_size.x == 0 || frame_size.y == 0)
        return Error{"screen_ray: the frame size must be at least 1x1"};
    if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y))
        return Error{"screen_ray: the pixel must be finite"};
    // As shaders/shared/raygen_common.glsl primary_dir(): ndc in -1..1 over the frame (y down), the
    // vertical half-angle over the height, the aspect ratio widening x; the same basis as
    // render::Renderer (right = forward x up, up' = right x forward).
    const glm::dvec3 fwd = world::unit_direction(viewer.forward);
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, world::unit_direction(viewer.up)));
    const glm::dvec3 up = glm::cross(right, fwd);
    // Far outside the frame only the pixel's bearing matters: scaled down before anything can
    // overflow (2 * 1e308 is infinite), the direction changes by rounding only (the forward axis
    // is 1e-15 of the rest).
    glm::dvec2 half = pixel / glm::dvec2(frame_size) - 0.5;
    if (const double m = glm::max(std::abs(half.x), std::abs(half.y)); m > 1e15)
        half *= 1e15 / m;
    const glm::dvec2 ndc = half * 2.0;
    const double th = std::tan(glm::radians(double(viewer.fov_y_degrees)) * 0.5);
    const double aspect = double(frame_size.x) / double(frame_size.y);
    ScreenRay ray;
    const glm::dvec3 whole = glm::floor(viewer.offset);
    const Result<BlockPos> block = viewer_block(viewer, whole);
    if (!block)
        return Error{block.error()};
    ray.origin_block = *block;
    ray.origin_offset = viewer.offset - whole;
    ray.direction = world::unit_direction(fwd + ndc.x * th * aspect * right - ndc.y * th * up);
    return ray;
}

Engine::Engine() : m(std::make_unique<Impl>()) {}

Engine::~Engine() {
    if (Status s = shutdown(); !s)
        VX_LOG_ERROR("engine shutdown: %s", s.error().c_str());
}

Result<std::unique_ptr<Engine>> Engine::create(const EngineCreateInfo& info) {
    if (Status s = validate(info); !s)
        return Error{s.error()};
    Result<engine::OpenedWorld> world = engine::open_world(info.world, info.blocks);
    if (!world)
        return Error{world.error()};
    std::unique_ptr<Engine> e(new Engine());
    Impl& m = *e->m;
    m.info = info;
    m.world = std::move(*world);
    if (info.render.target.kind != RenderTarget::Kind::None) {
        auto renderer = make_renderer(info.render, m.world.registry);
        if (!renderer)
            return Error{renderer.error()};
        m.renderer = std::move(*renderer);
    }
    m.sink = std::make_unique<engine::EngineSink>(m.renderer.get(), info.chunk_events);
    engine::MeshSink* meshes = m.sink.get();
    if (auto lod = lod_settings(info.streaming, *m.world.generator)) {
        if (const uint64_t n = world::lod_box_chunks(*lod); n > world::kMaxLodBoxChunks)
            return Error{"levels of detail would keep " + std::to_string(n) + " coarse chunks around the viewer (at most " +
                         std::to_string(world::kMaxLodBoxChunks) + "): lower lod_vertical_reach, lod_ring or view_distance"};
        m.lod = std::make_unique<engine::LodStreamer>(*m.world.generator, m.world.store.get(), *m.sink, *lod,
                                                      m.world.registry);
        meshes = m.lod.get();
    }
    engine::StreamingSettings streaming = streaming_settings(info.streaming);
    if (m.lod) // The level swaps get the last quarter of the update budget.
        streaming.frame_budget = streaming.frame_budget * 3 / 4;
    m.streamer = std::make_unique<engine::ChunkStreamer>(*m.world.generator, m.world.store.get(), *meshes,
                                                         streaming, m.world.registry);
    const engine::JobSystem& jobs = m.streamer->jobs();
    if (!jobs.start_error().empty()) {
        const std::string why = "engine: cannot start its worker threads: " + jobs.start_error();
        m.streamer.reset(); // Nothing loaded or edited, so nothing to flush (and no thread to do it).
        return Error{why};
    }
    if (jobs.refused_workers() > 0)
        VX_LOG_WARN("engine: the OS refused %d of the %d worker threads asked for (%s); running on %d",
                    jobs.refused_workers(), jobs.refused_workers() + jobs.worker_count(),
                    jobs.refused_reason().c_str(), jobs.worker_count());
    m.streamer->set_observer(m.sink.get());
    if (m.lod)
        m.lod->attach(m.streamer->jobs(), m.streamer->world());
    m.saves = m.streamer->save_tracker();
    return e;
}

Status Engine::set_viewer(const Viewer& viewer) {
    const engine::CallGuard call(m->calls, "set_viewer");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (Status s = check_viewer(viewer); !s)
        return s;
    const glm::dvec3 whole = glm::floor(viewer.offset);
    const Result<BlockPos> folded = viewer_block(viewer, whole);
    if (!folded)
        return Error{folded.error()};
    const BlockPos block = *folded;
    m->viewer = viewer;
    m->viewer.block = block;
    m->viewer.offset -= whole;
    m->viewer.forward = world::unit_direction(viewer.forward); // The camera's floats stay finite.
    m->viewer.up = world::unit_direction(viewer.up);
    return {};
}

void Engine::update(std::chrono::steady_clock::time_point now) {
    const engine::CallGuard call(m->calls, "update");
    if (!call)
        return;
    if (m->shut_down)
        return;
    m->follow_thread();
    const glm::dvec3 forward = m->viewer.forward;
    const auto t0 = std::chrono::steady_clock::now();
    const std::chrono::nanoseconds cpu0 = engine::thread_cpu_time();
    if (m->lod) // Edits since the last frame reach the coarse levels before their chunks may go.
        m->lod->apply_edits();
    if (m->viewer.velocity)
        m->streamer->update(m->eye(), forward, *m->viewer.velocity, now);
    else
        m->streamer->update(m->eye(), forward, now);
    if (m->lod) // Up to 85% of the budget (the streamer keeps to 3/4 of it); what follows the deadline
                // (a few swaps and requests, submitting the jobs, counting holes) fits in the rest.
        m->lod->update(m->eye(), now,
                       t0 + std::chrono::nanoseconds(int64_t(m->info.streaming.update_budget_ms * 0.85e6)));
    m->frame.update_cpu_ms = std::chrono::duration<double, std::milli>(engine::thread_cpu_time() - cpu0).count();
    m->frame.update_wall_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool Engine::settled() const {
    const engine::CallGuard call(m->calls, "settled");
    return call && !m->shut_down && m->streamer->settled() && (!m->lod || m->lod->settled());
}

namespace {
// Why `id` at `pos` cannot be set now, or success.
Status check_edit(const engine::ChunkStreamer& streamer, const world::BlockRegistry& registry, BlockPos pos,
                  BlockId id) {
    if (!world::in_world(pos))
        return Error{"block " + std::to_string(pos.x) + "," + std::to_string(pos.y) + "," + std::to_string(pos.z) +
                     " is outside the world"};
    if (id != kAir && !registry.contains(id))
        return Error{"block id " + std::to_string(id) + " is not a registered block"};
    const ChunkCoord c = chunk_of(pos);
    if (!streamer.world().find_chunk(c))
        return Error{"block " + std::to_string(pos.x) + "," + std::to_string(pos.y) + "," + std::to_string(pos.z) +
                     ": chunk " + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) +
                     " is not loaded"};
    return {};
}
} // namespace

Status Engine::set_block(BlockPos pos, BlockId id) {
    const BlockEdit edit{pos, id};
    return set_blocks(std::span<const BlockEdit>(&edit, 1));
}

Status Engine::set_blocks(std::span<const BlockEdit> edits) {
    const engine::CallGuard call(m->calls, "set_blocks");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    for (const BlockEdit& e : edits)
        if (Status s = check_edit(*m->streamer, m->world.registry, e.pos, e.id); !s)
            return s;
    for (const BlockEdit& e : edits) {
        if (Status s = m->streamer->set_block(e.pos, e.id); !s)
            return s; // Unreachable after the checks; kept so a future check cannot be silently lost.
        if (m->lod)
            m->lod->note_edit(world::chunk_of(e.pos));
        else
            m->mark_coarse_stale(world::chunk_of(e.pos));
    }
    return {};
}

// Without levels of detail the edit reaches no coarse level here, yet the store may keep them (`vx
// world gen --lod-levels`, a session with them on): its ancestors are marked stale, once per chunk
// and session, so a later view derives them from the blocks. Unmarked, they read as current (or,
// absent, as plain terrain), and the far view hid the edit.
void Engine::Impl::mark_coarse_stale(ChunkCoord c) {
    world::ChunkStore* store = world.store.get();
    if (!store || !store->supports_lod() || store->read_only() || !coarse_marked.insert(c).second)
        return;
    streamer->jobs().submit(std::make_unique<engine::LodMarkDirtyJob>(c, *store, world::lod_ancestors(c, 1)));
}

std::optional<BlockId> Engine::get_block(BlockPos pos) const {
    const engine::CallGuard call(m->calls, "get_block");
    if (!call)
        return std::nullopt;
    if (m->shut_down || !world::in_world(pos))
        return std::nullopt;
    const world::Chunk* chunk = m->streamer->world().find_chunk(chunk_of(pos));
    if (!chunk)
        return std::nullopt;
    return chunk->get(world::local_of(pos));
}

Result<RayHit> Engine::raycast(BlockPos origin_block, glm::dvec3 origin_offset, glm::dvec3 direction,
                               double max_distance) const {
    const engine::CallGuard call(m->calls, "raycast");
    if (!call)
        return Error{call.error().error()};
    if (Status s = m->alive(); !s)
        return Error{s.error()};
    if (!finite(direction) || direction == glm::dvec3(0.0) || !finite(origin_offset))
        return Error{"raycast: the direction must be finite and non-zero, the origin finite"};
    if (offset_too_far(origin_offset) || !world::in_world(origin_block))
        return Error{"raycast: the origin block must lie inside the world (|coordinate| < 2^36) and the offset "
                     "be small (|offset| <= 2^40)"};
    if (!std::isfinite(max_distance) || max_distance < 0)
        return Error{"raycast: max_distance must be finite and >= 0"};
    const world::World& w = m->streamer->world();
    auto chunk_at = [&w](world::BlockPos p) { return world::in_world(p) ? w.find_chunk(world::chunk_of(p)) : nullptr; };
    // Unloaded space reads as a solid block, so the walk stops where knowledge ends.
    auto query = [&chunk_at](world::BlockPos p) -> world::BlockId {
        const world::Chunk* c = chunk_at(p);
        return c ? c->get(world::local_of(p)) : world::BlockId(1);
    };
    const world::RaycastHit h = world::raycast(world::Ray{origin_block, origin_offset, direction}, max_distance, query);
    RayHit out;
    if (!h.hit)
        return out;
    out.kind = chunk_at(h.block) ? RayHit::Kind::Hit : RayHit::Kind::Unloaded;
    out.inside = h.inside;
    out.block = h.block;
    out.distance = h.distance;
    if (out.kind == RayHit::Kind::Hit) {
        out.id = h.id;
        out.face = Face(h.face);
        out.previous = h.previous;
    }
    return out;
}

std::optional<BlockId> Engine::find_block(std::string_view name) const { return m->world.registry.find(name); }

std::optional<BlockType> Engine::block_type(BlockId id) const {
    if (id == kAir || !m->world.registry.contains(id))
        return std::nullopt;
    const world::BlockInfo b = m->world.registry.info(id);
    return BlockType{b.name, b.albedo, b.reflectivity, b.emission, b.opaque};
}

size_t Engine::block_count() const { return m->world.registry.size() - 1; }

std::vector<ChunkEvent> Engine::poll_events() {
    const engine::CallGuard call(m->calls, "poll_events");
    if (!call || !m->sink)
        return {};
    return m->sink->take_events();
}

Result<SaveTicket> Engine::save() {
    const engine::CallGuard call(m->calls, "save");
    if (!call)
        return Error{call.error().error()};
    if (Status s = m->alive(); !s)
        return Error{s.error()};
    if (!m->world.store)
        return Error{"this world does not persist (built-in terrain or a generator): open a SQLite world to save"};
    if (m->world.store->read_only())
        return Error{"this world is read-only (a VDB world opened read_only): edits stay in memory"};
    if (m->lod) // The coarse levels' saves and stale marks of edits made since the last frame.
        m->lod->flush_edits();
    return SaveTicket{m->streamer->request_save()};
}

SaveState Engine::save_state(SaveTicket ticket) const {
    switch (m->saves->state(ticket.sequence)) {
    case engine::SaveState::Pending:
        return SaveState::Pending;
    case engine::SaveState::Durable:
        return SaveState::Durable;
    case engine::SaveState::Failed:
        break;
    case engine::SaveState::Unknown:
        return SaveState::Unknown;
    }
    return SaveState::Failed;
}

Status Engine::recreate_renderer() {
    const engine::CallGuard call(m->calls, "recreate_renderer");
    if (!call)
        return call.error();
    if (Status s = m->alive(); !s)
        return s;
    if (m->info.render.target.kind == RenderTarget::Kind::None)
        return Error{"recreate_renderer needs a render target (headless or window)"};
    // The old renderer goes first: one Vulkan context per process at a time.
    m->sink->detach_renderer();
    if (m->renderer)
        m->validation_errors_before += m->renderer->validation_errors();
    m->frame.validation_errors = m->validation_errors_before;
    m->renderer.reset();
    m->loss_counted = false;
    auto renderer = make_renderer(m->info.render, m->world.registry);
    if (!renderer)
        return Error{"recreate_renderer: " + renderer.error()};
    m->renderer = std::move(*renderer);
    m->sink->attach_renderer(m->renderer.get());
    if (m->lod)
        m->lod->for_each_drawn([&](world::LodCoord c, const world::ChunkMesh& mesh) { m->renderer->set_chunk(c, mesh); });
    else
        m->streamer->for_each_mesh(
            [&](world::ChunkCoord c, const world::ChunkMesh& mesh) { m->renderer->set_chunk(c, mesh); });
    if (Status s = m->resend_ui(); !s)
        return Error{"recreate_renderer: " + s.error()};
    return {};
}

Status Engine::wait(SaveTicket ticket) const { return m->saves->wait(ticket.sequence); }

Status Engine::shutdown() {
    const engine::CallGuard call(m->calls, "shutdown");
    if (!call)
        return call.error();
    return m->shutdown();
}

Status Engine::Impl::shutdown() {
    if (shut_down)
        return {};
    follow_thread(); // Destroyed by a game object on another thread, say.
    shut_down = true;
    Status result;
    if (streamer && world.store && !world.store->read_only()) {
        if (lod) // Edits since the last frame reach the coarse levels' records too.
            lod->flush_edits();
        result = streamer->flush(); // Every edit saved and synced before the threads stop.
    }
    streamer.reset();               // Joins the workers and the I/O thread.
    lod.reset();                    // Its jobs ran on those.
    if (sink)
        sink->detach_renderer();
    if (renderer) // Kept for stats() after shutdown.
        frame.validation_errors = validation_errors_before + renderer->validation_errors();
    renderer.reset();
    world.store.reset();            // Closes the database.
    return result;
}

} // namespace vx
