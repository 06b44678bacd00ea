// A game with headers of its own named like vx's internal ones ("world/chunk.h",
// "engine/engine_impl.h"): linking vx::vx must leave them the game's. Prints "vx_shadow: ok".
#include <cstdio>

#include <vx/vx.h>

#include "engine/engine_impl.h"
#include "world/chunk.h"

int main() {
    game::Chunk c;
    c.blocks = game::kChunkMarker;
    const int64_t h = vx::terrain_height(42, 0, 0);
    std::printf("vx_shadow: %s, chunk %d, ground at %lld\n", game::engine_name(), c.blocks, (long long)h);
    std::printf("vx_shadow: ok\n");
    return 0;
}
