#pragma once
// Shared by the tests of the facade <vx/vx.h> (and the sandbox's game tests): waiting for a view
// to fill. Test main thread only.

#include <chrono>
#include <thread>

#include <vx/vx.h>

namespace vx::test {

// Updates `e` until its view is loaded and meshed (true), or `limit` passes on a very slow
// machine (false): a test waits for the state, never for a time.
inline bool settle(vx::Engine& e, std::chrono::seconds limit = std::chrono::minutes(3)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
        e.update();
        if (e.settled())
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

} // namespace vx::test
