// An advanced user of a component target: vx::world gives vx's internal headers by their source
// paths. Prints "vx_advanced: ok".
#include <cstdio>

#include "world/block_registry.h"
#include "world/chunk.h"

int main() {
    const vx::world::Chunk c(vx::world::BlockId(1));
    if (!c.is_uniform() || c.get(0, 0, 0) != vx::world::BlockId(1))
        return 1;
    std::printf("vx_advanced: ok\n");
    return 0;
}
