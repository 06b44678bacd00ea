#pragma once
// The sandbox's command line. Pure parsing (no window): unit-testable.
#include <cstdint>
#include <string>
#include <vector>

#include <vx/result.h>

#include "replay.h"

namespace sandbox {

struct Options {
    uint32_t width = 1280, height = 720; // --size WxH: window size in screen pixels.
    bool fullscreen = false;             // --fullscreen: the primary monitor's mode.
    bool vsync = true;                   // --no-vsync (V toggles it while playing).
    std::string world;                   // --world PATH (SQLite; default under XDG_DATA_HOME).
    uint64_t seed = 1;                   // --seed S: terrain of new worlds.
    std::string vdb;                     // --vdb FILE: play a VDB world; edits are kept in
                                         // FILE.edits.sqlite (the file is never written).
    bool read_only = false;              // --read-only (with --vdb): keep no edits.
    std::string replay;                  // --replay FILE: scripted play at fixed 1/60 s steps.
    uint64_t frames = 0;                 // --frames N: stop (save, exit 0) after N frames (0: no limit).
    std::string screenshot;              // --screenshot PATH: PNG of the last frame on exit.
    std::string stats_out;               // --stats-out FILE: CSV, one row per frame.
    int view_radius = 8;                 // --view-radius R (chunks): full detail.
    int64_t view_distance = 2048;        // --view-distance BLOCKS: coarse levels beyond (0: none).
    double fly_speed = 10.0;             // --fly-speed B: blocks per second in fly mode.
    std::string device = "auto";         // --device auto|cpu|gpu|N.
    bool validation = false;             // --validation: exit 1 if the layer reports errors.
    bool headless = false;               // --headless: no window (replays only): frames are traced
                                         // at --size into memory (a GPU host without a display).
};

// Parses argv[1..]. Error: one line naming the bad argument (the caller prints usage, exits 2).
vx::Result<Options> parse_options(const std::vector<std::string>& args);
// The files a scripted run will write (--screenshot, --stats-out and the replay's screenshots):
// a folder, or a folder that does not exist, fails here, before the world opens, not at the end.
vx::Status check_outputs(const Options& options, const std::vector<ReplayCommand>& replay);
// The default world path: $XDG_DATA_HOME/vx/worlds/default.sqlite (fallback ~/.local/share).
std::string default_world_path();
// The folder to make before a SQLite world at `world` opens (its parent), or "" for a
// PostgreSQL URI (postgresql://host/db once made a folder "postgresql:/host" in the current one).
std::string world_folder(const std::string& world);
// Usage text for --help and errors.
const char* usage();

} // namespace sandbox
