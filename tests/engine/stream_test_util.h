#pragma once
// Shared by the ChunkStreamer tests: updating a streamer on a synthetic clock until its view is
// filled. Test main thread only.

#include <chrono>
#include <thread>

#include "engine/chunk_streamer.h"

namespace vx::test {

// Updates `s` at `pos` (looking along -z), advancing the caller's clock `now` by 16 ms a step,
// until the view is loaded and meshed (true) or a generous real-time limit passes on a very slow
// machine (false): a test waits for the state, never for a time.
inline bool settle(engine::ChunkStreamer& s, glm::dvec3 pos, std::chrono::steady_clock::time_point& now) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    do {
        now += std::chrono::milliseconds(16);
        s.update(pos, glm::dvec3(0, 0, -1), now);
        if (s.settled())
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    } while (std::chrono::steady_clock::now() < limit);
    return false;
}

} // namespace vx::test
