// The GPU material table, with each see-through block's optics worked out once (material_table.h).
#include "render/material_table.h"

#include <algorithm>
#include <cmath>

namespace vx::render {

float refractive_index(float reflectivity) {
    const double s = std::sqrt(std::clamp(double(reflectivity), 0.0, 0.999));
    return float((1.0 + s) / (1.0 - s));
}

glm::vec3 absorption_coefficient(glm::vec3 albedo) {
    glm::vec3 sigma;
    for (int c = 0; c < 3; ++c) // -ln(1) is 0 exactly: a clear channel absorbs nothing however far.
        sigma[c] = float(-std::log(std::max(double(albedo[c]), double(kMinPassAlbedo))));
    return glm::max(sigma, glm::vec3(0.f)); // An albedo above 1 (not valid: material_problem) gains nothing.
}

gpu::Material gpu_material(const world::BlockInfo& info, bool opaque) {
    gpu::Material m{};
    m.albedo_reflectivity = glm::vec4(info.albedo, info.reflectivity);
    // w: transparent (the shaders' vx_transparent).
    m.emission = glm::vec4(info.emission, opaque ? 0.f : 1.f);
    m.optics = glm::vec4(absorption_coefficient(info.albedo), refractive_index(info.reflectivity));
    return m;
}

std::vector<gpu::Material> material_table(const world::BlockRegistry& registry, uint32_t count) {
    std::vector<gpu::Material> table(count);
    for (uint32_t id = 0; id < count; ++id)
        table[id] = gpu_material(registry.info(world::BlockId(id)), registry.is_opaque(world::BlockId(id)));
    return table;
}

} // namespace vx::render
