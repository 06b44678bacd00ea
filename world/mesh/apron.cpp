#include "world/mesh/apron.h"

#include <algorithm>

#include "world/world.h"

namespace vx::world {

Apron Apron::filled(BlockId id, const BlockRegistry& registry) {
    Apron a;
    for (int f = 0; f < 6; ++f)
        a.fill_face(Face(f), id, registry);
    return a;
}

void Apron::fill_face(Face f, BlockId id, const BlockRegistry& registry) {
    const int fi = int(f);
    ids[fi].fill(id);
    opaque[fi].fill(registry.is_opaque(id) ? ~0u : 0u);
    any_transparent[fi] = id != kAir && !registry.is_opaque(id);
}

void Apron::set(Face f, int u, int v, BlockId id, const BlockRegistry& registry) {
    const int fi = int(f);
    ids[fi][u + kChunkSize * v] = id;
    const uint32_t bit = 1u << u;
    opaque[fi][v] = registry.is_opaque(id) ? (opaque[fi][v] | bit) : (opaque[fi][v] & ~bit);
    if (id != kAir && !registry.is_opaque(id))
        any_transparent[fi] = 1;
}

void Apron::refresh_face(Face f, const BlockRegistry& registry) {
    const int fi = int(f);
    any_transparent[fi] = 0;
    for (int v = 0; v < kChunkSize; ++v) {
        uint32_t row = 0;
        for (int u = 0; u < kChunkSize; ++u) {
            const BlockId id = ids[fi][u + kChunkSize * v];
            const bool op = registry.is_opaque(id);
            row |= uint32_t(op) << u;
            any_transparent[fi] |= uint8_t(id != kAir && !op);
        }
        opaque[fi][v] = row;
    }
}

void Apron::copy_face(Face f, const Chunk* neighbour, const BlockRegistry& registry) {
    if (!neighbour || neighbour->is_uniform()) {
        fill_face(f, neighbour ? neighbour->uniform_id() : kAir, registry);
        return;
    }
    const int axis = face_axis(f);
    const int layer = face_positive(f) ? 0 : kChunkSize - 1; // The neighbour's touching layer.
    auto& out = ids[int(f)];
    for (int v = 0; v < kChunkSize; ++v)
        for (int u = 0; u < kChunkSize; ++u)
            out[u + kChunkSize * v] = neighbour->get(plane_to_local(axis, layer, u, v));
    refresh_face(f, registry);
}

Apron make_apron(const World& world, ChunkCoord c) {
    Apron a;
    for (int f = 0; f < 6; ++f)
        a.copy_face(Face(f), world.find_chunk(c + face_normal(Face(f))), world.registry());
    return a;
}

} // namespace vx::world
