#include "world/mesh/apron.h"

#include <algorithm>
#include <cstring>

#include "world/mesh/index_unpack.h"
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

void ApronLayer::take(Face f, const Chunk* neighbour) {
    palette.clear();
    ids.clear();
    if (!neighbour || neighbour->is_uniform()) {
        uniform = neighbour ? neighbour->uniform_id() : kAir;
        return;
    }
    const int axis = face_axis(f);
    const int layer = face_positive(f) ? 0 : kChunkSize - 1; // The neighbour's touching layer.
    const ChunkPalette& pal = *neighbour->palette();
    const PackedArray& packed = pal.indices;
    const uint32_t bits = packed.bits();
    if (bits > 8) { // Palettes of over 256 entries: rare, block by block.
        ids.resize(size_t(kChunkSize * kChunkSize));
        for (int v = 0; v < kChunkSize; ++v)
            for (int u = 0; u < kChunkSize; ++u)
                ids[size_t(u + kChunkSize * v)] = neighbour->get(plane_to_local(axis, layer, u, v));
        return;
    }
    palette = pal.ids;
    if (axis == 0) {
        // u = y, v = z: entry `layer` of every row. A row is 4 * bits bytes (32 entries), so the
        // entry sits at the same byte and shift in each; a 2-byte read holds it (bits <= 8; the
        // array's padding word keeps the last read inside it).
        const auto* bytes = reinterpret_cast<const uint8_t*>(packed.words());
        const size_t first = size_t(layer) * bits / 8;
        const uint32_t shift = uint32_t(layer) * bits % 8, mask = (1u << bits) - 1;
        for (size_t r = 0; r < entries.size(); ++r) {
            uint16_t two;
            std::memcpy(&two, bytes + r * 4 * bits + first, 2);
            entries[r] = uint8_t((uint32_t(two) >> shift) & mask);
        }
    } else if (axis == 1) { // u = x, v = z: rows z * 32 + layer.
        mesher_detail::unpack_rows8(packed, layer, kChunkSize, entries.data(), kChunkSize);
    } else { // u = x, v = y: rows layer * 32 + y.
        mesher_detail::unpack_rows8(packed, layer * kChunkSize, kChunkSize, entries.data());
    }
}

void Apron::set_face(Face f, const ApronLayer& layer, const BlockRegistry& registry) {
    const int fi = int(f);
    if (!layer.ids.empty()) {
        std::copy(layer.ids.begin(), layer.ids.end(), ids[fi].begin());
        refresh_face(f, registry);
        return;
    }
    if (layer.palette.empty()) {
        fill_face(f, layer.uniform, registry);
        return;
    }
    // Palette entries are classified once, not per block.
    std::array<BlockId, 256> id_of{};
    std::array<uint8_t, 256> opaque_of{}, transparent_of{};
    for (size_t e = 0; e < layer.palette.size(); ++e) {
        const BlockId id = layer.palette[e];
        id_of[e] = id;
        opaque_of[e] = registry.is_opaque(id);
        transparent_of[e] = id != kAir && !opaque_of[e];
    }
    uint8_t transparent = 0;
    for (int v = 0; v < kChunkSize; ++v) {
        uint32_t row = 0;
        for (int u = 0; u < kChunkSize; ++u) {
            const uint8_t e = layer.entries[size_t(u + kChunkSize * v)];
            ids[fi][size_t(u + kChunkSize * v)] = id_of[e];
            row |= uint32_t(opaque_of[e]) << u;
            transparent |= transparent_of[e];
        }
        opaque[fi][v] = row;
    }
    any_transparent[fi] = transparent;
}

void Apron::copy_face(Face f, const Chunk* neighbour, const BlockRegistry& registry) {
    if (!neighbour || neighbour->is_uniform()) {
        fill_face(f, neighbour ? neighbour->uniform_id() : kAir, registry);
        return;
    }
    ApronLayer layer;
    layer.take(f, neighbour);
    set_face(f, layer, registry);
}

Apron make_apron(const World& world, ChunkCoord c) {
    Apron a;
    for (int f = 0; f < 6; ++f)
        a.copy_face(Face(f), world.find_neighbour(c, Face(f)), world.registry());
    return a;
}

} // namespace vx::world
