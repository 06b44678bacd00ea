#include "options.h"

#include <charconv>
#include <cstdlib>
#include <filesystem>

namespace sandbox {
namespace {

template <class T> bool parse_number(const std::string& s, T& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
}

bool parse_size(const std::string& s, uint32_t& w, uint32_t& h) {
    const size_t x = s.find('x');
    return x != std::string::npos && parse_number(s.substr(0, x), w) && parse_number(s.substr(x + 1), h) &&
           w >= 1 && h >= 1 && w <= 16384 && h <= 16384;
}

} // namespace

const char* usage() {
    return "usage: vx_sandbox [--world PATH] [--seed S] [--vdb FILE [--read-only]] [--size WxH] [--fullscreen]\n"
           "                  [--no-vsync] [--view-radius R] [--view-distance BLOCKS] [--fly-speed B] [--device auto|cpu|gpu|N]\n"
           "                  [--validation] [--replay FILE [--frames N] [--screenshot PATH]]\n"
           "                  [--stats-out FILE.csv] [--headless (with --replay: no window)]\n";
}

vx::Status check_outputs(const Options& options, const std::vector<ReplayCommand>& replay) {
    namespace fs = std::filesystem;
    std::vector<std::pair<const char*, std::string>> outputs;
    if (!options.screenshot.empty())
        outputs.emplace_back("--screenshot", options.screenshot);
    if (!options.stats_out.empty())
        outputs.emplace_back("--stats-out", options.stats_out);
    for (const ReplayCommand& c : replay)
        if (c.kind == ReplayCommand::Kind::Screenshot)
            outputs.emplace_back("the replay's screenshot", c.name);
    for (const auto& [what, path] : outputs) {
        std::error_code ec;
        const fs::path p(path);
        if (fs::is_directory(p, ec))
            return vx::Error{std::string(what) + " '" + path + "' is a folder, not a file"};
        if (!fs::is_directory(p.has_parent_path() ? p.parent_path() : fs::path("."), ec))
            return vx::Error{std::string(what) + " '" + path + "': its folder does not exist"};
    }
    return {};
}

std::string default_world_path() {
    std::filesystem::path base = ".";
    if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && *xdg)
        base = xdg;
    else if (const char* home = std::getenv("HOME"); home && *home)
        base = std::filesystem::path(home) / ".local" / "share";
    return (base / "vx" / "worlds" / "default.sqlite").string();
}

std::string world_folder(const std::string& world) {
    for (const char* scheme : {"postgresql://", "postgres://"})
        if (world.rfind(scheme, 0) == 0)
            return "";
    return std::filesystem::path(world).parent_path().string();
}

vx::Result<Options> parse_options(const std::vector<std::string>& args) {
    Options o;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool has_value = i + 1 < args.size();
        auto value = [&]() -> const std::string& { return args[++i]; };
        auto bad = [&](const char* why) {
            std::string msg = "vx_sandbox: "; // Appended piecewise: g++ 12 warns (-Wrestrict) on a + chain here.
            msg.append(a).append(": ").append(why);
            return vx::Error{std::move(msg)};
        };
        if (a == "--fullscreen")
            o.fullscreen = true;
        else if (a == "--no-vsync")
            o.vsync = false;
        else if (a == "--validation")
            o.validation = true;
        else if (a == "--headless")
            o.headless = true;
        else if (a == "--read-only")
            o.read_only = true;
        else if (!has_value)
            return bad(a.rfind("--", 0) == 0 ? "unknown option or missing value" : "unexpected argument");
        else if (a == "--size") {
            if (!parse_size(value(), o.width, o.height))
                return bad("wants WxH, e.g. 1280x720");
        } else if (a == "--world")
            o.world = value();
        else if (a == "--seed") {
            if (!parse_number(value(), o.seed))
                return bad("wants an unsigned integer");
        } else if (a == "--vdb")
            o.vdb = value();
        else if (a == "--replay")
            o.replay = value();
        else if (a == "--frames") {
            if (!parse_number(value(), o.frames))
                return bad("wants a frame count");
        } else if (a == "--screenshot")
            o.screenshot = value();
        else if (a == "--stats-out")
            o.stats_out = value();
        else if (a == "--view-radius") {
            if (!parse_number(value(), o.view_radius) || o.view_radius < 1 || o.view_radius > 64)
                return bad("wants 1..64 chunks");
        } else if (a == "--view-distance") {
            if (!parse_number(value(), o.view_distance) || o.view_distance < 0 || o.view_distance > 65536)
                return bad("wants 0..65536 blocks (0: full detail only)");
        } else if (a == "--fly-speed") {
            if (!parse_number(value(), o.fly_speed) || !(o.fly_speed > 0) || o.fly_speed > 10000)
                return bad("wants blocks per second in (0, 10000]");
        } else if (a == "--device")
            o.device = value();
        else
            return bad("unknown option");
    }
    if (!o.world.empty() && !o.vdb.empty())
        return vx::Error{"vx_sandbox: --world and --vdb exclude each other"};
    if (o.read_only && o.vdb.empty())
        return vx::Error{"vx_sandbox: --read-only goes with --vdb (a SQLite world always keeps its edits)"};
    if (o.world.empty() && o.vdb.empty())
        o.world = default_world_path();
    if (o.headless && o.replay.empty())
        return vx::Error{"vx_sandbox: --headless needs --replay (nobody can play without a window)"};
    return o;
}

} // namespace sandbox
