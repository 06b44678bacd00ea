#include "world/vdb/vdb_analytic.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <openvdb/openvdb.h>

#include "world/vdb/vdb_common.h"

namespace vx::vdb {
namespace {

double largest_voxel(const AnalyticVolume& v) {
    return std::max({glm::length(v.index_to_world[0]), glm::length(v.index_to_world[1]), glm::length(v.index_to_world[2])});
}

openvdb::math::Transform::Ptr make_transform(const AnalyticVolume& v, const openvdb::CoordBBox& box) {
    if (v.frustum) {
        const openvdb::BBoxd b(box.min().asVec3d(), box.max().asVec3d());
        return openvdb::math::Transform::createFrustumTransform(b, 0.5, 2.0, largest_voxel(v));
    }
    // OpenVDB multiplies row vectors: world = index * M, so row k is the image of index axis k.
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            m(k, j) = v.index_to_world[k][j];
    for (int j = 0; j < 3; ++j)
        m(3, j) = v.translation[j];
    return openvdb::math::Transform::createLinearTransform(m);
}

// Index box covering the shape's world bounds plus `margin` world units.
openvdb::CoordBBox index_box(const AnalyticVolume& v, double margin) {
    glm::dvec3 lo, hi;
    analytic_bounds(v, lo, hi);
    lo -= margin;
    hi += margin;
    const glm::dmat3 inv = glm::inverse(v.index_to_world);
    glm::dvec3 qlo(std::numeric_limits<double>::infinity()), qhi(-std::numeric_limits<double>::infinity());
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 w(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
        const glm::dvec3 q = inv * (w - v.translation);
        qlo = glm::min(qlo, q);
        qhi = glm::max(qhi, q);
    }
    return openvdb::CoordBBox(openvdb::Coord(int(std::floor(qlo.x)), int(std::floor(qlo.y)), int(std::floor(qlo.z))),
                              openvdb::Coord(int(std::ceil(qhi.x)), int(std::ceil(qhi.y)), int(std::ceil(qhi.z))));
}

Result<openvdb::FloatGrid::Ptr> make_grid(const AnalyticVolume& v) {
    const double voxel = largest_voxel(v);
    const double bg = v.level_set ? v.band_voxels * voxel : 0.0;
    const openvdb::CoordBBox box = index_box(v, (v.level_set ? bg : voxel) + 2 * voxel);
    if (double(box.volume()) > double(1 << 26))
        return Error{"analytic volume '" + v.name + "' would cover " + std::to_string(box.volume()) + " voxels"};
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(float(bg));
    grid->setName(v.name);
    grid->setGridClass(v.level_set ? openvdb::GRID_LEVEL_SET : openvdb::GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    for (int z = box.min().z(); z <= box.max().z(); ++z)
        for (int y = box.min().y(); y <= box.max().y(); ++y)
            for (int x = box.min().x(); x <= box.max().x(); ++x) {
                const glm::dvec3 w = v.index_to_world * glm::dvec3(x, y, z) + v.translation;
                const double d = analytic_distance(v, w);
                const openvdb::Coord c(x, y, z);
                if (v.level_set) {
                    if (std::abs(d) < bg)
                        acc.setValueOn(c, float(d));
                    else if (d < 0)
                        acc.setValueOff(c, float(-bg)); // Interior: inactive -background.
                } else {
                    const double density = std::clamp(0.5 - 0.5 * d / voxel, 0.0, 1.0);
                    if (density > 0)
                        acc.setValueOn(c, float(density));
                }
            }
    grid->tree().prune();
    grid->setTransform(make_transform(v, box));
    return grid;
}

Status write_impl(const std::string& path, std::span<const AnalyticVolume> volumes) {
    openvdb::initialize();
    openvdb::GridPtrVec grids;
    for (const AnalyticVolume& v : volumes) {
        Result<openvdb::FloatGrid::Ptr> g = make_grid(v);
        if (!g)
            return Error{g.error()};
        grids.push_back(*g);
    }
    openvdb::io::File file(path);
    file.write(grids);
    file.close();
    return {};
}

} // namespace

double analytic_distance(const AnalyticVolume& v, const glm::dvec3& p) {
    const glm::dvec3 q = glm::transpose(v.rotation) * (p - v.centre); // Shape frame.
    const glm::dvec3& a = v.half_extent;
    if (v.shape == AnalyticShape::Box) {
        const glm::dvec3 e = glm::abs(q) - a;
        return glm::length(glm::max(e, 0.0)) + std::min(std::max({e.x, e.y, e.z}), 0.0);
    }
    return (glm::length(q / a) - 1.0) * std::min({a.x, a.y, a.z});
}

double analytic_volume(const AnalyticVolume& v) {
    const glm::dvec3& a = v.half_extent;
    return v.shape == AnalyticShape::Box ? 8.0 * a.x * a.y * a.z : 4.0 / 3.0 * M_PI * a.x * a.y * a.z;
}

void analytic_bounds(const AnalyticVolume& v, glm::dvec3& min, glm::dvec3& max) {
    // Half extent along world axis j: box sum_k |R_jk| a_k; ellipsoid sqrt(sum_k (R_jk a_k)^2).
    glm::dvec3 h(0.0);
    for (int j = 0; j < 3; ++j) {
        double box = 0, ell = 0;
        for (int k = 0; k < 3; ++k) {
            const double r = v.rotation[k][j] * v.half_extent[k];
            box += std::abs(r);
            ell += r * r;
        }
        h[j] = v.shape == AnalyticShape::Box ? box : std::sqrt(ell);
    }
    min = v.centre - h;
    max = v.centre + h;
}

Status write_analytic_vdb(const std::string& path, const AnalyticVolume& v) {
    return write_analytic_vdb(path, std::span<const AnalyticVolume>(&v, 1));
}

Status write_analytic_vdb(const std::string& path, std::span<const AnalyticVolume> volumes) {
    try {
        Status s;
        detail::run_in_calling_thread([&] { s = write_impl(path, volumes); });
        return s;
    } catch (const std::exception& e) {
        return detail::make_error("cannot write '" + path + "'", e.what());
    } catch (...) {
        return detail::make_error("cannot write '" + path + "'", "unknown error");
    }
}

glm::dmat3 axis_rotation(double degrees, glm::dvec3 axis) {
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(axis)));
}

} // namespace vx::vdb
