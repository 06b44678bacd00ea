#pragma once
// The block lattice of a volume import in a grid's continuous index space (vx_vdb internal; no
// OpenVDB types). Block (bx, by, bz) is the world cell s * [b, b + 1) per axis (s = block size in
// world units); through the grid's linear index-to-world map that cell is a parallelepiped in
// index space (index coordinates name voxel centres, as in OpenVDB). Immutable once created:
// thread-safe.

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#include "world/base/result.h"

namespace vx::vdb::detail {

class BlockLattice {
public:
    BlockLattice() = default;

    // index_to_world: column k is the world vector of one index step along axis k; origin: the
    // world position of index (0, 0, 0); block_size in world units (finite, > 0). Fails on a
    // non-finite or degenerate map. Entries of the block-to-index map within 1e-9 (relative) of a
    // whole number are snapped to it, and its offset to a multiple of 1/2: representation noise
    // (0.4 / 0.1 is 4.000000000000001 in binary) must not move a block boundary off a voxel.
    static Result<BlockLattice> create(const glm::dmat3& index_to_world, const glm::dvec3& origin, double block_size);

    // Continuous block coordinates (block b's cell is [b, b + 1)) to index space, and back.
    glm::dvec3 index_of(const glm::dvec3& block) const { return m_g * block + m_c; }
    glm::dvec3 block_of(const glm::dvec3& index) const { return m_g_inv * (index - m_c); }

    // Index-space bounding box of block b's cell: [min, max] (closed).
    void cell_bounds(const glm::i64vec3& b, glm::dvec3& min, glm::dvec3& max) const;
    // Blocks (inclusive range) whose cells meet the index box [lo, hi]; conservative; clamped to
    // +-2^61 (so that a range size fits int64).
    void blocks_meeting(const glm::dvec3& lo, const glm::dvec3& hi, glm::i64vec3& out_lo, glm::i64vec3& out_hi) const;

    // Index units from a cell's centre to its farthest corner.
    double half_diagonal() const { return m_half_diagonal; }
    // Index-space map of one block: column k = index vector of one block step along world axis k.
    const glm::dmat3& index_per_block() const { return m_g; }

private:
    glm::dmat3 m_g{1.0}, m_g_inv{1.0};
    glm::dvec3 m_c{0.0};
    glm::dvec3 m_extent_lo{0.0}, m_extent_hi{1.0}; // Cell bounds relative to index_of(b).
    double m_half_diagonal = 0.0;
};

} // namespace vx::vdb::detail
