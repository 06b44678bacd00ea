#pragma once
// Analytic test volumes: a sphere, ellipsoid or box given in world space, written as an OpenVDB
// level set or fog grid with any linear transform (or a frustum one, which import refuses). The
// ground truth for import tests and the accuracy table; OpenVDB stays inside vdb_analytic.cpp.

#include <span>
#include <string>

#include <glm/glm.hpp>

#include "world/base/result.h"

namespace vx::vdb {

enum class AnalyticShape {
    Ellipsoid, // Semi-axes `half_extent` (equal: a sphere).
    Box,       // Half edges `half_extent`.
};

struct AnalyticVolume {
    std::string name = "shape";      // Grid name.
    AnalyticShape shape = AnalyticShape::Ellipsoid;
    bool level_set = true;           // Else a fog volume: density 1 inside, 0 outside, 0.5 on the surface.
    glm::dvec3 centre{0.0};          // World units.
    glm::dvec3 half_extent{1.0};     // World units, in the shape's own frame.
    glm::dmat3 rotation{1.0};        // Shape frame -> world (orthonormal).
    glm::dmat3 index_to_world{1.0};  // The grid's linear map: column k = world vector of one index step along k.
    glm::dvec3 translation{0.0};     // World position of index (0, 0, 0).
    bool frustum = false;            // Write a frustum transform instead of the linear one.
    double band_voxels = 3.0;        // Level set: half width of the narrow band, in largest voxel edges.
};

// The rotation by `degrees` about `axis` (any length), for AnalyticVolume::rotation and
// index_to_world. Thread-safe.
glm::dmat3 axis_rotation(double degrees, glm::dvec3 axis);

// Signed distance to the shape's surface at world point p (negative inside), world units: exact
// for boxes and spheres; for ellipsoids (|p / a| - 1) * min(a), negative exactly inside. Thread-safe.
double analytic_distance(const AnalyticVolume& v, const glm::dvec3& p);

// Volume of the shape, world units³. Thread-safe.
double analytic_volume(const AnalyticVolume& v);

// Axis-aligned world bounding box of the shape (exact). Thread-safe.
void analytic_bounds(const AnalyticVolume& v, glm::dvec3& min, glm::dvec3& max);

// Writes the shape as one float grid to `path` (replaced). Level set: distances clamped to the
// band (inactive +-background outside it, so the interior reads as inside); fog: a linear ramp
// over one largest voxel edge each side of the surface, active where positive. Fails when the
// shape covers more than 2^26 voxels. Runs in the calling thread. Thread-safe.
Status write_analytic_vdb(const std::string& path, const AnalyticVolume& v);
// The same with one grid per volume, in order (a multi-grid file). Thread-safe.
Status write_analytic_vdb(const std::string& path, std::span<const AnalyticVolume> volumes);

} // namespace vx::vdb
