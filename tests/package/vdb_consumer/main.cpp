// The package test's vdb consumer: writes a small world as a VDB file with vx::vdb, then opens it
// through the facade as a read-only world (WorldSource::vdb) and finds its blocks. Prints
// "vx_vdb_consumer: ok" and exits 0 when all of that holds.
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include <vx/vx.h>

#include "world/vdb/vdb_world.h"
#include "world/world.h"

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : "vx_vdb_consumer.vdb";
    vx::world::World w;
    for (int64_t x = 0; x < 8; ++x)
        for (int64_t z = 0; z < 8; ++z)
            w.set_block({x, 0, z}, 1);
    w.set_block({3, 1, 3}, 8);
    if (vx::Status s = vx::vdb::export_vdb(w, path); !s) {
        std::printf("vx_vdb_consumer: %s\n", s.error().c_str());
        return 1;
    }
    vx::EngineCreateInfo info;
    info.world = vx::WorldSource::vdb(path);
    info.streaming.view_radius = 1;
    info.streaming.view_radius_vertical = 1;
    auto e = vx::Engine::create(info);
    if (!e) {
        std::printf("vx_vdb_consumer: %s\n", e.error().c_str());
        return 2;
    }
    vx::Viewer v;
    v.block = {4, 4, 4};
    if (!(*e)->set_viewer(v))
        return 3;
    const auto limit = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (!(*e)->settled() && std::chrono::steady_clock::now() < limit) {
        (*e)->update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if ((*e)->get_block({3, 1, 3}) != vx::BlockId(8) || (*e)->get_block({5, 0, 5}) != vx::BlockId(1))
        return 4;
    std::printf("vx_vdb_consumer: ok\n");
    return (*e)->shutdown() ? 0 : 5;
}
