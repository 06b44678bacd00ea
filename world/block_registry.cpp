#include "world/block_registry.h"

#include <cmath>
#include <cstdio>

namespace vx::world {

BlockRegistry::BlockRegistry() {
    BlockInfo air;
    air.name = "air";
    air.albedo = glm::vec3(0.f);
    air.opaque = false;
    m_blocks.push_back(air);
    m_opaque.push_back(0);
    m_by_name.emplace(m_blocks[0].name, kAir);
}

const BlockRegistry& BlockRegistry::default_registry() {
    static const BlockRegistry registry = [] {
        BlockRegistry r;
        auto add = [&r](const char* name, glm::vec3 albedo, float refl, glm::vec3 emit, bool opaque) {
            BlockInfo b;
            b.name = name;
            b.albedo = albedo;
            b.reflectivity = refl;
            b.emission = emit;
            b.opaque = opaque;
            VX_ASSERT(r.add(b).ok());
        };
        add("stone", {0.45f, 0.45f, 0.47f}, 0.f, glm::vec3(0.f), true);
        add("dirt", {0.42f, 0.29f, 0.18f}, 0.f, glm::vec3(0.f), true);
        add("grass", {0.30f, 0.55f, 0.20f}, 0.f, glm::vec3(0.f), true);
        add("sand", {0.86f, 0.80f, 0.58f}, 0.f, glm::vec3(0.f), true);
        // See-through blocks' reflectivity is their reflectance at normal incidence (BlockInfo):
        // water's and glass's from their indices of refraction, 1.33 and 1.5. Their albedo is what
        // one block (a metre) of them passes: water's is pure water's absorption (Pope & Fry 1997)
        // at the sRGB primaries' dominant wavelengths, 612, 549 and 465 nm, so a pond's floor
        // fades from sand to blue with depth.
        add("water", {0.77f, 0.95f, 0.99f}, 0.02f, glm::vec3(0.f), false);
        add("glass", {0.85f, 0.90f, 0.95f}, 0.04f, glm::vec3(0.f), false);
        add("mirror", {0.90f, 0.90f, 0.90f}, 0.9f, glm::vec3(0.f), true);
        add("lamp", {1.0f, 0.9f, 0.7f}, 0.f, glm::vec3(4.f, 3.6f, 2.8f), true);
        add("snow", {0.95f, 0.95f, 0.97f}, 0.f, glm::vec3(0.f), true);
        add("wood", {0.50f, 0.36f, 0.20f}, 0.f, glm::vec3(0.f), true);
        add("leaves", {0.20f, 0.45f, 0.15f}, 0.f, glm::vec3(0.f), true);
        // Glazed tile mirrors a quarter of the light, as every block of the thesis's scene did (its
        // hit shader mixed a hit's own light and the reflected ray's 3:1): Table 6.3 like for like.
        add("glazed", {0.25f, 0.55f, 0.30f}, 0.25f, glm::vec3(0.f), true);
        return r;
    }();
    return registry;
}

Result<BlockId> BlockRegistry::add(BlockInfo info) {
    if (m_blocks.size() > 0xFFFF)
        return Error{"block registry is full (65536 ids)"};
    const BlockId id = BlockId(m_blocks.size());
    Status s = set(id, std::move(info));
    if (!s)
        return Error{s.error()};
    return id;
}

Status BlockRegistry::set(BlockId id, BlockInfo info) {
    if (id == kAir)
        return Error{"block id 0 is reserved for air"};
    if (info.name.empty())
        return Error{"block name is empty"};
    // Stores record the names one per line ("blocks" meta): a newline would let two different
    // lists read the same.
    for (const char ch : info.name)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
            return Error{"block name holds a control character (a newline, a tab...): names are stored one per line"};
    if (auto existing = find(info.name); existing && *existing != id)
        return Error{"duplicate block name '" + info.name + "'"};
    if (Status s = material_problem(info); !s)
        return s;
    if (id >= m_blocks.size()) {
        m_blocks.resize(size_t(id) + 1);
        m_opaque.resize(size_t(id) + 1, 1);
    }
    m_opaque[id] = info.opaque ? 1 : 0;
    if (!m_blocks[id].name.empty())
        m_by_name.erase(m_blocks[id].name); // Renamed in place.
    m_by_name[info.name] = id;
    m_blocks[id] = std::move(info);
    return {};
}

BlockInfo BlockRegistry::info(BlockId id) const {
    if (contains(id))
        return m_blocks[id];
    BlockInfo b;
    b.name = "block_" + std::to_string(id);
    b.albedo = fallback_albedo(id);
    return b;
}

std::optional<BlockId> BlockRegistry::find(std::string_view name) const {
    const auto it = m_by_name.find(std::string(name));
    if (it == m_by_name.end())
        return std::nullopt;
    return it->second;
}

namespace {

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", double(v));
    return text;
}

std::string triple(glm::vec3 v) { return number(v.x) + ", " + number(v.y) + ", " + number(v.z); }

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

} // namespace

Status material_problem(const BlockInfo& b) {
    if (!finite(b.albedo) || glm::any(glm::lessThan(b.albedo, glm::vec3(0.f))) ||
        glm::any(glm::greaterThan(b.albedo, glm::vec3(1.f))))
        return Error{"albedo must be 0..1 per channel, got " + triple(b.albedo)};
    if (!std::isfinite(b.reflectivity) || b.reflectivity < 0.f || b.reflectivity > 1.f)
        return Error{"reflectivity must be 0..1, got " + number(b.reflectivity)};
    if (!finite(b.emission) || glm::any(glm::lessThan(b.emission, glm::vec3(0.f))))
        return Error{"emission must be finite and >= 0 per channel, got " + triple(b.emission)};
    return {};
}

glm::vec3 fallback_albedo(BlockId id) {
    const float h = std::fmod(float(id) * 0.61803398875f, 1.f) * 6.f;
    const float x = 1.f - std::fabs(std::fmod(h, 2.f) - 1.f);
    glm::vec3 c = h < 1 ? glm::vec3(1, x, 0)
                : h < 2 ? glm::vec3(x, 1, 0)
                : h < 3 ? glm::vec3(0, 1, x)
                : h < 4 ? glm::vec3(0, x, 1)
                : h < 5 ? glm::vec3(x, 0, 1)
                        : glm::vec3(1, 0, x);
    return 0.25f + 0.6f * c;
}

} // namespace vx::world
