#pragma once
// The game's own "engine/engine_impl.h", named like a vx internal header (see world/chunk.h).
namespace game {

inline const char* engine_name() { return "the game's engine"; }

} // namespace game
