#pragma once
// The game's own "world/chunk.h", named like a vx internal header. vx::vx must not put
// include/vx/internal on the game's include path, where vx's header of this name would be found
// in its place (and this one, found by vx's headers, would break them: it declares none of vx).
namespace game {

struct Chunk {
    int blocks = 0;
};
inline constexpr int kChunkMarker = 4242;

} // namespace game
