#include "world/block_registry_text.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace vx::world {

namespace {

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", double(v));
    return text;
}

std::string triple(const glm::vec3& v) { return number(v.x) + " " + number(v.y) + " " + number(v.z); }

std::vector<std::string_view> split(std::string_view s, char by) {
    std::vector<std::string_view> out;
    size_t start = 0;
    for (size_t at; (at = s.find(by, start)) != std::string_view::npos; start = at + 1)
        out.push_back(s.substr(start, at - start));
    out.push_back(s.substr(start));
    return out;
}

// Exactly `n` finite floats separated by single spaces.
bool parse_floats(std::string_view s, float* out, int n) {
    const std::vector<std::string_view> parts = split(s, ' ');
    if (int(parts.size()) != n)
        return false;
    for (int i = 0; i < n; ++i) {
        const std::string part(parts[size_t(i)]);
        char* end = nullptr;
        out[i] = std::strtof(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(out[i]))
            return false;
    }
    return true;
}

} // namespace

std::string registry_to_text(const BlockRegistry& registry) {
    std::string out;
    for (size_t id = 1; id < registry.size(); ++id) {
        if (registry.contains(BlockId(id))) {
            const BlockInfo b = registry.info(BlockId(id));
            out += b.name + "\t" + triple(b.albedo) + "\t" + number(b.reflectivity) + "\t" + triple(b.emission) +
                   "\t" + (b.opaque ? "1" : "0");
        }
        out += "\n";
    }
    return out;
}

std::string registry_names_text(const BlockRegistry& registry) {
    std::string out;
    for (size_t id = 1; id < registry.size(); ++id)
        out += registry.info(BlockId(id)).name + "\n";
    return out;
}

Result<BlockRegistry> registry_from_text(std::string_view text) {
    BlockRegistry registry;
    std::vector<std::string_view> lines = split(text, '\n');
    if (!lines.empty() && lines.back().empty())
        lines.pop_back(); // The last line's newline.
    if (lines.size() > 0xFFFF)
        return Error{"block table: " + std::to_string(lines.size()) + " ids, more than 65535"};
    for (size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].empty())
            continue; // An id not registered.
        const std::vector<std::string_view> f = split(lines[i], '\t');
        BlockInfo b;
        float refl = 0.f;
        if (f.size() != 5 || !parse_floats(f[1], &b.albedo.x, 3) || !parse_floats(f[2], &refl, 1) ||
            !parse_floats(f[3], &b.emission.x, 3) || (f[4] != "0" && f[4] != "1"))
            return Error{"block table line " + std::to_string(i + 1) +
                         ": not 'name<TAB>r g b<TAB>reflectivity<TAB>r g b<TAB>0|1'"};
        b.name = std::string(f[0]);
        b.reflectivity = refl;
        b.opaque = f[4] == "1";
        if (Status s = registry.set(BlockId(i + 1), std::move(b)); !s)
            return Error{"block table line " + std::to_string(i + 1) + ": " + s.error()};
    }
    return registry;
}

} // namespace vx::world
