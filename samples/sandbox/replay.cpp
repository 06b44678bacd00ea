#include "replay.h"

#include <charconv>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <vx/vx.h>

namespace sandbox {
namespace {

using Kind = ReplayCommand::Kind;

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r'))
            ++i;
        size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r')
            ++j;
        if (j > i)
            words.push_back(line.substr(i, j - i));
        i = j;
    }
    return words;
}

bool parse_u64(std::string_view s, uint64_t& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
}

bool parse_int(std::string_view s, int& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
}

bool parse_double(std::string_view s, double& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size() && std::isfinite(out);
}

bool one_of(std::string_view s, std::initializer_list<std::string_view> names) {
    for (std::string_view n : names)
        if (s == n)
            return true;
    return false;
}

// Fills `c` from the words after the frame number; returns why it does not parse, or "".
std::string parse_command(const std::vector<std::string_view>& w, ReplayCommand& c) {
    const std::string_view cmd = w[1];
    const size_t args = w.size() - 2;
    auto want = [&](size_t n) { return args == n ? std::string() : std::string(cmd) + " takes " + std::to_string(n) + " argument(s)"; };
    if (cmd == "pose") {
        c.kind = Kind::Pose;
        if (auto e = want(5); !e.empty())
            return e;
        for (int i = 0; i < 5; ++i)
            if (!parse_double(w[2 + i], c.pose[i]))
                return "pose wants 5 numbers (x y z yaw pitch)";
        // The engine refuses a viewer outside the streamed world: the game went on where it was.
        for (int i = 0; i < 3; ++i)
            if (!(std::floor(c.pose[i]) >= -double(vx::kStreamedWorldExtent) &&
                  std::floor(c.pose[i]) <= double(vx::kStreamedWorldExtent - 1)))
                return "pose: x, y and z must lie inside the streamed world (|coordinate| < 2^36 - 2^17)";
        for (int i = 3; i < 5; ++i)
            if (!(std::abs(c.pose[i]) <= 1e6))
                return "pose: yaw and pitch are degrees, at most 1e6 in size";
        return "";
    }
    if (cmd == "key") {
        c.kind = Kind::Key;
        if (auto e = want(2); !e.empty())
            return e;
        if (!is_replay_key(w[2]))
            return "unknown key '" + std::string(w[2]) + "' (w a s d space shift f escape f1 f3)";
        if (!one_of(w[3], {"down", "up"}))
            return "key state must be down or up";
        c.name = w[2];
        c.down = w[3] == "down";
        return "";
    }
    if (cmd == "click") {
        c.kind = Kind::Click;
        if (auto e = want(1); !e.empty())
            return e;
        if (!one_of(w[2], {"left", "right", "middle"}))
            return "click wants left, right or middle";
        c.name = w[2];
        return "";
    }
    if (cmd == "select" || cmd == "block") {
        c.kind = cmd == "select" ? Kind::Select : Kind::Block;
        if (auto e = want(1); !e.empty())
            return e;
        if (!parse_int(w[2], c.value))
            return std::string(cmd) + " wants an integer";
        if (c.kind == Kind::Select && (c.value < 1 || c.value > 9))
            return "select wants a hotbar slot 1..9";
        if (c.kind == Kind::Block && (c.value < 1 || c.value > 65535))
            return "block wants an id 1..65535";
        return "";
    }
    if (cmd == "toggle") {
        c.kind = Kind::Toggle;
        if (auto e = want(1); !e.empty())
            return e;
        if (!one_of(w[2], {"shadows", "reflections", "denoise", "raster", "walk"}))
            return "toggle wants shadows, reflections, denoise, raster or walk";
        c.name = w[2];
        return "";
    }
    if (cmd == "wait-loaded" || cmd == "quit") {
        c.kind = cmd == "quit" ? Kind::Quit : Kind::WaitLoaded;
        return want(0);
    }
    if (cmd == "screenshot") {
        c.kind = Kind::Screenshot;
        if (auto e = want(1); !e.empty())
            return e;
        c.name = w[2];
        return "";
    }
    return "unknown command '" + std::string(cmd) + "'";
}

} // namespace

bool is_replay_key(std::string_view name) {
    return one_of(name, {"w", "a", "s", "d", "space", "shift", "f", "escape", "f1", "f3"});
}

vx::Result<std::vector<ReplayCommand>> parse_replay(std::string_view text) {
    std::vector<ReplayCommand> out;
    int line_no = 0;
    uint64_t last_frame = 0;
    while (!text.empty()) {
        const size_t nl = text.find('\n');
        std::string_view line = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
        ++line_no;
        const std::string_view code = line.substr(0, line.find('#'));
        const auto words = split_words(code);
        if (words.empty())
            continue;
        ReplayCommand c;
        c.line = line_no;
        std::string why;
        if (words.size() < 2 || !parse_u64(words[0], c.frame))
            why = "expected FRAME COMMAND ARGS...";
        else if (c.frame < last_frame)
            why = "frame " + std::to_string(c.frame) + " is before frame " + std::to_string(last_frame);
        else
            why = parse_command(words, c);
        if (!why.empty())
            return vx::Error{"replay line " + std::to_string(line_no) + ": " + why + ": " + std::string(line)};
        last_frame = c.frame;
        out.push_back(std::move(c));
    }
    return out;
}

vx::Result<std::vector<ReplayCommand>> load_replay(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) // An ifstream opens a folder and reads nothing.
        return vx::Error{"cannot read replay " + path + ": it is a folder"};
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return vx::Error{"cannot read replay " + path};
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad())
        return vx::Error{"cannot read replay " + path + ": read error"};
    auto parsed = parse_replay(ss.str());
    if (!parsed)
        return vx::Error{path + ": " + parsed.error()};
    return parsed;
}

bool replay_quits(const std::vector<ReplayCommand>& replay) {
    return std::any_of(replay.begin(), replay.end(), [](const ReplayCommand& c) { return c.kind == Kind::Quit; });
}

} // namespace sandbox
