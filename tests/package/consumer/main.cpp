// The package test's consumer: a game-like program on the installed facade <vx/vx.h> alone. It
// streams the built-in terrain around a viewer (no GPU: RenderTarget::none), edits a block,
// raycasts onto it and saves the world to a SQLite file, then reopens it and finds the edit.
// Prints "vx_consumer: ok" and exits 0 when all of that holds.
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include <vx/vx.h>

namespace {

bool settle(vx::Engine& e) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (std::chrono::steady_clock::now() < limit) {
        e.update();
        if (e.settled())
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

std::unique_ptr<vx::Engine> open(const std::string& path, vx::BlockPos eye) {
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::sqlite(path, 42);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    auto e = vx::Engine::create(info);
    if (!e) {
        std::printf("vx_consumer: %s\n", e.error().c_str());
        return nullptr;
    }
    vx::Viewer v;
    v.block = eye;
    v.forward = {0, -1, 0.01};
    if (!(*e)->set_viewer(v) || !settle(**e))
        return nullptr;
    return std::move(*e);
}

} // namespace

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : "vx_consumer_world.db";
    std::remove(path.c_str());
    const int64_t ground = vx::terrain_height(42, 0, 0);
    const vx::BlockPos eye{0, ground + 8, 0}, placed{0, ground + 2, 0};
    {
        auto e = open(path, eye);
        if (!e || !e->set_block(placed, 1))
            return 1;
        auto hit = e->raycast(eye, {0.5, 0.5, 0.5}, {0, -1, 0}, 32);
        if (!hit || hit->kind != vx::RayHit::Kind::Hit || hit->block != placed)
            return 2;
        auto ticket = e->save();
        if (!ticket || !e->wait(*ticket) || !e->shutdown())
            return 3;
    }
    auto again = open(path, eye);
    if (!again || again->get_block(placed) != vx::BlockId(1))
        return 4;
    std::printf("vx_consumer: streamed %zu chunks, edit saved and found again\n", again->stats().chunks_loaded);
    std::printf("vx_consumer: ok\n");
    return 0;
}
