#pragma once
// Whether two different transparent blocks touch anywhere among the drawn chunks: that decides
// each frame's pipeline variant (render/rt_pipeline.h). The probe for a coincident face
// (coincident_pass, shaders/shared/raygen_common.glsl) costs every ray ~7% on the NVIDIA driver
// where it is compiled in, even where it never runs (docs/render_report.md), so frames carry it
// only while such a pair exists. Inside a chunk mark_touching_faces (render/touching_faces.h)
// finds the pairs; across a border plane this compares the two chunks' border faces cell by cell,
// whatever their levels of detail: two different transparent blocks touch there exactly where
// both chunks have a face on the shared plane with different blocks (each chunk writes the faces
// of its own cells). Chunks of other levels across a plane are found as an octree's neighbours
// are (world/lod/lod_coords.h): their border lies on the plane and a coarse cell covers 2^(j-k)
// fine cells per axis. Main thread only (the renderer's).

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "render/touching_faces.h"
#include "world/lod/lod_coords.h"

namespace vx::render {

class TouchingPairs {
public:
    // Chunk c as it is now drawn (replacing what c had): `inside`, a pair within it; `border`, its
    // border faces (TouchingFaces). Links it with every chunk whose border faces meet its own.
    void set(world::LodCoord c, bool inside, BorderFaces border);
    void remove(world::LodCoord c); // No-op when absent.
    void clear();
    // Some pair exists: frames need the probing variant.
    bool any() const { return m_inside > 0 || m_pairs > 0; }
    size_t chunks_with_inside_pairs() const { return m_inside; }
    size_t border_pairs() const { return m_pairs; } // Pairs of chunks whose border faces meet.
    // The chunks held (those with a pair inside or a transparent border face), any order.
    std::vector<world::LodCoord> chunks() const;

private:
    struct Entry {
        bool inside = false;
        BorderFaces border;
        std::vector<world::LodCoord> partners;
    };
    // The held chunks with border faces on side `side` (BorderFaces' index) whose border plane is
    // `plane` (blocks along the side's axis) and whose square overlaps c's across it.
    std::vector<world::LodCoord> across(world::LodCoord c, int side) const;
    void link(world::LodCoord a, world::LodCoord b);

    std::unordered_map<world::LodCoord, Entry, world::LodCoordHash> m_chunks;
    std::array<uint32_t, world::kMaxLodLevel + 1> m_per_level{}; // Held chunks by level.
    size_t m_inside = 0, m_pairs = 0;
};

// Whether chunk a's faces on its side `side_a` and chunk b's on the opposite side (the same axis),
// lying on one plane, hold two different blocks over some cell. The chunks may be of different
// levels; a's and b's squares on the plane must overlap. Exposed for tests.
bool border_faces_meet(world::LodCoord a, const std::vector<world::BlockId>& faces_a, world::LodCoord b,
                       const std::vector<world::BlockId>& faces_b, int axis);

} // namespace vx::render
