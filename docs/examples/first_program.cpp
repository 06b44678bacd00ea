// A first vx program: a stored world, a short walk through it, a block placed, a picture saved.
// Sized to run in seconds without a GPU (on lavapipe, the CPU driver, a 1280x720 frame takes
// seconds); for a game raise the picture (1280x720, or a window), view_radius (8) and the frames
// (until the player quits).
#include <chrono>
#include <cstdio>
#include <thread>

#include <vx/vx.h>

int main() {
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::sqlite("my_world.db", /*seed=*/2024); // persists edits
    info.streaming.view_radius = 2;                                      // chunks of 32 blocks
    info.streaming.view_radius_vertical = 1;
    info.render.target = vx::RenderTarget::headless(160, 90);            // picture in memory
    auto created = vx::Engine::create(info);
    if (!created) { std::fprintf(stderr, "%s\n", created.error().c_str()); return 1; }
    vx::Engine& engine = **created;
    const std::optional<vx::BlockId> lamp = engine.find_block("lamp");  // ids by name
    if (!lamp) { std::fprintf(stderr, "no block named lamp\n"); return 1; }

    vx::Viewer player;
    player.block = {0, vx::terrain_height(2024, 0, 0) + 2, 0};
    player.forward = {1, -0.2, 0};
    if (vx::Status s = engine.set_viewer(player); !s) { std::fprintf(stderr, "%s\n", s.error().c_str()); return 1; }
    while (!engine.settled()) {                       // a loading screen: fill the view first
        engine.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    vx::Image frame;
    const int frames = 10;
    for (int i = 0; i < frames; ++i) {                // the game loop
        player.offset.x += 0.1;                       // move (blocks)
        engine.set_viewer(player);
        engine.update();                              // streaming, meshes, saves: ~2 ms budget
        auto hit = engine.raycast(player.block, player.offset, player.forward, 8.0);
        if (i == frames / 2 && hit && hit->kind == vx::RayHit::Kind::Hit)
            engine.set_block(hit->previous, *lamp);   // place a block where the player looks
        if (vx::Status s = engine.render_to_image(frame); !s) { std::fprintf(stderr, "%s\n", s.error().c_str()); return 1; }
    }
    vx::write_png("my_world.png", frame);             // the last frame
    auto ticket = engine.save();                      // returns at once
    if (ticket) engine.wait(*ticket);                 // or poll engine.save_state(*ticket)
    std::printf("%d frames of %ux%u, %zu chunks loaded\n", frames, frame.width, frame.height, engine.stats().chunks_loaded);
    return engine.shutdown() ? 0 : 1;                 // saves and syncs what is left
}
