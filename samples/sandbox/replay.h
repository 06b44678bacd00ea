#pragma once
// Scripted play: a replay file is text, one command per line, `FRAME COMMAND ARGS...`, `#` starts
// a comment, frame numbers never decrease. The game runs each command at the start of its frame
// and advances in fixed steps of 1/60 s, so a replay gives the same world every time.
// Pure parsing: no window, no engine. Thread: any (plain values).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <vx/result.h>

namespace sandbox {

struct ReplayCommand {
    enum class Kind : uint8_t {
        Pose,       // Camera at world x y z (blocks), yaw and pitch (degrees).
        Key,        // Key `name` down (`down` true) or up.
        Click,      // Mouse button `name`: left, right or middle.
        Select,     // Hotbar slot `value` (1..9).
        Block,      // Select block id `value` directly.
        Toggle,     // `name`: shadows, reflections, denoise, raster or walk.
        WaitLoaded, // Hold the frame counter until everything in view is meshed.
        Screenshot, // Write the frame as PNG to `name`.
        Quit,       // Save, flush and exit 0.
    };
    uint64_t frame = 0;
    Kind kind = Kind::Quit;
    double pose[5] = {0, 0, 0, 0, 0}; // Pose: x y z yaw pitch.
    std::string name;                 // Key, Click, Toggle: the name; Screenshot: the path.
    bool down = false;                // Key.
    int value = 0;                    // Select, Block.
    int line = 0;                     // 1-based line in the file (for messages).
};

// Parses a whole replay. Error: "replay line N: <why>: <the line>" for the first bad line.
vx::Result<std::vector<ReplayCommand>> parse_replay(std::string_view text);
// Reads and parses a replay file. Error: unreadable file (a folder too) or a bad line (as above).
vx::Result<std::vector<ReplayCommand>> load_replay(const std::string& path);
// Whether the replay ends the game itself (a `quit` line). Without one, or --frames, a headless
// replay would run for ever: nobody can close a window that is not there.
bool replay_quits(const std::vector<ReplayCommand>& replay);

// Key names a replay may press: w a s d space shift f escape f1 f3 (escape, f1, f3 toggle the
// menu, help and stats on `down`, as the keys do).
bool is_replay_key(std::string_view name);

} // namespace sandbox
