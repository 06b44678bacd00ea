// The smallest program that embeds vx: a generated world streamed around a moving viewer, every
// mesh handed to the ray-tracing renderer, an edit, and a picture. Headless (no window).
//
//   minimal_embed [OUT.png] [--device auto|cpu|gpu|N]
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "engine/chunk_streamer.h"
#include "engine/renderer_sink.h"
#include "render/renderer.h"
#include "world/gen/terrain.h"

using namespace vx;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    std::string out = "minimal_embed.png", device = "auto";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--device" && i + 1 < argc)
            device = argv[++i];
        else
            out = a;
    }
    auto choice = render::parse_device_choice(device);
    if (!choice) {
        std::fprintf(stderr, "minimal_embed: %s\n", choice.error().c_str());
        return 2;
    }
    // 1. A renderer (no window) and the streaming engine feeding it.
    render::RendererCreateInfo rci;
    rci.device = *choice;
    auto renderer = render::Renderer::create(rci);
    if (!renderer) {
        std::fprintf(stderr, "minimal_embed: %s\n", renderer.error().c_str());
        return 2;
    }
    const world::TerrainGenerator terrain(2024);
    engine::RendererSink sink(**renderer);
    engine::StreamingSettings settings;
    settings.view_radius = 4;
    settings.view_radius_vertical = 2;
    engine::ChunkStreamer streamer(terrain, /*store=*/nullptr, sink, settings);

    // 2. Fly along +x for a second of game time, one update per frame.
    const double ground = terrain.surface_height(0, 0);
    glm::dvec3 eye(0.5, ground + 20.0, 0.5);
    auto now = Clock::now();
    for (int frame = 0; frame < 60; ++frame) {
        eye.x += 0.5;
        streamer.update(eye, glm::dvec3(1, -0.3, 0), now += std::chrono::milliseconds(16));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    while (!streamer.settled()) { // Let the view fill before taking the picture.
        streamer.update(eye, glm::dvec3(1, -0.3, 0), now += std::chrono::milliseconds(16));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }

    // 3. An edit: a mirror pillar in front of the camera, remeshed through the six-slice path.
    const int64_t px = int64_t(eye.x) + 24;
    const int64_t top = terrain.surface_height(px, 0);
    for (int64_t y = top + 1; y <= top + 12; ++y)
        if (Status s = streamer.set_block({px, y, 0}, *world::BlockRegistry::default_registry().find("mirror")); !s)
            std::fprintf(stderr, "minimal_embed: edit refused: %s\n", s.error().c_str());
    streamer.update(eye, glm::dvec3(1, -0.3, 0), now += std::chrono::milliseconds(16));

    // 4. A picture.
    (*renderer)->set_registry(streamer.world().registry());
    render::RenderSettings rs;
    rs.width = 640;
    rs.height = 360;
    rs.light.block = world::BlockPos(int64_t(eye.x) - 40, int64_t(ground) + 120, -60);
    const render::RenderImage img =
        (*renderer)->render(rs, render::Camera::look_at(eye, eye + glm::dvec3(30, -8, 0)));
    if (Status s = render::write_png(out, img); !s) {
        std::fprintf(stderr, "minimal_embed: %s\n", s.error().c_str());
        return 1;
    }
    const engine::StreamingMetrics m = streamer.metrics();
    std::printf("minimal_embed: %zu chunks loaded, %zu meshed in view; rendered %s on %s\n", m.loaded, m.meshed,
                out.c_str(), (*renderer)->device().name.c_str());
    return 0;
}
