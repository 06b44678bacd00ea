#pragma once
// Shared by the tests of the facade <vx/vx.h> (and the sandbox's game tests): waiting for a view
// to fill, temporary world paths. Test main thread only.

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <vx/vx.h>

#include "tests/test_device.h"

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

// A fresh SQLite world path `<tmp>/<dir>/<name>_<pid>.db` (the file and its WAL removed), so
// parallel test processes never share one.
inline std::string temp_world_path(const char* dir, const char* name) {
    const auto folder = std::filesystem::temp_directory_path() / dir;
    std::filesystem::create_directories(folder);
    const auto p = folder / (std::string(name) + "_" + std::to_string(::getpid()) + ".db");
    for (const char* suffix : {"", "-wal", "-shm"})
        std::filesystem::remove(p.string() + suffix);
    return p.string();
}

} // namespace vx::test
