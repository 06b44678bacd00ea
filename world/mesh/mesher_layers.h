#pragma once
// The greedy mesher's input side: per-layer occupancy bits of a chunk (row v, bit u on planes
// perpendicular to an axis), built from packed palette indices. Internal to vx_world (included by
// greedy_mesher.cpp and mesher_layers.cpp only). Not thread-safe: plain functions on caller data.

#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "world/mesh/mesher.h"

namespace vx::world::mesher_detail {

enum : uint8_t { kNonAir = 1, kOpaque = 2, kTransparent = 4 };

// Face masks of one layer of blocks (perpendicular to some axis), row v, bit u.
struct LayerBits {
    uint32_t n[kChunkSize]; // Non-air.
    uint32_t o[kChunkSize]; // Opaque.
    uint32_t t[kChunkSize]; // Non-air and not opaque.
};

// What the mesher needs to know about the chunk, computed once per call.
struct ChunkView {
    const Chunk* chunk = nullptr;
    const ChunkPalette* pal = nullptr; // Null for a uniform chunk.
    const Apron* apron = nullptr;
    const uint8_t* flags = nullptr;    // Per palette entry.
    uint8_t uniform_flags = 0;
    bool multi = false;       // More than one non-air id present: merging must compare ids.
    bool transparent = false; // Some non-opaque, non-air block present.
    BlockId single = kAir;    // The only non-air id when !multi.
    const uint8_t* dense = nullptr; // Unpacked palette indices (full meshes of palettes <= 256).
    // Split mode (few ids, unpacked): per-entry occupancy layers, so each id merges on its own
    // bitmask with no id compares. split_layers[k][axis][layer][v] for entry split_entries[k].
    int split_count = 0;
    const uint8_t* split_entries = nullptr;
    const uint32_t (*split_layers)[3][kChunkSize][kChunkSize] = nullptr;
    // Entry classes for byte-compare masks (palettes of <= 256 entries, used entries only).
    const uint8_t* air_entries = nullptr;
    const uint8_t* opaque_entries = nullptr;
    int n_air = 0, n_opaque = 0;
    bool all_opaque = true; // Every used non-air entry is opaque.
    uint32_t entry(uint32_t i) const { return dense ? dense[i] : pal->indices.get(i); }
};

// Local index steps for (layer, u, v) on planes perpendicular to each axis.
constexpr uint32_t kLayerStep[3] = {1, kChunkSize, kChunkSize * kChunkSize};
constexpr uint32_t kUStep[3] = {kChunkSize, 1, 1};
constexpr uint32_t kVStep[3] = {kChunkSize * kChunkSize, kChunkSize * kChunkSize, kChunkSize};

// Bit x set where row[x] == e, for a row of 32 bytes.
inline uint32_t eq_mask(const uint8_t* row, uint8_t e) {
#if defined(__SSE2__)
    const __m128i v = _mm_set1_epi8(char(e));
    const uint32_t lo = uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_loadu_si128((const __m128i*)row), v)));
    const uint32_t hi = uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_loadu_si128((const __m128i*)(row + 16)), v)));
    return lo | hi << 16;
#else
    uint32_t m = 0;
    for (int x = 0; x < kChunkSize; ++x)
        m |= uint32_t(row[x] == e) << x;
    return m;
#endif
}

uint8_t block_flags(BlockId id, const BlockRegistry& r);
// 32×32 bit-matrix transpose: bit j of row i moves to bit i of row j.
void transpose32(uint32_t a[32]);
// One layer's bits read straight from the chunk (generic widths).
void extract_layer(const ChunkView& cv, int axis, int layer, LayerBits& out);
// Unpacks all kChunkVolume indices of 1..8-bit arrays to bytes; false for wider ones.
bool unpack_indices(const PackedArray& a, uint8_t* out);
// One layer for incremental remeshing from B-bit indices: unpacks them into `dense` (at their
// chunk indices) and builds the bits. Null for widths it does not handle.
using ExtractFn = void (*)(const ChunkView&, int, int, uint8_t*, LayerBits&);
ExtractFn extract_fixed_for(uint32_t bits);
// All 3×32 layers of a chunk at once (layers[axis][layer]).
void extract_all_layers(const ChunkView& cv, LayerBits (*layers)[kChunkSize]);

} // namespace vx::world::mesher_detail
