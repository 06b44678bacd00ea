#pragma once
// vx's headless ray-tracing renderer: the public API. A scene is a set of chunk meshes
// (ChunkCoord -> world::ChunkMesh) plus a BlockRegistry for materials; render() traces one image
// and reads it back. No Vulkan types here: only render/ touches Vk* objects.
//
// Coordinates: world block units (y up). The camera and the light are given as a 64-bit block
// position plus a float offset inside (or from) that block; everything the GPU sees is relative
// to the camera's block, so far-away worlds (2^24 blocks and beyond) render like the origin.
// Main thread only.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/device_probe.h"
#include "world/block_registry.h"
#include "world/mesh/chunk_mesh.h"
#include "world/coords.h"

namespace vx::render {

class Context;

struct Camera {
    world::BlockPos block{0};       // World block holding the eye.
    glm::vec3 offset{0.5f};         // Eye position inside that block, 0..1 per axis.
    glm::vec3 forward{0, 0, -1};    // View direction (need not be unit).
    glm::vec3 up{0, 1, 0};          // Approximate up; must not be parallel to forward.
    float fov_y_degrees = 60.f;     // Vertical field of view.

    // A camera at world position `eye` looking at `target` (double precision world units).
    static Camera look_at(glm::dvec3 eye, glm::dvec3 target, glm::vec3 up = {0, 1, 0}, float fov_y_degrees = 60.f);
};

// A two-sided rectangular area light: corner = block + offset, spanned by edge_u and edge_v.
struct AreaLight {
    world::BlockPos block{0};
    glm::vec3 offset{0.f};
    glm::vec3 edge_u{16, 0, 0};
    glm::vec3 edge_v{0, 0, 16};
    glm::vec3 emission{20.f}; // Radiance, linear RGB.
};

enum class ShadingMode : uint8_t {
    Flat,       // Block albedo (linear, unencoded) at the primary hit, sky colour on a miss.
    Full,       // Area light + soft shadows + emission + mirror reflections; sRGB encoded.
    Visibility, // Fraction of unoccluded shadow samples at the primary hit (grey), sky on a miss.
};

struct RenderSettings {
    uint32_t width = 64, height = 64;
    ShadingMode mode = ShadingMode::Full;
    uint32_t shadow_samples = 4; // Per pixel and bounce (correlated multi-jittered); 0: no shadows.
    uint32_t max_bounces = 2;    // Mirror reflection depth.
    uint32_t seed = 1;           // Same seed, same image.
    glm::vec3 sky{0.55f, 0.7f, 0.95f}; // Linear RGB radiance of the sky.
    AreaLight light;
};

// 8-bit RGBA pixels, row 0 at the top.
struct RenderImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
    glm::u8vec4 at(uint32_t x, uint32_t y) const {
        const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
        return {p[0], p[1], p[2], p[3]};
    }
};

struct RenderStats {
    uint32_t blas_builds = 0, blas_refits = 0, instances = 0;
    uint64_t triangles = 0;  // Including spare (degenerate) slots.
    double cpu_ms = 0;       // Recording, including CPU-side geometry work.
    double gpu_ms = 0;       // Submit to fence (builds + trace + copy), wall clock.
    // GPU time of each phase from timestamp queries, milliseconds; -1 where the queue has no
    // timestamps. Upload + BLAS builds/refits, the TLAS build, the trace, the image read-back copy.
    double gpu_blas_ms = -1, gpu_tlas_ms = -1, gpu_trace_ms = -1, gpu_copy_ms = -1;
};

// A whole scene for the one-call API: chunk meshes (not owned) plus the materials.
struct Scene {
    std::vector<std::pair<world::ChunkCoord, const world::ChunkMesh*>> chunks;
    const world::BlockRegistry* registry = nullptr; // Null: the default registry.
};

// GPU memory of the renderer's sub-allocator, bytes (all of the renderer's buffers and images).
struct GpuMemoryStats {
    uint64_t held_bytes = 0; // Device memory blocks allocated from the driver.
    uint64_t used_bytes = 0; // Of them, handed out to resources.
};

struct RendererCreateInfo {
    bool validation = false;
    bool sync_validation = false; // With validation: synchronization validation too (slow).
    DeviceChoice device{};
    // BLASes allow updates, so edits that fit their slots refit; false: no ALLOW_UPDATE (the
    // driver may build a faster-to-trace BVH) and every edit rebuilds its chunk's BLAS.
    bool allow_refit = true;
};

class Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const RendererCreateInfo& info);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Materials come from `registry` (copied); unknown ids get the registry's fallback colours.
    void set_registry(const world::BlockRegistry& registry);
    // Incremental scene edits: applied at the next render() (refit when the slots fit).
    void set_chunk(world::ChunkCoord c, const world::ChunkMesh& mesh);
    void remove_chunk(world::ChunkCoord c);
    void clear_chunks();

    // Renders one image and reads it back (waits for the GPU).
    RenderImage render(const RenderSettings& settings, const Camera& camera);
    // One call: makes `scene` the renderer's scene, then renders. Chunks absent from `scene` are
    // dropped; every chunk in it is re-sent (a refit when its slots fit), so for small edits
    // prefer set_chunk + render.
    RenderImage render(const RenderSettings& settings, const Camera& camera, const Scene& scene);

    const DeviceReport& device() const;
    uint32_t validation_errors() const;
    const RenderStats& last_stats() const;
    GpuMemoryStats memory_stats() const;
    Context& context();

private:
    Renderer();
    struct Impl;
    std::unique_ptr<Impl> m;
};

// Writes an image as PNG (stb_image_write). Main thread only.
Status write_png(const std::string& path, const RenderImage& image);

} // namespace vx::render
