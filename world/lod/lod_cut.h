#pragma once
// Which level draws where (issue 16): the levels of detail around a viewer as a cut through the
// octree of levels. Every level k has a box B_k of level-k chunks around the viewer; level 0's
// box is the streamer's (view radius, vertical radius), each coarser level's reaches `ring` of its
// own chunks. The target cut starts at the roots (top-level chunks within the view distance) and
// replaces a chunk by its 8 children exactly when all 8 lie in the finer level's box.
//
// Why a cut: every point under a root is covered by exactly one chunk of a cut, so a renderer
// that draws a cut has no gap and no overlap by construction. The boxes nest (each box holds the
// parents of the finer box, enforced by raising `ring` and the vertical half-heights where
// needed), so the parent of any chunk a cut can hold is in its level's box: an engine that keeps
// the boxes' chunks ready can always coarsen, and refines only when all 8 children are ready
// (engine/lod_streamer.h). Holes can then only be roots not yet ready.
//
// Sizes: with ring R, level k >= 1 draws to about R * 32 * 2^k blocks from the viewer (R = 12:
// 768, 1,536, 3,072, 6,144 blocks for levels 1..4), and a cell at a level's outer edge subtends
// about 1 / (32 R) radians (R = 12: 0.15 degrees, 2.3 pixels of a 70-degree 1080p view).
//
// Coordinates: the viewer and distances in world block units; chunks as in lod_coords.h.
// Thread-safe: a LodView is an immutable value.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "world/lod/lod_coords.h"

namespace vx::world {

// The most blocks coarse levels may reach above and below the viewer (LodViewSettings::
// vertical_reach): the roots span 2 reach / chunk size + 1 chunks in every column, so a reach of
// a billion blocks (an eye far above the terrain) asked for billions of chunks.
inline constexpr int64_t kMaxLodVerticalReach = 65536;

struct LodViewSettings {
    int radius0 = 12;              // Level 0's box: chunks from the viewer's chunk, horizontally
    int vradius0 = 4;              // and vertically (the full-detail streamer's view radii).
    int ring = 12;                 // Coarse levels' box half-width, in that level's chunks (>= 1).
    int64_t vertical_reach = 256;  // Blocks above and below the viewer coarse levels reach (>= 0).
    int64_t view_distance = 2048;  // Blocks, horizontal, to the nearest point of a root chunk.
    int max_level = kMaxLodLevel;  // Coarsest level used (0: full detail only).
};

class LodView {
public:
    // `viewer` in world block units. Settings out of range are clamped (radii >= 0, ring >= 1).
    LodView(const glm::dvec3& viewer, const LodViewSettings& settings);

    // The coarsest level: the finest whose box reaches the view distance (0 when level 0's box
    // already does), at most settings.max_level.
    int top_level() const { return m_top; }
    // The viewer's chunk at `level` (level-0 chunk >> level, so the boxes nest).
    ChunkCoord center(int level) const { return m_center0 >> level; }
    // Half-widths of level k's box (k <= top_level()): horizontal and vertical, in level-k chunks.
    int half_width(int level) const { return m_half[size_t(level)]; }
    int half_height(int level) const { return m_half_v[size_t(level)]; }
    const LodViewSettings& settings() const { return m_settings; }

    // `c` lies in its level's box (levels above top_level() have none).
    bool in_box(LodCoord c) const;
    // The target cut replaces `c` by its children: level >= 1 and all 8 children in B_{level-1}.
    bool refines(LodCoord c) const;
    // Horizontal distance (blocks) from the viewer to the nearest point of `c`'s blocks.
    double distance(LodCoord c) const;
    // A root: a top-level chunk in its box within view_distance + extra blocks.
    bool is_root(LodCoord c, double extra = 0.0) const;

    // Roots within view_distance + extra, in no particular order (appended to `out`).
    void roots(std::vector<LodCoord>& out, double extra = 0.0) const;
    // The target cut: the chunks drawn when everything is ready, under the roots within the view
    // distance; chunks beyond it are left out (appended to `out`).
    void cut(std::vector<LodCoord>& out) const;
    // Every chunk an engine keeps ready: the coarse boxes' chunks (levels 1..top) under the
    // roots within view_distance + extra. Level 0 is the streamer's. Appended to `out`.
    void coarse_chunks(std::vector<LodCoord>& out, double extra = 0.0) const;

private:
    void cut_below(LodCoord c, std::vector<LodCoord>& out) const;

    LodViewSettings m_settings;
    glm::dvec3 m_viewer;
    ChunkCoord m_center0;
    int m_top = 0;
    std::array<int, kMaxLodLevel + 1> m_half{}, m_half_v{};
};

// Coarse chunks the level boxes of `settings` hold around a viewer (levels 1..top): what an
// engine's LOD streamer keeps (a node, and block data once loaded), and at most what one view's
// cut draws. Settings whose boxes hold more than kMaxLodBoxChunks are refused where they are
// received (the engine at create, `vx render` at load): lod_ring 64, vertical reach 65536 and view
// distance 65536 asked for 66 million, whose first update took 95 s and 7.5 GB.
inline constexpr uint64_t kMaxLodBoxChunks = uint64_t(1) << 20;
uint64_t lod_box_chunks(const LodViewSettings& settings);

} // namespace vx::world
