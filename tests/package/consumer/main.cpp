// The package test's consumer: generates terrain and meshes it on the engine's job system through
// the installed headers and libraries only. Prints "vx_consumer: ok" and exits 0 when the meshes
// are what the greedy mesher makes of the same chunks on this thread.
// When <vx/vx.h> (the facade) is installed, this program can use it instead: the package test only
// checks for the "ok" line and the exit code.
#include <cstdio>

#include "engine/job_batch.h"
#include "engine/region_mesher.h"
#include "world/gen/terrain.h"
#include "world/world.h"

int main() {
    using namespace vx;
    const world::TerrainGenerator gen(42);
    world::World w;
    const int y = world::chunk_of(world::BlockPos(0, gen.surface_height(0, 0), 0)).y;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dx = -1; dx <= 1; ++dx)
            w.put_chunk(world::ChunkCoord(dx, y, dz), gen.generate(world::ChunkCoord(dx, y, dz)));

    engine::JobSystem jobs(engine::batch_job_system_info(2));
    engine::RegionMesher mesher(jobs);
    world::MeshMap meshes;
    const engine::RegionMeshStats stats = mesher.mesh(w, engine::chunk_coords(w), meshes);

    world::GreedyMesher serial;
    uint32_t expect = 0;
    world::ChunkMesh mesh;
    const world::ChunkCoord centre(0, y, 0);
    serial.mesh({*w.find_chunk(centre), world::make_apron(w, centre), w.registry()}, mesh);
    expect = mesh.quad_count();
    const uint32_t got = meshes[centre].mesh.quad_count();
    std::printf("vx_consumer: %zu chunks meshed, %llu quads; centre chunk %u quads (serial %u)\n", stats.chunks,
                static_cast<unsigned long long>(stats.quads), got, expect);
    if (stats.chunks != 9 || got != expect || expect == 0)
        return 1;
    std::printf("vx_consumer: ok\n");
    return 0;
}
