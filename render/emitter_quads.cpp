#include "emitter_quads.h"

#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "shaders/shared/tonemap.h"

namespace vx::render {

void collect_emissive_quads(const world::ChunkMesh& mesh, const std::vector<bool>& emissive,
                            std::vector<world::Quad>& out) {
    mesh.for_each_quad([&](const world::Quad& q) {
        if (q.block < emissive.size() && emissive[q.block])
            out.push_back(q);
    });
}

gpu::EmitterQuad emitter_quad(world::LodCoord c, const world::Quad& q, world::BlockPos origin, glm::vec3 emission) {
    glm::ivec3 corners[4];
    world::quad_corners(q, corners); // Counter-clockwise from the air side.
    const float cell = float(world::lod_chunk_blocks(c.level) / world::kChunkSize);
    const glm::vec3 base = glm::vec3(world::lod_origin(c) - origin);
    const glm::vec3 c0 = base + glm::vec3(corners[0]) * cell;
    const glm::vec3 eu = glm::vec3(corners[1] - corners[0]) * cell;
    const glm::vec3 ev = glm::vec3(corners[3] - corners[0]) * cell;
    gpu::EmitterQuad e;
    e.corner = glm::vec4(c0, glm::length(glm::cross(eu, ev)));
    e.edge_u = glm::vec4(eu, 0.f);
    e.edge_v = glm::vec4(ev, 0.f);
    e.emission = glm::vec4(emission, gpu::vx_luminance(emission));
    return e;
}

EmitterListSize write_emitter_quads(std::span<const world::LodCoord> chunks,
                                    const std::function<const std::vector<world::Quad>*(world::LodCoord)>& quads_of,
                                    const std::function<glm::vec3(world::BlockId)>& emission_of,
                                    world::BlockPos origin, std::span<gpu::EmitterQuad> dst,
                                    std::span<gpu::EmitterBound> bounds) {
    EmitterListSize n;
    for (const world::LodCoord c : chunks) {
        const std::vector<world::Quad>* quads = quads_of(c);
        if (!quads || quads->size() > dst.size() - n.quads || n.covered_chunks == bounds.size())
            break;
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        float power = 0.f;
        for (const world::Quad& q : *quads) {
            const gpu::EmitterQuad e = emitter_quad(c, q, origin, emission_of(q.block));
            const glm::vec3 far = glm::vec3(e.corner + e.edge_u + e.edge_v);
            lo = glm::min(lo, glm::min(glm::vec3(e.corner), far));
            hi = glm::max(hi, glm::max(glm::vec3(e.corner), far));
            power += e.emission.w * e.corner.w;
            dst[n.quads++] = e;
        }
        bounds[n.covered_chunks++] = {glm::vec4(lo, power), glm::vec4(hi, 0.f)};
    }
    return n;
}

} // namespace vx::render
