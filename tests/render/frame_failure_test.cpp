// Frame resources that cannot be allocated and a lost device (Context's test hooks): the frame
// call returns an error line instead of aborting, the scene is kept, and the next frame after
// the injection stops renders the image a fresh renderer renders. A lost device fails every
// later frame; a new renderer given the same meshes renders the same image. Validation stays
// silent throughout. A frame size the device cannot hold is refused before any frame.
#include <cctype>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>

#include "render/commands.h"
#include "render/context.h"
#include "scene_util.h"

namespace vx::render {
namespace {

const Camera kCamera = Camera::look_at({30.3, 24.6, 29.1}, {-4.0, 4.0, -6.0});

RenderSettings small(ShadingMode mode, bool denoise, bool raster = false) {
    RenderSettings s;
    s.width = 32;
    s.height = 24;
    s.mode = mode;
    s.shadow_samples = 1;
    s.max_bounces = 1;
    s.denoise = denoise;
    s.pipeline = raster ? PipelineKind::Raster : PipelineKind::RayTraced;
    return s;
}

// One opaque white square of UI, so the UI pass runs (its texture and geometry).
UiDrawList white_square() {
    UiDrawList ui;
    for (glm::vec2 p : {glm::vec2(2, 2), glm::vec2(8, 2), glm::vec2(8, 8), glm::vec2(2, 8)})
        ui.vertices.push_back({p, {0.5f, 0.5f}, 0xffffffffu});
    ui.indices = {0, 1, 2, 0, 2, 3};
    ui.cmds.push_back({0, 6, {0, 0, 32, 24}});
    return ui;
}

struct Injection {
    const char* name_prefix; // Context::fail_allocations: the resources' debug names, or calls'.
    bool denoise = false;    // Full mode with the denoiser (its images).
    bool gbuffer = false;    // try_render with a GBufferImage (the G-buffer read-back).
    bool ui = false;         // A UI over the frame (its texture).
    bool raster = false;     // The raster pipeline (its depth buffer).
    bool light_cache = false; // Full mode with the light cache.
};

RenderSettings settings_of(const Injection& inj) {
    RenderSettings s = small(inj.denoise || inj.light_cache ? ShadingMode::Full : ShadingMode::Flat, inj.denoise,
                             inj.raster);
    s.light_cache = inj.light_cache;
    return s;
}

class FrameFailure : public ::testing::TestWithParam<Injection> {};

// The reference: a fresh renderer's first frame of the scene (Flat, or Full + denoiser: with
// accumulate 1 each frame traces with the same seed and starts without history).
RenderImage reference(const world::MeshMap& meshes, const Injection& inj) {
    std::unique_ptr<Renderer> r = test::make_renderer();
    EXPECT_NE(r, nullptr);
    if (!r)
        return {};
    test::load_meshes(*r, meshes);
    if (inj.ui)
        r->set_ui(white_square());
    const RenderSettings s = settings_of(inj);
    GBufferImage g;
    Result<RenderImage> img = r->try_render(s, kCamera, inj.gbuffer ? &g : nullptr);
    EXPECT_TRUE(img) << (img ? "" : img.error());
    EXPECT_EQ(r->validation_errors(), 0u);
    return img ? std::move(*img) : RenderImage{};
}

TEST_P(FrameFailure, OneLineErrorThenTheNextFrameRenders) {
    const Injection inj = GetParam();
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderImage expected = reference(meshes, inj);
    ASSERT_FALSE(expected.rgba.empty());

    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    test::load_meshes(*r, meshes);
    if (inj.ui)
        r->set_ui(white_square());
    const RenderSettings s = settings_of(inj);
    GBufferImage g;
    r->fail_allocations(inj.name_prefix);
    const bool call = std::string_view(inj.name_prefix).starts_with("vk"); // Not a resource.
    for (int i = 0; i < 2; ++i) { // Still failing while the injection lasts, never aborting.
        Result<RenderImage> failed = r->try_render(s, kCamera, inj.gbuffer ? &g : nullptr);
        ASSERT_FALSE(failed) << inj.name_prefix;
        EXPECT_NE(failed.error().find("out of GPU memory"), std::string::npos) << failed.error();
        EXPECT_EQ(failed.error().find('\n'), std::string::npos); // One line.
        if (call && !inj.ui) { // Named (the UI's error names its whole preparation).
            EXPECT_NE(failed.error().find(inj.name_prefix), std::string::npos) << failed.error();
        }
    }
    if (inj.ui && !call) { // The texture is allocated when it is set: refused now, the default kept.
        EXPECT_FALSE(r->set_ui_texture(1, 1, {255, 255, 255, 255}));
    }
    EXPECT_FALSE(r->device_lost());

    r->fail_allocations("");
    Result<RenderImage> img = r->try_render(s, kCamera, inj.gbuffer ? &g : nullptr);
    ASSERT_TRUE(img) << img.error();
    EXPECT_EQ(test::differing_bytes(*img, expected), 0) << inj.name_prefix;
    EXPECT_EQ(r->last_stats().instances, meshes.size()); // Every chunk drawn: none was dropped.
    EXPECT_EQ(r->last_stats().failed_chunks, 0u);
    if (inj.gbuffer) {
        EXPECT_EQ(g.albedo.size(), size_t(s.width) * s.height);
    }
    EXPECT_EQ(r->validation_errors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(EachFrameResource, FrameFailure,
                         ::testing::Values(Injection{"render target"}, Injection{"gbuffer radiance"},
                                           Injection{"gbuffer reflected"}, Injection{"gbuffer mirror light"},
                                           Injection{"gbuffer mirror albedo"},
                                           Injection{"gbuffer mirror normal depth"}, Injection{"render readback"},
                                           Injection{"gbuffer readback", false, true}, Injection{"materials"},
                                           Injection{"emitter chunks"}, Injection{"emitter faces"}, Injection{"emitter bounds"},
                                           Injection{"TLAS"},
                                           Injection{"TLAS instances"}, Injection{"chunk table"}, Injection{"AS scratch"},
                                           Injection{"frame staging"}, Injection{"slot index pattern"},
                                           Injection{"denoise", true}, Injection{"ui", false, false, true},
                                           Injection{"raster depth", false, false, false, true},
                                           // Pipelines made at their first frame (these were
                                           // VK_CHECK aborts): Context::create_call's names.
                                           Injection{"vkCreateDescriptorSetLayout (denoise", true},
                                           Injection{"vkCreatePipelineLayout (denoise", true},
                                           Injection{"vkCreateShaderModule (denoise_atrous", true},
                                           Injection{"vkCreateComputePipelines (denoise_temporal", true},
                                           Injection{"vkCreateDescriptorPool (denoise", true},
                                           Injection{"vkAllocateDescriptorSets (denoise", true},
                                           Injection{"vkCreatePipelineLayout (light cache", false, false, false,
                                                     false, true},
                                           Injection{"vkCreateComputePipelines (light_cache", false, false, false,
                                                     false, true},
                                           // The resolve's alone, after the gather's was made.
                                           Injection{"vkCreateComputePipelines (light_cache.comp", false, false,
                                                     false, false, true},
                                           Injection{"vkCreatePipelineLayout (raster", false, false, false, true},
                                           Injection{"vkCreateShaderModule (raster.frag", false, false, false, true},
                                           Injection{"vkCreateGraphicsPipelines (raster", false, false, false, true},
                                           Injection{"vkCreateGraphicsPipelines (raster transparent", false, false,
                                                     false, true},
                                           Injection{"vkCreatePipelineLayout (ui", false, false, true},
                                           Injection{"vkCreateGraphicsPipelines (ui", false, false, true}),
                         [](const ::testing::TestParamInfo<Injection>& p) {
                             std::string n = p.param.name_prefix;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c)))
                                     c = '_';
                             return n;
                         });

// A TLAS that cannot be made for many frames (a second of them at 60 fps) does not grow: its
// capacity doubled at every attempt, so after about 40 failed frames the next allocation asked
// for terabytes and the process aborted.
TEST(TlasFailure, ManyFailedFramesDoNotGrowTheTlas) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderSettings s = small(ShadingMode::Flat, false);
    std::unique_ptr<Renderer> fresh = test::make_renderer();
    ASSERT_NE(fresh, nullptr);
    test::load_meshes(*fresh, meshes);
    ASSERT_TRUE(fresh->try_render(s, kCamera));
    const uint64_t tlas_bytes = fresh->last_stats().memory.tlas;
    ASSERT_GT(tlas_bytes, 0u);

    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    test::load_meshes(*r, meshes);
    r->fail_allocations("TLAS");
    for (int i = 0; i < 64; ++i)
        ASSERT_FALSE(r->try_render(s, kCamera));
    r->fail_allocations("");
    Result<RenderImage> img = r->try_render(s, kCamera);
    ASSERT_TRUE(img) << img.error();
    EXPECT_LE(r->last_stats().memory.tlas, 2 * tlas_bytes);
    EXPECT_EQ(r->last_stats().instances, meshes.size());
    EXPECT_EQ(r->validation_errors(), 0u);
}

// Any failure of a submit, a wait, a command pool's reset, a command buffer's begin or end or a
// query read (out of memory, an unknown error) gives the device up as lost: the frame fails with
// the lost-device line, later ones too, and the renderer is destroyed cleanly. Out of memory
// there was VK_CHECKed (an abort); so was a compaction query read on a device lost after the
// frame's fence wait.
TEST(DeviceErrors, AFailedSubmitWaitEndOrQueryIsALostDeviceNotAnAbort) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderSettings s = small(ShadingMode::Flat, false);
    const std::pair<const char*, VkResult> cases[] = {
        {"vkQueueSubmit2", VK_ERROR_OUT_OF_DEVICE_MEMORY},
        {"vkWaitForFences", VK_ERROR_OUT_OF_HOST_MEMORY},
        {"vkEndCommandBuffer", VK_ERROR_OUT_OF_DEVICE_MEMORY},
        {"vkGetQueryPoolResults (compaction)", VK_ERROR_DEVICE_LOST},
        {"vkResetCommandPool", VK_ERROR_OUT_OF_DEVICE_MEMORY},
        {"vkBeginCommandBuffer", VK_ERROR_OUT_OF_HOST_MEMORY},
    };
    for (const auto& [call, result] : cases) {
        std::unique_ptr<Renderer> r = test::make_renderer();
        ASSERT_NE(r, nullptr);
        test::load_meshes(*r, meshes);
        ASSERT_TRUE(r->try_render(s, kCamera)) << call; // Frame 1 builds; its queries are read in frame 3.
        r->context().inject_result(call, result);
        bool failed = false;
        for (int i = 0; i < 4 && !failed; ++i) {
            Result<RenderImage> img = r->try_render(s, kCamera);
            if (!img) {
                failed = true;
                EXPECT_NE(img.error().find("device was lost"), std::string::npos) << call << ": " << img.error();
            }
        }
        EXPECT_TRUE(failed) << call << " was never called, or its failure never reached the frame";
        EXPECT_TRUE(r->device_lost()) << call;
        EXPECT_FALSE(r->try_render(s, kCamera)) << call;
        EXPECT_EQ(r->validation_errors(), 0u) << call;
    }
}

// Renderer::create with Context::fail_allocations(`fail`) from the start: its error ("created"
// if it did not fail).
std::string create_error(const std::string& fail) {
    RendererCreateInfo ci;
    ci.validation = true;
    ci.device = test::test_device_choice();
    ci.fail_allocations = fail;
    Result<std::unique_ptr<Renderer>> r = Renderer::create(ci);
    return r ? std::string("created") : r.error();
}

// Out of memory while the renderer is made (a renderer recreated after a device loss meets a
// full device) is an error from create, not an assertion; the emitter-faces pipeline, made at
// the first frame with an emitter, is a frame error and the next frame draws once it fits.
TEST(RendererCreateFailure, OutOfMemoryIsAnErrorFromCreate) {
    for (const char* resource : {"shader binding table", "rt pipeline", "frame params"}) {
        const std::string e = create_error(resource);
        EXPECT_NE(e.find("cannot create the renderer: out of GPU memory"), std::string::npos) << resource << ": " << e;
    }
}

// A creation call refused while the renderer is made (each was a VK_CHECK abort): an error from
// create naming the call, and nothing leaked: the validation layer reports leaked objects as
// errors when the device is destroyed, inside create here, so its log lines are counted.
TEST(RendererCreateFailure, ARefusedCreationCallIsAnErrorNamingIt) {
    const test::LayerErrorCounter layer;
    for (const char* call : {"vkCreateDescriptorSetLayout (rt set layout)",
                             "vkCreatePipelineLayout (rt pipeline layout)",
                             "vkCreateShaderModule (closest_hit.rchit)", "vkGetRayTracingShaderGroupHandlesKHR",
                             "vkCreateDescriptorPool (rt descriptor pool)",
                             "vkAllocateDescriptorSets (rt descriptor set)", "vkCreateQueryPool (frame timestamps)"}) {
        const std::string e = create_error(call);
        EXPECT_NE(e.find("cannot create the renderer: out of GPU memory"), std::string::npos) << e;
        EXPECT_NE(e.find(std::string(call) + " failed (VK_ERROR_OUT_OF_HOST_MEMORY)"), std::string::npos) << e;
    }
    // The context's: its frames' command pools, buffers and fences, the debug messenger.
    const std::string frames = "cannot create the Vulkan context's frames: ";
    const std::pair<const char*, std::string> context_calls[] = {
        {"vkCreateCommandPool (frame pool 1)", frames},
        {"vkAllocateCommandBuffers (frame cmd 0)", frames},
        {"vkCreateFence (frame fence 1)", frames},
        {"vkCreateCommandPool (one-shot pool)", frames},
        {"vkCreateFence (one-shot fence)", frames},
        {"vkCreateDebugUtilsMessengerEXT", "cannot create the Vulkan instance's debug messenger: "},
    };
    for (const auto& [call, prefix] : context_calls) {
        const std::string e = create_error(call);
        EXPECT_NE(e.find(prefix + call + " failed (VK_ERROR_OUT_OF_HOST_MEMORY)"), std::string::npos) << e;
    }
    EXPECT_EQ(layer.errors(), 0);
}

// Out of memory in a one-shot submission (the material table's upload at the first frame: its
// pool's reset, its buffer's allocation, begin or end, its fence's reset) or in the reset of a
// frame's fence: a lost context, reported by the frame, not a VK_CHECK abort; nothing leaks.
TEST(DeviceErrors, AFailedOneShotOrFenceResetIsALostDeviceNotAnAbort) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderSettings s = small(ShadingMode::Flat, false);
    const test::LayerErrorCounter layer;
    for (const char* call : {"vkResetCommandPool (one-shot)", "vkAllocateCommandBuffers (one-shot cmd)",
                             "vkBeginCommandBuffer (one-shot)", "vkEndCommandBuffer (one-shot)",
                             "vkResetFences (one-shot)", "vkResetFences"}) {
        std::unique_ptr<Renderer> r = test::make_renderer();
        ASSERT_NE(r, nullptr);
        test::load_meshes(*r, meshes);
        r->context().inject_result(call, VK_ERROR_OUT_OF_DEVICE_MEMORY);
        Result<RenderImage> img = r->try_render(s, kCamera);
        ASSERT_FALSE(img) << call;
        EXPECT_NE(img.error().find("device was lost"), std::string::npos) << call << ": " << img.error();
        EXPECT_TRUE(r->device_lost()) << call;
        EXPECT_EQ(r->validation_errors(), 0u) << call;
    }
    EXPECT_EQ(layer.errors(), 0); // Leaks are reported as each renderer is destroyed.
}

// A lost device: this frame and every later one fail with the same line, the renderer still
// takes scene edits and is destroyed cleanly; a new renderer given the meshes renders the image
// the old one rendered before the loss.
TEST(DeviceLoss, FramesFailUntilANewRendererRendersTheSameImage) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderSettings s = small(ShadingMode::Flat, false);
    RenderImage before;
    {
        std::unique_ptr<Renderer> r = test::make_renderer();
        ASSERT_NE(r, nullptr);
        test::load_meshes(*r, meshes);
        Result<RenderImage> img = r->try_render(s, kCamera);
        ASSERT_TRUE(img) << img.error();
        before = std::move(*img);

        r->simulate_device_loss();
        for (int i = 0; i < 3; ++i) {
            Result<RenderImage> lost = r->try_render(s, kCamera);
            ASSERT_FALSE(lost);
            EXPECT_NE(lost.error().find("device was lost"), std::string::npos) << lost.error();
        }
        EXPECT_TRUE(r->device_lost());
        EXPECT_FALSE(r->set_ui_texture(1, 1, {1, 2, 3, 4}));
        r->set_chunk(meshes.begin()->first, meshes.begin()->second.mesh); // Taken, not drawn.
        EXPECT_EQ(r->validation_errors(), 0u);
    }
    EXPECT_EQ(test::differing_bytes(test::fresh_render(meshes, s, kCamera), before), 0);
}

// A one-shot submission whose fence wait fails (the GPU hung and the driver gave the device up:
// Context::simulate_hang) may still be pending: it is not freed
// (VUID-vkFreeCommandBuffers-pCommandBuffers-00047), nor is its pool reset under it by the next
// one-shot (VUID-vkResetCommandPool-commandPool-00040); the context reads as lost and is destroyed
// cleanly. The buffer was freed right after the failed wait.
using OneShotHang = test::RenderTest;

TEST_F(OneShotHang, APendingOneShotIsNotFreedAfterAFailedWait) {
    auto barrier = [](VkCommandBuffer cmd) {
        memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
    };
    m_ctx->submit_now(barrier); // One that completes first: the pool has been used.
    EXPECT_FALSE(m_ctx->lost());
    m_ctx->simulate_hang();
    m_ctx->submit_now(barrier);
    EXPECT_TRUE(m_ctx->lost());
    m_ctx->submit_now(barrier); // On the lost device: recorded, never submitted.
    EXPECT_EQ(m_ctx->validation_errors(), 0u);
}

// The estimate of check_frame_size against this device's largest device-local heap: 16384^2
// pixels need 16384^2 * frame_bytes_per_pixel() (240 B: about 60 GiB), more than lavapipe's heap
// (the machine's memory); a small frame fits anywhere.
TEST(FrameSize, TooLargeForTheDeviceIsRefusedWithTheEstimate) {
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    EXPECT_TRUE(r->check_frame_size(64, 64));
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(r->context().physical_device(), &mem);
    uint64_t heap = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            heap = std::max<uint64_t>(heap, mem.memoryHeaps[i].size);
    const uint64_t need = 16384ull * 16384ull * frame_bytes_per_pixel();
    const Status big = r->check_frame_size(16384, 16384);
    if (need <= heap)
        GTEST_SKIP() << "this device's heap holds a 16384^2 frame";
    ASSERT_FALSE(big);
    EXPECT_NE(big.error().find("16384x16384"), std::string::npos) << big.error();
    EXPECT_NE(big.error().find("GiB"), std::string::npos) << big.error();
}

// No memory for the query pool that reads compacted BLAS sizes (it was VK_CHECKed: an abort in
// the middle of a frame): compaction is skipped, the chunks keep their build size and draw the
// same image, and chunks built once memory is back are compacted again.
TEST(DeviceErrors, NoMemoryForCompactionQueriesLeavesChunksUncompacted) {
    const world::World w = test::hills();
    const world::MeshMap meshes = test::mesh_world(w);
    const RenderSettings s = small(ShadingMode::Flat, false);
    std::unique_ptr<Renderer> r = test::make_renderer();
    ASSERT_NE(r, nullptr);
    r->fail_allocations("BLAS compacted sizes");
    test::load_meshes(*r, meshes);
    RenderImage img;
    uint32_t compactions = 0;
    for (int i = 0; i < 4; ++i) {
        img = r->render(s, kCamera);
        compactions += r->last_stats().blas_compactions;
    }
    EXPECT_EQ(compactions, 0u);
    EXPECT_FALSE(r->device_lost());
    EXPECT_EQ(test::differing_bytes(test::fresh_render(meshes, s, kCamera), img), 0);
    r->fail_allocations("");
    r->clear_chunks();
    test::load_meshes(*r, meshes);
    for (int i = 0; i < 4; ++i) {
        r->render(s, kCamera);
        compactions += r->last_stats().blas_compactions;
    }
    EXPECT_GT(compactions, 0u);
    EXPECT_EQ(r->validation_errors(), 0u);
}

} // namespace
} // namespace vx::render
