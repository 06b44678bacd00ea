// Presentation benchmark: frame period (wall time between present() calls) against the GPU time
// of a frame, with two frames in flight, and beside it in the same process the wall time of the
// headless render(), which waits for every frame. Run it under a display (xvfb-run -a on a
// headless machine). Usage: vx_present_bench [rounds=5] [WxH=160x120] [device=auto] [vsync=0]
// A small window keeps lavapipe runs short.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "render/renderer.h"
#include "world/base/median.h"
#include "world/mesh/edit_mesher.h"
#include "world/world.h"

namespace vx::render {
namespace {

// Rolling hills of stone over 4 x 4 chunks, with a wooden tower: a few thousand quads.
void load_scene(Renderer& r) {
    world::World w;
    const world::BlockId stone = *world::BlockRegistry::default_registry().find("stone");
    const world::BlockId wood = *world::BlockRegistry::default_registry().find("wood");
    for (int64_t z = -64; z < 64; ++z)
        for (int64_t x = -64; x < 64; ++x) {
            const int64_t h = 4 + int64_t(3.0 * std::sin(double(x) * 0.15) + 3.0 * std::cos(double(z) * 0.11));
            for (int64_t y = 0; y < h; ++y)
                w.set_block({x, y, z}, stone);
        }
    for (int64_t y = 0; y < 20; ++y)
        for (int64_t z = 0; z < 3; ++z)
            for (int64_t x = 0; x < 3; ++x)
                w.set_block({x, y, z}, wood);
    world::EditMesher mesher;
    world::MeshMap meshes;
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) { mesher.mesh_chunk(w, c, meshes); });
    for (const auto& [c, mc] : meshes)
        r.set_chunk(c, mc.mesh);
}

struct Run {
    const char* name;
    RenderSettings settings;
};

// Rounds of 10 presents (the last 8 measured: frame periods need a previous call, GPU times
// come two frames late) then 3 headless renders, interleaved so machine load hits both alike.
void bench(Renderer& r, const Run& run, int rounds, uint32_t w, uint32_t h) {
    const Camera cam = Camera::look_at({40.5, 30.2, 45.3}, {0, 4, 0});
    std::vector<double> period, wait, cpu, present, gpu, trace, headless;
    RenderSettings s = run.settings;
    s.width = w;
    s.height = h;
    for (int round = 0; round < rounds; ++round) {
        for (int i = 0; i < 10; ++i) {
            glfwPollEvents();
            Result<PresentResult> res = r.present(run.settings, cam);
            if (!res || *res != PresentResult::Presented) {
                std::fprintf(stderr, "present failed: %s\n", res ? "skipped" : res.error().c_str());
                std::exit(1);
            }
            const RenderStats& st = r.last_stats();
            if (i < 2)
                continue;
            period.push_back(st.frame_ms);
            wait.push_back(st.wait_ms);
            cpu.push_back(st.cpu_ms);
            present.push_back(st.present_ms);
            gpu.push_back(st.gpu_frame_ms);
            trace.push_back(st.gpu_trace_ms);
        }
        for (int i = 0; i < 3; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            r.render(s, cam);
            headless.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
    }
    std::printf("%-9s %ux%u present(): frame %.2f ms = wait %.2f + record+submit %.2f + vkQueuePresentKHR %.2f; GPU frame "
                "%.2f ms (trace %.2f); headless render() %.2f ms; frame/GPU %.2f; frame/headless %.2f "
                "[medians of %zu frames, %zu renders]\n",
                run.name, w, h, median(period), median(wait), median(cpu), median(present), median(gpu),
                median(trace), median(headless), median(period) / median(gpu), median(period) / median(headless),
                period.size(), headless.size());
}

} // namespace
} // namespace vx::render

int main(int argc, char** argv) {
    using namespace vx::render;
    const int rounds = argc > 1 ? std::atoi(argv[1]) : 5;
    unsigned w = 160, h = 120;
    if (argc > 2 && std::sscanf(argv[2], "%ux%u", &w, &h) != 2) {
        std::fprintf(stderr, "bad size '%s' (expected WxH)\n", argv[2]);
        return 2;
    }
    vx::Result<DeviceChoice> device = parse_device_choice(argc > 3 ? argv[3] : "auto");
    if (!device) {
        std::fprintf(stderr, "%s\n", device.error().c_str());
        return 2;
    }
    if (rounds < 1 || !glfwInit()) {
        std::fprintf(stderr, "no display (run under xvfb-run -a) or bad round count\n");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(int(w), int(h), "vx present bench", nullptr, nullptr);
    RendererCreateInfo ci;
    ci.device = *device;
    ci.glfw_window = window;
    ci.vsync = argc > 4 && std::atoi(argv[4]) != 0;
    vx::Result<std::unique_ptr<Renderer>> r = Renderer::create(ci);
    if (!window || !r) {
        std::fprintf(stderr, "no renderer: %s\n", r ? "no window" : r.error().c_str());
        return 1;
    }
    std::printf("device: %s (%s), vsync %s\n", (*r)->device().name.c_str(), device_type_name((*r)->device().type),
                ci.vsync ? "on" : "off");
    load_scene(**r);
    RenderSettings flat;
    flat.mode = ShadingMode::Flat;
    RenderSettings full;
    full.shadow_samples = 4;
    full.max_bounces = 1;
    full.light.block = {-20, 40, -20};
    full.light.edge_u = {40, 0, 0};
    full.light.edge_v = {0, 0, 40};
    full.light.emission = glm::vec3(60.f);
    bench(**r, {"flat", flat}, rounds, w, h);
    bench(**r, {"full 4spp", full}, rounds, w, h);
    r->reset();
    glfwDestroyWindow(window);
    glfwTerminate();
    return 0;
}
