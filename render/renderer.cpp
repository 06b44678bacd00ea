// The Renderer's creation (context, pipelines, descriptor sets, timestamp queries) and its public
// API: chunks and registry, render() and present(), device checks. A frame's parts are
// renderer_frame.cpp (resources, parameters) and renderer_record.cpp (commands).
#include "render/renderer.h"

#include <algorithm>
#include <bit>
#include <utility>
#include <vector>

#include "render/emitter_quads.h"
#include "render/renderer_impl.h"
#include "render/touching_faces.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

Renderer::Renderer() : m(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RendererCreateInfo& info) {
    ContextCreateInfo ci;
    ci.validation = info.validation;
    ci.sync_validation = info.sync_validation;
    ci.device = info.device;
    ci.window = info.glfw_window;
    ci.fail_allocations = info.fail_allocations;
    ci.pipeline_statistics = info.pipeline_statistics;
    Result<std::unique_ptr<Context>> ctx = Context::create(ci);
    if (!ctx)
        return Error{ctx.error()};
    std::unique_ptr<Renderer> r(new Renderer());
    r->m->ctx = std::move(*ctx);
    r->m->ctx->allocator().set_budget(info.gpu_memory_budget_bytes);
    r->m->accel = std::make_unique<SceneAccel>(*r->m->ctx, SceneAccelCreateInfo{info.allow_refit, info.hot_frames, info.max_refits});
    r->m->pipeline = std::make_unique<RtPipeline>(*r->m->ctx);
    // Out of memory here is the device's state, not our bug: an error, as for a frame (it was
    // an assertion; a renderer recreated after a device loss meets a full device).
    if (!r->m->pipeline->valid())
        return r->m->create_error("the ray tracing pipeline");
    if (!r->m->create_descriptors())
        return r->m->create_error("the frame parameters");
    if (!r->m->create_queries())
        return r->m->create_error("the frame timestamps");
    r->set_registry(world::BlockRegistry::default_registry());
    if (info.glfw_window) {
        r->m->presenter = std::make_unique<Presenter>(*r->m->ctx, info.vsync);
        if (!r->m->presenter->valid())
            return Error{"cannot create the renderer: cannot present to the window (" +
                         r->m->ctx->last_create_failure() + ")"};
        r->m->target_format = r->m->presenter->target_format();
    }
    return r;
}

bool Renderer::Impl::create_descriptors() {
    const VkDescriptorPoolSize sizes[] = {
        {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, kFramesInFlight},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 8 * kFramesInFlight}, // Output + 7 G-buffer images.
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFramesInFlight},
    };
    VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    ci.maxSets = kFramesInFlight;
    ci.poolSizeCount = uint32_t(std::size(sizes));
    ci.pPoolSizes = sizes;
    if (ctx->create_call("vkCreateDescriptorPool (rt descriptor pool)",
                         [&] { return vkCreateDescriptorPool(ctx->device(), &ci, nullptr, &pool); }) != VK_SUCCESS)
        return false;
    ctx->set_name(pool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "rt descriptor pool");
    std::array<VkDescriptorSetLayout, kFramesInFlight> layouts;
    layouts.fill(pipeline->set_layout());
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = kFramesInFlight;
    ai.pSetLayouts = layouts.data();
    if (ctx->create_call("vkAllocateDescriptorSets (rt descriptor set)",
                         [&] { return vkAllocateDescriptorSets(ctx->device(), &ai, sets.data()); }) != VK_SUCCESS)
        return false; // The pool frees whatever was allocated.
    for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        ctx->set_name(sets[i], VK_OBJECT_TYPE_DESCRIPTOR_SET, "rt descriptor set");
        params[i] = Buffer::create(*ctx, {sizeof(gpu::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                          MemoryUse::Upload, 0, "frame params"});
        if (!params[i].valid())
            return false;
    }
    return true;
}

bool Renderer::Impl::create_queries() {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, families.data());
    if (families[ctx->queue_family()].timestampValidBits == 0 || ctx->limits().timestampPeriod <= 0.f)
        return true; // No timestamps on this queue: stats without GPU times.
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = kStamps * kFramesInFlight;
    if (ctx->create_call("vkCreateQueryPool (frame timestamps)",
                         [&] { return vkCreateQueryPool(ctx->device(), &ci, nullptr, &queries); }) != VK_SUCCESS)
        return false;
    ctx->set_name(queries, VK_OBJECT_TYPE_QUERY_POOL, "frame timestamps");
    ms_per_tick = double(ctx->limits().timestampPeriod) * 1e-6; // timestampPeriod: ns per tick.
    return true;
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer) {
    Result<RenderImage> img = try_render(settings, camera, gbuffer);
    VX_ASSERT_MSG(img, img ? "" : img.error().c_str());
    return std::move(*img);
}

Result<RenderImage> Renderer::try_render(const RenderSettings& settings, const Camera& camera, GBufferImage* gbuffer) {
    VX_ASSERT(settings.width > 0 && settings.height > 0);
    // Auto exposure without an adapted value yet: a frame to meter, then the frame itself.
    if (Impl::metered(settings) && !m->adapted_ev100)
        if (Result<RenderImage> first = m->render_frame(settings, camera, nullptr); !first)
            return first;
    return m->render_frame(settings, camera, gbuffer);
}

void Renderer::set_ui(UiDrawList list) {
    VX_ASSERT_MSG(ui_draw_list_error(list).empty(), "set_ui: a malformed UI draw list");
    if (list.cmds.empty() && !m->ui)
        return;
    m->ui_pass().set(std::move(list));
}

Status Renderer::set_ui_texture(uint32_t width, uint32_t height, std::vector<uint8_t> rgba) {
    if (m->ctx->lost())
        return Impl::lost_error();
    if (!m->ui_pass().set_texture(width, height, std::move(rgba)))
        return Error{"out of GPU memory for a " + std::to_string(width) + "x" + std::to_string(height) +
                     " UI texture: the previous texture stays"};
    return {};
}

Result<PresentResult> Renderer::present(const RenderSettings& settings, const Camera& camera, RenderImage* capture) {
    using Clock = std::chrono::steady_clock;
    using Ms = std::chrono::duration<double, std::milli>;
    Impl& d = *m;
    if (!d.presenter)
        return Error{"present() needs a renderer created with a window (RendererCreateInfo::glfw_window)"};
    if (d.ctx->lost())
        return Error{Impl::lost_error().error()};
    const auto t0 = Clock::now();
    const std::optional<VkExtent2D> extent = d.presenter->prepare();
    if (d.ctx->lost()) // Recreating the swapchain waits for the device.
        return Error{Impl::lost_error().error()};
    if (!extent)
        return PresentResult::Skipped;
    // After prepare(): the first call creates the swapchain, whose usage decides this.
    if (capture && !d.presenter->can_capture())
        return Error{"present(): this surface's images cannot be read back (no TRANSFER_SRC usage)"};
    VkCommandBuffer cmd = d.ctx->begin_frame(); // Waits for the frame kFramesInFlight back.
    if (!cmd)
        return Error{Impl::lost_error().error()};
    RenderStats st;
    d.read_stamps(st);
    d.read_check(st);
    d.read_meter(settings.exposure.adapt_speed);
    const auto t_record = Clock::now();
    RenderSettings s = settings;
    s.width = extent->width;
    s.height = extent->height;
    // Everything that can run out of memory comes before the acquire: a failed frame then ends
    // without holding a swapchain image or a signalled semaphore.
    Status ok = d.prepare_frame(s, false, false);
    if (ok && capture && !d.presenter->prepare_capture())
        ok = Error{"out of GPU memory for the present capture: nothing drawn"};
    if (ok)
        ok = d.record_scene(cmd, camera);
    if (!ok)
        return Error{d.abandon_frame(std::move(ok)).error()};
    const auto t_acquire = Clock::now();
    if (!d.presenter->acquire()) {
        // Out of date (recreated next call) or lost: the scene's builds are submitted still.
        Status why = d.abandon_frame({});
        if (!why || d.ctx->lost())
            return Error{Impl::lost_error().error()};
        return PresentResult::Skipped;
    }
    const auto t1 = Clock::now();
    d.record_shading(cmd, s, camera);
    d.record_ui(cmd, s.width, s.height);
    d.presenter->record_blit(cmd, d.target().handle(), capture != nullptr);
    d.stamp(cmd, 4);
    if (!d.ctx->end_frame(d.presenter->submit_sync()))
        return Error{Impl::lost_error().error()};
    const auto t2 = Clock::now();
    if (!d.presenter->present())
        return Error{Impl::lost_error().error()};
    const auto t3 = Clock::now();

    d.fill_accel_stats(st);
    st.cpu_ms = Ms(t2 - t1).count() + Ms(t_acquire - t_record).count();
    st.gpu_ms = -1;
    st.wait_ms = Ms(t_record - t0).count() + Ms(t1 - t_acquire).count();
    st.present_ms = Ms(t3 - t2).count();
    st.present_width = s.width;
    st.present_height = s.height;
    st.ev100 = d.frame_ev100;
    if (d.last_present != Clock::time_point{})
        st.frame_ms = Ms(t0 - d.last_present).count();
    d.last_present = t0;
    d.stats = st;
    if (capture) {
        if (!d.ctx->wait_frame())
            return Error{Impl::lost_error().error()};
        *capture = d.presenter->read_capture();
    }
    return PresentResult::Presented;
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera, const Scene& scene) {
    set_registry(scene.registry ? *scene.registry : world::BlockRegistry::default_registry());
    std::unordered_set<world::LodCoord, world::LodCoordHash> keep;
    auto add = [&](world::LodCoord c, const world::ChunkMesh* mesh) {
        VX_ASSERT(mesh != nullptr);
        keep.insert(c);
        set_chunk(c, *mesh);
    };
    for (const auto& [c, mesh] : scene.chunks)
        add(world::LodCoord{0, c}, mesh);
    for (const auto& [c, mesh] : scene.lod_chunks)
        add(c, mesh);
    m->accel->retain_only(keep);
    std::erase_if(m->chunk_blocks, [&](const auto& kv) { return !keep.contains(kv.first); });
    std::erase_if(m->emissive_quads, [&](const auto& kv) { return !keep.contains(kv.first); });
    if (std::erase_if(m->emitter_set, [&](world::LodCoord c) { return !keep.contains(c); }) > 0)
        m->emitter_list_dirty = true;
    for (world::LodCoord c : m->touching.chunks())
        if (!keep.contains(c))
            m->touching.remove(c);
    std::erase_if(m->see_through_set, [&](world::LodCoord c) { return !keep.contains(c); });
    return render(settings, camera);
}

std::vector<world::LodCoord> Renderer::set_registry(const world::BlockRegistry& registry) {
    std::vector<world::LodCoord> stale_chunks;
    const auto changed = [&](world::BlockId id) { return m->registry.is_opaque(id) != registry.is_opaque(id); };
    // Ids past both tables are opaque in both; no chunk scan unless some id changed (render(scene)
    // calls this every frame).
    bool any_changed = false;
    for (size_t id = 0; id < std::max(registry.size(), m->registry.size()) && !any_changed; ++id)
        any_changed = changed(world::BlockId(id));
    if (any_changed)
        for (const auto& [c, ids] : m->chunk_blocks)
            if (std::any_of(ids.begin(), ids.end(), changed))
                stale_chunks.push_back(c);
    std::sort(stale_chunks.begin(), stale_chunks.end(), world::lod_coord_less);
    m->registry = registry;
    if (any_changed) { // The shaders ask the materials: what is see-through now is.
        m->see_through_set.clear();
        for (const auto& [c, ids] : m->chunk_blocks)
            if (!chunk_traits(ids, m->registry).opaque)
                m->see_through_set.insert(c);
    }
    m->materials_dirty = true;
    m->emitters_dirty = true;
    std::vector<bool> emissive(registry.size(), false);
    for (size_t id = 0; id < registry.size(); ++id) {
        const glm::vec3 e = registry.info(world::BlockId(id)).emission;
        emissive[id] = e.r > 0.f || e.g > 0.f || e.b > 0.f;
    }
    // The chunks' emissive faces (render/emitter_quads.h) are stale where an id's flag changed;
    // ids appended that do not emit change nothing (an unregistered id did not emit either).
    bool stale = false;
    for (size_t id = 0; id < std::max(emissive.size(), m->emissive.size()); ++id) {
        const bool was = id < m->emissive.size() && m->emissive[id], is = id < emissive.size() && emissive[id];
        stale = stale || was != is;
    }
    if (stale)
        m->emissive_quads.clear();
    m->emissive = std::move(emissive);
    return stale_chunks;
}

void Renderer::set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) {
    set_chunk(world::LodCoord{0, c}, mesh, changed_slices);
}

void Renderer::remove_chunk(world::ChunkCoord c) { remove_chunk(world::LodCoord{0, c}); }

void Renderer::note_edit(world::BlockPos lo, world::BlockPos hi) { m->edit_marks.add(glm::min(lo, hi), glm::max(lo, hi)); }

size_t Renderer::noted_edits() const { return m->edit_marks.boxes().size(); }

void Renderer::set_chunk(world::LodCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) {
    VX_ASSERT_MSG(world::valid_lod_level(c.level), "set_chunk: LOD level outside 0..world::kMaxLodLevel");
    std::vector<world::BlockId>& ids = m->chunk_blocks[c];
    ids = mesh.block_ids();
    for (world::BlockId id : ids)
        m->max_block_id = std::max<uint32_t>(m->max_block_id, id);
    const bool emits = m->emits(ids);
    if (emits ? m->emitter_set.insert(c).second : m->emitter_set.erase(c) > 0)
        m->emitter_list_dirty = true;
    if (emits) {
        std::vector<world::Quad>& faces = m->emissive_quads[c];
        faces.clear();
        collect_emissive_quads(mesh, m->emissive, faces);
    } else {
        m->emissive_quads.erase(c);
    }
    // Faces that may touch another transparent block's carry a mark (a copy of the mesh, only
    // in chunks that have such faces).
    world::ChunkMesh marked;
    const ChunkTraits traits = chunk_traits(ids, m->registry);
    if (traits.opaque)
        m->see_through_set.erase(c);
    else
        m->see_through_set.insert(c);
    TouchingFaces touching = mark_touching_faces(mesh, ids, m->registry, marked);
    m->touching.set(c, touching.inside, std::move(touching.border));
    m->accel->set_chunk(c, touching.marked ? marked : mesh, changed_slices, traits);
}

void Renderer::remove_chunk(world::LodCoord c) {
    m->accel->remove_chunk(c);
    m->chunk_blocks.erase(c);
    m->emissive_quads.erase(c);
    if (m->emitter_set.erase(c) > 0)
        m->emitter_list_dirty = true;
    m->touching.remove(c);
    m->see_through_set.erase(c);
}
void Renderer::clear_chunks() {
    m->accel->clear();
    m->chunk_blocks.clear();
    m->emissive_quads.clear();
    m->emitter_set.clear();
    m->emitter_list_dirty = true;
    m->touching.clear();
    m->see_through_set.clear();
}
bool Renderer::device_lost() const { return m->ctx->lost(); }

Result<PipelineReport> Renderer::pipeline_report() {
    if (m->ctx->lost())
        return Error{"the device was lost"};
    PipelineReport report{m->ctx->report().name, {}, m->ctx->pipeline_statistics_note()};
    for (SeeThrough level : {SeeThrough::kNone, SeeThrough::kPlain, SeeThrough::kProbe})
        for (bool faces : {false, true}) {
            PipelineVariantReport v = m->pipeline->report(faces, level);
            if (v.name.empty())
                return Error{"out of memory for ray tracing pipeline variant " +
                             std::to_string(report.variants.size() + 1) + " of 6 (the log names it)"};
            report.variants.push_back(std::move(v));
        }
    note_missing_executables(report);
    return report;
}
void Renderer::simulate_device_loss() { m->ctx->simulate_device_loss(); }
void Renderer::fail_allocations(std::string name_prefix, uint64_t above_bytes) {
    m->ctx->fail_allocations(std::move(name_prefix), above_bytes);
}

void Renderer::limit_light_cache_cells(uint32_t cells) {
    VX_ASSERT(cells == 0 || (cells >= 4 && std::has_single_bit(cells)));
    m->light_cache_cell_limit = cells;
}

void Renderer::set_vsync(bool vsync) {
    if (m->presenter)
        m->presenter->set_vsync(vsync);
}

bool Renderer::vsync() const {
    return m->presenter && m->presenter->swapchain().present_mode() == VK_PRESENT_MODE_FIFO_KHR;
}

uint64_t frame_bytes_per_pixel() {
    // Per frame slot: the 8-bit target and the G-buffer (radiance, albedo, normal_depth,
    // reflected, mirror light, albedo and normal_depth: render/gbuffer.h); the 8-bit read-back;
    // the denoiser's sixteen RGBA16F images and its 8-bit output (render/denoiser.h).
    constexpr uint64_t kSlot = 4 + 8 + 4 + 8 + 8 + 8 + 4 + 8;
    constexpr uint64_t kDenoiser = 16 * 8 + 4;
    return kFramesInFlight * kSlot + 4 + kDenoiser;
}

Status Renderer::check_frame_size(uint32_t width, uint32_t height) const {
    const uint64_t pixels = uint64_t(width) * height;
    const uint64_t need = pixels * frame_bytes_per_pixel();
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(m->ctx->physical_device(), &mem);
    uint64_t heap = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            heap = std::max<uint64_t>(heap, mem.memoryHeaps[i].size);
    VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p11};
    vkGetPhysicalDeviceProperties2(m->ctx->physical_device(), &p2);
    const uint64_t largest_image = pixels * 8; // RGBA16F.
    auto gib = [](uint64_t b) { return std::to_string(double(b) / double(1ull << 30)).substr(0, 5) + " GiB"; };
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (need > heap)
        return Error{"a " + size + " target needs about " + gib(need) + " of GPU memory for its frame resources (" +
                     std::to_string(frame_bytes_per_pixel()) + " bytes per pixel), more than the device's " + gib(heap) +
                     ": choose a smaller size"};
    if (p11.maxMemoryAllocationSize && largest_image > p11.maxMemoryAllocationSize)
        return Error{"a " + size + " target needs " + gib(largest_image) + " images, more than the device allows in one "
                     "allocation (" + gib(p11.maxMemoryAllocationSize) + "): choose a smaller size"};
    return {};
}

const DeviceReport& Renderer::device() const { return m->ctx->report(); }
uint32_t Renderer::validation_errors() const { return m->ctx->validation_errors(); }
const RenderStats& Renderer::last_stats() const { return m->stats; }
GpuHeapStats Renderer::memory_stats() const {
    const AllocatorStats a = m->ctx->allocator().stats();
    return {uint64_t(a.block_bytes), uint64_t(a.used_bytes)};
}
Context& Renderer::context() { return *m->ctx; }

Camera Camera::look_at(glm::dvec3 eye, glm::dvec3 target, glm::vec3 up, float fov_y_degrees) {
    Camera c;
    const glm::dvec3 cell = glm::floor(eye);
    c.block = world::BlockPos(cell);
    c.offset = glm::vec3(eye - cell);
    c.forward = glm::vec3(target - eye);
    c.up = up;
    c.fov_y_degrees = fov_y_degrees;
    return c;
}

} // namespace vx::render
