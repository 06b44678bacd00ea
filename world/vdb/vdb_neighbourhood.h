#pragma once
// The voxel values around one block (the index bounding box of its cell, grown to whole voxels),
// fetched once so that many trilinear samples read local memory instead of walking the tree
// (vx_vdb internal; no OpenVDB types). Not thread-safe; one per importer.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace vx::vdb::detail {

struct Neighbourhood {
    glm::ivec3 lo{0};  // Index coordinates of values[0].
    glm::ivec3 dim{0}; // Voxels per axis, >= 2.
    std::vector<double> values;
    double min = 0, max = 0;

    double at(int x, int y, int z) const { return values[size_t(x + dim.x * (y + dim.y * z))]; }

    // Reads the dim.x * dim.y * dim.z voxels from `origin` through get(x, y, z) (index coordinates).
    template <class Get> void fetch(glm::ivec3 origin, glm::ivec3 size, Get&& get) {
        lo = origin;
        dim = size;
        values.resize(size_t(dim.x) * dim.y * dim.z);
        min = std::numeric_limits<double>::infinity();
        max = -min;
        size_t i = 0;
        for (int z = 0; z < dim.z; ++z)
            for (int y = 0; y < dim.y; ++y)
                for (int x = 0; x < dim.x; ++x) {
                    const double v = get(lo.x + x, lo.y + y, lo.z + z);
                    values[i++] = v;
                    min = std::min(min, v);
                    max = std::max(max, v);
                }
    }

    // Value of the voxel nearest to continuous index position p (box reconstruction).
    double nearest(const glm::dvec3& p) const {
        const glm::ivec3 i = glm::clamp(glm::ivec3(glm::floor(p + 0.5)) - lo, glm::ivec3(0), dim - 1);
        return at(i.x, i.y, i.z);
    }

    // Trilinear value at continuous index position p (p - lo must lie in [0, dim - 1]).
    double sample(const glm::dvec3& p) const {
        const glm::dvec3 q = p - glm::dvec3(lo);
        const glm::ivec3 i = glm::clamp(glm::ivec3(glm::floor(q)), glm::ivec3(0), dim - 2);
        const glm::dvec3 f = q - glm::dvec3(i);
        double c[2][2];
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 2; ++y)
                c[z][y] = at(i.x, i.y + y, i.z + z) * (1 - f.x) + at(i.x + 1, i.y + y, i.z + z) * f.x;
        const double c0 = c[0][0] * (1 - f.y) + c[0][1] * f.y, c1 = c[1][0] * (1 - f.y) + c[1][1] * f.y;
        return c0 * (1 - f.z) + c1 * f.z;
    }
};

} // namespace vx::vdb::detail
