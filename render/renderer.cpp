#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <unordered_set>

#include "render/commands.h"
#include "render/context.h"
#include "render/gpu_layouts.h"
#include "render/rt_pipeline.h"
#include "render/scene_accel.h"

namespace vx::render {

struct Renderer::Impl {
    std::unique_ptr<Context> ctx;
    std::unique_ptr<SceneAccel> accel;
    std::unique_ptr<RtPipeline> pipeline;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::array<VkDescriptorSet, kFramesInFlight> sets{};
    std::array<Buffer, kFramesInFlight> params;
    world::BlockRegistry registry;
    Buffer materials;
    uint32_t material_count = 0;
    bool materials_dirty = true;
    uint32_t max_block_id = 0;
    Image target;
    Buffer readback;
    RenderStats stats;
    // Timestamps (kStamps per frame slot): frame start, after BLAS builds, after the TLAS, after
    // the trace, after the copy. Null when the queue family has no timestamps.
    static constexpr uint32_t kStamps = 5;
    VkQueryPool queries = VK_NULL_HANDLE;
    double ms_per_tick = 0;

    ~Impl() {
        if (!ctx)
            return;
        ctx->wait_idle();
        vkDestroyDescriptorPool(ctx->device(), pool, nullptr);
        if (queries)
            vkDestroyQueryPool(ctx->device(), queries, nullptr);
    }
    void create_descriptors();
    void create_queries();
    void stamp(VkCommandBuffer cmd, uint32_t i) {
        if (queries)
            vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries, ctx->frame_slot() * kStamps + i);
    }
    void read_stamps();
    void update_materials();
    void ensure_target(uint32_t width, uint32_t height);
    void write_params(const RenderSettings& s, const Camera& cam);
    void write_descriptors();
    void record_trace(VkCommandBuffer cmd, uint32_t width, uint32_t height);
};

Renderer::Renderer() : m(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const RendererCreateInfo& info) {
    ContextCreateInfo ci;
    ci.validation = info.validation;
    ci.device = info.device;
    Result<std::unique_ptr<Context>> ctx = Context::create(ci);
    if (!ctx)
        return Error{ctx.error()};
    std::unique_ptr<Renderer> r(new Renderer());
    r->m->ctx = std::move(*ctx);
    r->m->accel = std::make_unique<SceneAccel>(*r->m->ctx, info.allow_refit);
    r->m->pipeline = std::make_unique<RtPipeline>(*r->m->ctx);
    r->m->create_descriptors();
    r->m->create_queries();
    r->m->registry = world::BlockRegistry::default_registry();
    return r;
}

void Renderer::Impl::create_descriptors() {
    const VkDescriptorPoolSize sizes[] = {
        {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, kFramesInFlight},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kFramesInFlight},
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFramesInFlight},
    };
    VkDescriptorPoolCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    ci.maxSets = kFramesInFlight;
    ci.poolSizeCount = uint32_t(std::size(sizes));
    ci.pPoolSizes = sizes;
    VK_CHECK(vkCreateDescriptorPool(ctx->device(), &ci, nullptr, &pool));
    ctx->set_name(pool, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "rt descriptor pool");
    std::array<VkDescriptorSetLayout, kFramesInFlight> layouts;
    layouts.fill(pipeline->set_layout());
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = kFramesInFlight;
    ai.pSetLayouts = layouts.data();
    VK_CHECK(vkAllocateDescriptorSets(ctx->device(), &ai, sets.data()));
    for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        ctx->set_name(sets[i], VK_OBJECT_TYPE_DESCRIPTOR_SET, "rt descriptor set");
        params[i] = Buffer::create(*ctx, {sizeof(gpu::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                          MemoryUse::Upload, 0, "frame params"});
        VX_ASSERT(params[i].valid());
    }
}

void Renderer::Impl::create_queries() {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device(), &count, families.data());
    if (families[ctx->queue_family()].timestampValidBits == 0 || ctx->limits().timestampPeriod <= 0.f)
        return;
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = kStamps * kFramesInFlight;
    VK_CHECK(vkCreateQueryPool(ctx->device(), &ci, nullptr, &queries));
    ctx->set_name(queries, VK_OBJECT_TYPE_QUERY_POOL, "frame timestamps");
    ms_per_tick = double(ctx->limits().timestampPeriod) * 1e-6; // timestampPeriod: ns per tick.
}

void Renderer::Impl::read_stamps() {
    if (!queries)
        return;
    uint64_t t[kStamps];
    VK_CHECK(vkGetQueryPoolResults(ctx->device(), queries, ctx->frame_slot() * kStamps, kStamps, sizeof t, t,
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    auto ms = [&](int i) { return double(t[i + 1] - t[i]) * ms_per_tick; };
    stats.gpu_blas_ms = ms(0);
    stats.gpu_tlas_ms = ms(1);
    stats.gpu_trace_ms = ms(2);
    stats.gpu_copy_ms = ms(3);
}

void Renderer::Impl::update_materials() {
    const uint32_t count = std::max<uint32_t>(uint32_t(registry.size()), max_block_id + 1);
    if (!materials_dirty && count <= material_count)
        return;
    std::vector<gpu::Material> table(count);
    for (uint32_t id = 0; id < count; ++id) {
        const world::BlockInfo b = registry.info(world::BlockId(id));
        table[id].albedo_reflectivity = glm::vec4(b.albedo, b.reflectivity);
        table[id].emission = glm::vec4(b.emission, 0.f);
    }
    materials = upload_buffer(*ctx, table.data(), table.size() * sizeof(gpu::Material),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "materials");
    VX_ASSERT_MSG(materials.valid(), "out of GPU memory for materials");
    material_count = count;
    materials_dirty = false;
}

void Renderer::Impl::ensure_target(uint32_t width, uint32_t height) {
    if (target.valid() && target.width() == width && target.height() == height)
        return;
    target = Image::create(*ctx, {width, height, VK_FORMAT_R8G8B8A8_UNORM,
                                  VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "render target"});
    readback = Buffer::create(*ctx, {VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     MemoryUse::Readback, 0, "render readback"});
    VX_ASSERT_MSG(target.valid() && readback.valid(), "out of GPU memory for the render target");
}

void Renderer::Impl::write_params(const RenderSettings& s, const Camera& cam) {
    gpu::FrameParams p{};
    const glm::vec3 fwd = glm::normalize(cam.forward);
    const glm::vec3 right = glm::normalize(glm::cross(fwd, cam.up));
    const glm::vec3 up = glm::cross(right, fwd);
    p.camera_origin = glm::vec4(cam.offset, std::tan(glm::radians(cam.fov_y_degrees) * 0.5f));
    p.camera_forward = glm::vec4(fwd, float(s.width) / float(s.height));
    p.camera_right = glm::vec4(right, 0.f);
    p.camera_up = glm::vec4(up, 0.f);
    p.sky_color = glm::vec4(s.sky, 0.f);
    // 64-bit difference, then float: the light is placed relative to the camera's block.
    const world::BlockPos rel = s.light.block - cam.block;
    p.light_corner = glm::vec4(glm::vec3(rel) + s.light.offset, 0.f);
    p.light_edge_u = glm::vec4(s.light.edge_u, 0.f);
    p.light_edge_v = glm::vec4(s.light.edge_v, 0.f);
    p.light_emission = glm::vec4(s.light.emission, 0.f);
    p.size_samples = glm::uvec4(s.width, s.height, s.shadow_samples, s.max_bounces);
    const uint32_t mode = s.mode == ShadingMode::Flat ? gpu::kModeFlat
                          : s.mode == ShadingMode::Full ? gpu::kModeFull
                                                        : gpu::kModeVisibility;
    p.mode_seed = glm::uvec4(mode, s.seed, material_count, 0);
    p.chunk_table = accel->chunk_table();
    p.materials = materials.address();
    std::memcpy(params[ctx->frame_slot()].mapped(), &p, sizeof p);
}

void Renderer::Impl::write_descriptors() {
    const uint32_t slot = ctx->frame_slot();
    VkAccelerationStructureKHR tlas = accel->tlas();
    VkWriteDescriptorSetAccelerationStructureKHR as_info{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
    as_info.accelerationStructureCount = 1;
    as_info.pAccelerationStructures = &tlas;
    VkDescriptorImageInfo image_info{VK_NULL_HANDLE, target.view(), VK_IMAGE_LAYOUT_GENERAL};
    VkDescriptorBufferInfo buffer_info{params[slot].handle(), 0, sizeof(gpu::FrameParams)};
    VkWriteDescriptorSet w[3];
    for (uint32_t i = 0; i < 3; ++i) {
        w[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w[i].dstSet = sets[slot];
        w[i].dstBinding = i;
        w[i].descriptorCount = 1;
    }
    w[0].pNext = &as_info;
    w[0].descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    w[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    w[1].pImageInfo = &image_info;
    w[2].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w[2].pBufferInfo = &buffer_info;
    vkUpdateDescriptorSets(ctx->device(), 3, w, 0, nullptr);
}

void Renderer::Impl::record_trace(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
    image_barrier(cmd, target.handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline->pipeline());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline->layout(), 0, 1,
                            &sets[ctx->frame_slot()], 0, nullptr);
    pipeline->trace(cmd, width, height);
    stamp(cmd, 3);
    image_barrier(cmd, target.handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width, height, 1};
    vkCmdCopyImageToBuffer(cmd, target.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.handle(), 1, &region);
    stamp(cmd, 4);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                   VK_ACCESS_2_HOST_READ_BIT);
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera) {
    using Clock = std::chrono::steady_clock;
    VX_ASSERT(settings.width > 0 && settings.height > 0);
    const auto t0 = Clock::now();
    Impl& d = *m;
    VkCommandBuffer cmd = d.ctx->begin_frame();
    d.update_materials();
    d.ensure_target(settings.width, settings.height);
    if (d.queries)
        vkCmdResetQueryPool(cmd, d.queries, d.ctx->frame_slot() * Impl::kStamps, Impl::kStamps);
    d.stamp(cmd, 0);
    d.accel->record_builds(cmd);
    d.stamp(cmd, 1);
    d.accel->record_tlas_build(cmd, camera.block);
    d.stamp(cmd, 2);
    d.write_params(settings, camera);
    d.write_descriptors();
    d.record_trace(cmd, settings.width, settings.height);
    const auto t1 = Clock::now();
    d.ctx->end_frame();
    d.ctx->wait_frame();
    const auto t2 = Clock::now();

    RenderImage img;
    img.width = settings.width;
    img.height = settings.height;
    img.rgba.resize(size_t(settings.width) * settings.height * 4);
    std::memcpy(img.rgba.data(), d.readback.mapped(), img.rgba.size());

    const AccelStats& a = d.accel->stats();
    d.stats = {a.blas_builds, a.blas_refits, a.instances, a.triangles,
               std::chrono::duration<double, std::milli>(t1 - t0).count(),
               std::chrono::duration<double, std::milli>(t2 - t1).count()};
    d.read_stamps();
    return img;
}

RenderImage Renderer::render(const RenderSettings& settings, const Camera& camera, const Scene& scene) {
    set_registry(scene.registry ? *scene.registry : world::BlockRegistry::default_registry());
    std::unordered_set<world::ChunkCoord, world::ChunkCoordHash> keep;
    for (const auto& [c, mesh] : scene.chunks) {
        VX_ASSERT(mesh != nullptr);
        keep.insert(c);
        set_chunk(c, *mesh);
    }
    m->accel->retain_only(keep);
    return render(settings, camera);
}

void Renderer::set_registry(const world::BlockRegistry& registry) {
    m->registry = registry;
    m->materials_dirty = true;
}

void Renderer::set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh) {
    mesh.for_each_quad([&](const world::Quad& q) { m->max_block_id = std::max<uint32_t>(m->max_block_id, q.block); });
    m->accel->set_chunk(c, mesh);
}

void Renderer::remove_chunk(world::ChunkCoord c) { m->accel->remove_chunk(c); }
void Renderer::clear_chunks() { m->accel->clear(); }
const DeviceReport& Renderer::device() const { return m->ctx->report(); }
uint32_t Renderer::validation_errors() const { return m->ctx->validation_errors(); }
const RenderStats& Renderer::last_stats() const { return m->stats; }
GpuMemoryStats Renderer::memory_stats() const {
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
