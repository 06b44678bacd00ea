#pragma once
// The greedy mesher's input side: what a chunk's palette says about each entry, and occupancy
// masks of rows of 32 blocks (bit i = block i along the row) built from unpacked entry rows with
// byte compares, or straight from the packed bits of a 1-bit palette. Internal to vx_world
// (greedy mesher only). Not thread-safe: plain functions on caller data.

#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "world/mesh/mesher.h"

namespace vx::world::mesher_detail {

enum : uint8_t { kNonAir = 1, kOpaque = 2, kTransparent = 4 };

uint8_t block_flags(BlockId id, const BlockRegistry& r);

constexpr int kRows = kChunkSize * kChunkSize; // Rows of 32 blocks along one direction.
constexpr int kMaxClasses = 64; // Air or transparent entries compared one by one (more: wide path).

// What the mesher needs to know about the chunk, computed once per call.
struct ChunkView {
    const Chunk* chunk = nullptr;
    const Apron* apron = nullptr;
    const ChunkPalette* pal = nullptr; // Null for a uniform chunk.
    uint32_t bits = 0;                 // Index width; 0 for a uniform chunk.
    uint8_t uniform_flags = 0;
    bool multi = false;       // More than one non-air id present: merging must compare ids.
    bool transparent = false; // Some non-opaque, non-air block present.
    BlockId single = kAir;    // The only non-air id when !multi.
    const uint8_t* flags = nullptr; // Per palette entry.
    // Used entries that are air, and used non-air entries that are not opaque.
    uint16_t air[kMaxClasses], clear[kMaxClasses];
    int n_air = 0, n_clear = 0;
    bool wide() const { return bits > 8; } // Entries need 16 bits.
};

ChunkView make_view(const MesherInput& in, std::vector<uint8_t>& flags);

// Masks of rows: non-air, then opaque and non-air-not-opaque (both only kept for chunks with
// transparent blocks: otherwise opaque = non-air). Row r's masks go to index r, or with `swap`
// to index (r % 32) * 32 + r / 32 (rows z * 32 + y stored as y * 32 + z: a Y plane's lines).
struct RowMasks {
    uint32_t* n;
    uint32_t* o;
    uint32_t* t;
    bool swap = false;
};

// Masks of `count` entry rows (32 entries each), written to `a` and, when not null, also to `b`
// (one pass serves two layouts).
void entry_row_masks(const ChunkView& cv, const uint8_t* rows, int count, const RowMasks& a, const RowMasks* b);
void entry_row_masks(const ChunkView& cv, const uint16_t* rows, int count, const RowMasks& a, const RowMasks* b);
// Masks from rows of 1-bit palette indices (bit set = entry 1); no link.
void bit_row_masks(const ChunkView& cv, const uint32_t* bits, int count, const RowMasks& out);
// Masks of a uniform chunk's rows.
void uniform_row_masks(const ChunkView& cv, int count, const RowMasks& out);

// Bit i set where row[i] == e.
inline uint32_t eq_value(const uint8_t* row, uint16_t e) {
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

inline uint32_t eq_value(const uint16_t* row, uint16_t e) {
#if defined(__SSE2__)
    const __m128i v = _mm_set1_epi16(short(e));
    auto half = [&](const uint16_t* x) {
        const __m128i p = _mm_cmpeq_epi16(_mm_loadu_si128((const __m128i*)x), v);
        const __m128i q = _mm_cmpeq_epi16(_mm_loadu_si128((const __m128i*)(x + 8)), v);
        return uint32_t(_mm_movemask_epi8(_mm_packs_epi16(p, q)));
    };
    return half(row) | half(row + 16) << 16;
#else
    uint32_t m = 0;
    for (int x = 0; x < kChunkSize; ++x)
        m |= uint32_t(row[x] == e) << x;
    return m;
#endif
}

// Bit i set where a[i] == b[i] (two rows of 32 entries).
inline uint32_t eq_rows(const uint8_t* a, const uint8_t* b) {
#if defined(__SSE2__)
    const __m128i lo = _mm_cmpeq_epi8(_mm_loadu_si128((const __m128i*)a), _mm_loadu_si128((const __m128i*)b));
    const __m128i hi =
        _mm_cmpeq_epi8(_mm_loadu_si128((const __m128i*)(a + 16)), _mm_loadu_si128((const __m128i*)(b + 16)));
    return uint32_t(_mm_movemask_epi8(lo)) | uint32_t(_mm_movemask_epi8(hi)) << 16;
#else
    uint32_t m = 0;
    for (int i = 0; i < kChunkSize; ++i)
        m |= uint32_t(a[i] == b[i]) << i;
    return m;
#endif
}

inline uint32_t eq_rows(const uint16_t* a, const uint16_t* b) {
#if defined(__SSE2__)
    auto half = [](const uint16_t* x, const uint16_t* y) {
        const __m128i p = _mm_cmpeq_epi16(_mm_loadu_si128((const __m128i*)x), _mm_loadu_si128((const __m128i*)y));
        const __m128i q =
            _mm_cmpeq_epi16(_mm_loadu_si128((const __m128i*)(x + 8)), _mm_loadu_si128((const __m128i*)(y + 8)));
        return uint32_t(_mm_movemask_epi8(_mm_packs_epi16(p, q)));
    };
    return half(a, b) | half(a + 16, b + 16) << 16;
#else
    uint32_t m = 0;
    for (int i = 0; i < kChunkSize; ++i)
        m |= uint32_t(a[i] == b[i]) << i;
    return m;
#endif
}

} // namespace vx::world::mesher_detail
