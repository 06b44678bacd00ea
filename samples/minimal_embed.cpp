// The smallest program that embeds vx, through <vx/vx.h> alone: a generated world streamed
// around a moving viewer, an edit, and a ray-traced picture. Headless (no window).
//
//   minimal_embed [OUT.png] [--device auto|cpu|gpu|N]
#include <cstdio>
#include <string>
#include <thread>

#include <vx/vx.h>

int main(int argc, char** argv) {
    std::string out = "minimal_embed.png", device = "auto";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--device" && i + 1 < argc)
            device = argv[++i];
        else
            out = a;
    }
    // 1. An engine: built-in terrain, a small view, a 640×360 picture in memory.
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::terrain(2024);
    info.streaming.view_radius = 4;
    info.streaming.view_radius_vertical = 2;
    info.render.target = vx::RenderTarget::headless(640, 360);
    info.render.device = device;
    auto engine = vx::Engine::create(info);
    if (!engine) {
        std::fprintf(stderr, "minimal_embed: %s\n", engine.error().c_str());
        return 2;
    }
    vx::Engine& e = **engine;

    // 2. Fly along +x for a second of game time (60 frames of 16 ms), then let the view fill.
    vx::Viewer viewer;
    viewer.block = {0, vx::terrain_height(2024, 0, 0) + 20, 0};
    viewer.forward = {30, -8, 0};
    auto now = std::chrono::steady_clock::now();
    for (int frame = 0; frame < 60 || !e.settled(); ++frame) {
        if (frame < 60)
            viewer.offset.x += 0.5;
        e.set_viewer(viewer);
        e.update(now += std::chrono::milliseconds(16));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }

    // 3. An edit: a mirror pillar in front of the camera, on the ground.
    const int64_t px = viewer.block.x + int64_t(viewer.offset.x) + 24;
    const int64_t top = vx::terrain_height(2024, px, 0);
    for (int64_t y = top + 1; y <= top + 12; ++y)
        if (vx::Status s = e.set_block({px, y, 0}, *e.find_block("mirror")); !s)
            std::fprintf(stderr, "minimal_embed: edit refused: %s\n", s.error().c_str());

    // 4. A picture.
    vx::Image image;
    if (vx::Status s = e.render_to_image(image); !s || !(s = vx::write_png(out, image))) {
        std::fprintf(stderr, "minimal_embed: %s\n", s.error().c_str());
        return 1;
    }
    const vx::Stats st = e.stats();
    std::printf("minimal_embed: %zu chunks loaded, %zu meshed in view; rendered %s (%u BLAS builds, %.1f ms GPU)\n",
                st.chunks_loaded, st.chunks_meshed, out.c_str(), st.blas_builds, st.gpu_ms);
    return e.shutdown() ? 0 : 1;
}
