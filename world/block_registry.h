#pragma once
// Block types: ids and their materials. Id 0 is always air.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "world/base/result.h"

namespace vx::world {

using BlockId = uint16_t;
inline constexpr BlockId kAir = 0;

struct BlockInfo {
    std::string name;
    // Linear RGB, 0..1. Of a see-through block (opaque false): what one block's length of it
    // passes; d blocks of path pass albedo^d (Beer-Lambert; water 0.77, 0.95, 0.99).
    glm::vec3 albedo{0.8f};
    // Fraction of light mirrored, 0..1. Of a see-through block (opaque false): at normal incidence,
    // more at grazing angles as the Fresnel equations say (water 0.02, glass 0.04; 0: it only
    // tints), and the index of refraction the view bends by, ((n - 1) / (n + 1))^2 = reflectivity.
    float reflectivity = 0.f;
    glm::vec3 emission{0.f};  // Linear RGB radiance, >= 0.
    bool opaque = true;       // Opaque blocks hide the faces of blocks behind them.
};

// Maps block ids to materials. Ids not registered mesh like opaque blocks and render with a
// colour derived from the id, so worlds made elsewhere (raw volumes, VDB) always work.
// Not thread-safe for writes; concurrent reads are safe.
class BlockRegistry {
public:
    BlockRegistry(); // Registers air (id 0).

    // The default palette: air, stone, dirt, grass, sand, water (transparent), glass
    // (transparent), mirror (reflective), lamp (emissive), snow, wood, leaves, glazed (a quarter
    // reflective, as the thesis's blocks).
    static const BlockRegistry& default_registry();

    // Adds a block with the next free id. Fails on an empty or duplicate name, a material out
    // of the ranges BlockInfo documents (material_problem) or when full.
    Result<BlockId> add(BlockInfo info);
    // Sets the info of a given id (extending the table), for loading registries from files.
    // Fails as add() does.
    Status set(BlockId id, BlockInfo info);

    size_t size() const { return m_blocks.size(); }
    bool contains(BlockId id) const { return id < m_blocks.size() && !m_blocks[id].name.empty(); }
    // The info of `id`; an unregistered id gets a generated opaque material.
    BlockInfo info(BlockId id) const;
    // Constant time on average (a name index), so a table of 65535 types loads in linear time.
    std::optional<BlockId> find(std::string_view name) const;

    // Opacity for meshing; air is not opaque, unknown ids are.
    bool is_opaque(BlockId id) const { return id == kAir ? false : (id < m_opaque.size() ? m_opaque[id] : true); }

private:
    std::vector<BlockInfo> m_blocks;
    std::vector<uint8_t> m_opaque;
    std::unordered_map<std::string, BlockId> m_by_name;
};

// Why `b`'s material is outside the ranges BlockInfo documents (albedo and reflectivity 0..1,
// emission finite and >= 0, nothing NaN), or ok: every way a table is filled (a game's types,
// a store's text, a VDB file's metadata) is checked here, where the value is received.
Status material_problem(const BlockInfo& b);

// A stable, distinct colour for ids without a registered material (golden-ratio hue walk).
glm::vec3 fallback_albedo(BlockId id);

} // namespace vx::world
