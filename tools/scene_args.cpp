#include "scene_args.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <utility>

#include "cli_common.h"

namespace vx::tools {
namespace {

// "-12.375" -> block -13, frac 0.625. Integer part by strtoll (exact), fraction by strtod.
std::optional<std::pair<int64_t, double>> parse_coord(const std::string& t) {
    if (t.empty() || t.find_first_of("eExXpP") != std::string::npos)
        return std::nullopt;
    const bool neg = t[0] == '-';
    const size_t dot = t.find('.');
    const std::string ip = t.substr(0, dot), fp = dot == std::string::npos ? "" : t.substr(dot + 1);
    if (fp.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    errno = 0;
    char* end = nullptr;
    const bool int_empty = ip.empty() || ip == "-" || ip == "+";
    const long long i = int_empty ? 0 : std::strtoll(ip.c_str(), &end, 10);
    if (errno != 0 || (!int_empty && *end != '\0') || (int_empty && fp.empty()))
        return std::nullopt;
    const double f = fp.empty() ? 0.0 : std::strtod(("0." + fp).c_str(), nullptr);
    if (f == 0.0)
        return std::pair<int64_t, double>{i, 0.0};
    // Negative: -12.375 = -13 + 0.625.
    return neg ? std::pair<int64_t, double>{i - 1, 1.0 - f} : std::pair<int64_t, double>{i, f};
}

} // namespace

std::optional<WorldPos> parse_world_pos(const std::string& s) {
    const auto parts = split_commas(s);
    if (parts.size() != 3)
        return std::nullopt;
    WorldPos p;
    for (int i = 0; i < 3; ++i) {
        const auto c = parse_coord(parts[i]);
        if (!c || !world::in_world(c->first))
            return std::nullopt;
        p.block[i] = c->first;
        p.frac[i] = c->second;
    }
    return p;
}

glm::dvec3 world_delta(const WorldPos& a, const WorldPos& b) {
    return glm::dvec3(a.block - b.block) + (a.frac - b.frac);
}

Result<engine::SceneLoadInfo> scene_load_info(const SceneArgs& a) {
    const int sources = int(!a.world_path.empty()) + int(a.seed.has_value()) + int(!a.scene.empty()) + int(!a.raw.empty());
    if (sources != 1)
        return Error{"name exactly one scene: --world PATH, --seed N, --scene seed or --raw FILE --dims X,Y,Z"};
    if (!a.scene.empty() && a.scene != "seed")
        return Error{"unknown scene '" + a.scene + "' (known: seed)"};
    if (!a.raw.empty() && a.dims.empty())
        return Error{"--raw needs --dims X,Y,Z"};
    if (!a.lod.empty() && !a.view_distance)
        return Error{"--lod needs --view-distance BLOCKS"};
    // 0 would mean "none" to the engine, and a negative one was taken for "not given".
    if (a.view_distance && *a.view_distance < 1)
        return Error{"--view-distance must be 1..16384 blocks, got " + std::to_string(*a.view_distance)};
    engine::SceneLoadInfo info;
    info.view_distance = a.view_distance.value_or(0);
    info.lod = a.lod != "off";
    info.lod_ring = a.lod_ring;
    info.radius = a.radius;
    info.vradius = a.vradius;
    info.eye = a.eye;
    if (!a.world_path.empty()) {
        info.kind = engine::SceneKind::StoredWorld;
        info.world_path = a.world_path;
    } else if (a.seed) {
        info.kind = engine::SceneKind::Terrain;
        info.seed = *a.seed;
    } else if (!a.scene.empty()) {
        info.kind = engine::SceneKind::SeedScene;
        info.seed_block = a.scene_block;
    } else {
        info.kind = engine::SceneKind::RawVolume;
        info.raw_path = a.raw;
        const auto dims = parse_i64vec3(a.dims);
        if (!dims)
            return Error{"--dims must be X,Y,Z (integers), got '" + a.dims + "'"};
        const auto origin = parse_i64vec3(a.origin);
        if (!origin)
            return Error{"--origin must be X,Y,Z (integers), got '" + a.origin + "'"};
        info.raw = {*dims, a.type == "u16" ? world::RawType::U16 : world::RawType::U8, *origin};
    }
    return info;
}

} // namespace vx::tools
