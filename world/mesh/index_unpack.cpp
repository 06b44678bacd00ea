#include "world/mesh/index_unpack.h"

#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "world/coords.h"

namespace vx::world::mesher_detail {

static_assert(std::endian::native == std::endian::little, "unpacking reads packed words as bytes");

namespace {

#if defined(__SSE2__)
constexpr bool kSse2 = true;
#else
constexpr bool kSse2 = false;
#endif

// 8 entries of B bits (the low 8B bits of x) spread to one per byte: entries 4..7 move to the
// high half, then 2..3 of each half to its upper 16 bits, then every odd entry up a byte.
template <int B> inline uint64_t spread8(uint64_t x) {
    if constexpr (B < 8)
        x &= (uint64_t(1) << (8 * B)) - 1;
    x = (x & ((uint64_t(1) << (4 * B)) - 1)) | ((x >> (4 * B)) << 32);
    constexpr uint64_t m2 = ((uint64_t(1) << (2 * B)) - 1) * 0x0000000100000001ull;
    x = (x & m2) | (((x >> (2 * B)) & m2) << 16);
    constexpr uint64_t m3 = ((uint64_t(1) << B) - 1) * 0x0001000100010001ull;
    return (x & m3) | (((x >> B) & m3) << 8);
}

// One row: 4B bytes of packed indices (the row starts on a byte: 32B bits) to 32 bytes.
template <int B> inline void unpack_row(const uint8_t* src, uint8_t* out) {
#if defined(__SSE2__)
    if constexpr (B == 1) {
        // Each source byte to 8 lanes, then test one bit per lane.
        uint32_t bits;
        std::memcpy(&bits, src, 4);
        const __m128i v = _mm_cvtsi32_si128(int(bits));
        const __m128i b2 = _mm_unpacklo_epi8(v, v);
        const __m128i b4 = _mm_unpacklo_epi16(b2, b2);
        const __m128i sel = _mm_set1_epi64x(0x8040201008040201ll);
        const __m128i one = _mm_set1_epi8(1);
        const __m128i lo = _mm_unpacklo_epi32(b4, b4), hi = _mm_unpackhi_epi32(b4, b4);
        _mm_storeu_si128((__m128i*)out, _mm_and_si128(_mm_cmpeq_epi8(_mm_and_si128(lo, sel), sel), one));
        _mm_storeu_si128((__m128i*)(out + 16), _mm_and_si128(_mm_cmpeq_epi8(_mm_and_si128(hi, sel), sel), one));
        return;
    } else if constexpr (B == 2) {
        const __m128i x = _mm_loadl_epi64((const __m128i*)src);
        const __m128i m = _mm_set1_epi8(3);
        const __m128i e0 = _mm_and_si128(x, m), e1 = _mm_and_si128(_mm_srli_epi16(x, 2), m);
        const __m128i e2 = _mm_and_si128(_mm_srli_epi16(x, 4), m), e3 = _mm_and_si128(_mm_srli_epi16(x, 6), m);
        const __m128i a = _mm_unpacklo_epi8(e0, e1), b = _mm_unpacklo_epi8(e2, e3);
        _mm_storeu_si128((__m128i*)out, _mm_unpacklo_epi16(a, b));
        _mm_storeu_si128((__m128i*)(out + 16), _mm_unpackhi_epi16(a, b));
        return;
    } else if constexpr (B == 4) {
        const __m128i x = _mm_loadu_si128((const __m128i*)src);
        const __m128i m = _mm_set1_epi8(15);
        const __m128i lo = _mm_and_si128(x, m), hi = _mm_and_si128(_mm_srli_epi16(x, 4), m);
        _mm_storeu_si128((__m128i*)out, _mm_unpacklo_epi8(lo, hi));
        _mm_storeu_si128((__m128i*)(out + 16), _mm_unpackhi_epi8(lo, hi));
        return;
    }
#endif
    if constexpr (B == 8) {
        std::memcpy(out, src, 32);
    } else if constexpr (kSse2) {
#if defined(__SSE2__)
        // Two groups of 8 per register, spread as in spread8.
        const __m128i keep = _mm_set1_epi64x(int64_t((uint64_t(1) << (8 * B)) - 1));
        const __m128i m1 = _mm_set1_epi64x(int64_t((uint64_t(1) << (4 * B)) - 1));
        const __m128i m2 = _mm_set1_epi64x(int64_t(((uint64_t(1) << (2 * B)) - 1) * 0x0000000100000001ull));
        const __m128i m3 = _mm_set1_epi64x(int64_t(((uint64_t(1) << B) - 1) * 0x0001000100010001ull));
        for (int g = 0; g < 4; g += 2) {
            __m128i x = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i*)(src + g * B)),
                                           _mm_loadl_epi64((const __m128i*)(src + (g + 1) * B)));
            x = _mm_and_si128(x, keep);
            x = _mm_or_si128(_mm_and_si128(x, m1), _mm_slli_epi64(_mm_srli_epi64(x, 4 * B), 32));
            x = _mm_or_si128(_mm_and_si128(x, m2), _mm_slli_epi64(_mm_and_si128(_mm_srli_epi64(x, 2 * B), m2), 16));
            x = _mm_or_si128(_mm_and_si128(x, m3), _mm_slli_epi64(_mm_and_si128(_mm_srli_epi64(x, B), m3), 8));
            _mm_storeu_si128((__m128i*)(out + g * 8), x);
        }
#endif
    } else {
        // 8 entries are B whole bytes; the 8-byte read stays within the array's padding word.
        for (int g = 0; g < 4; ++g) {
            uint64_t x;
            std::memcpy(&x, src + g * B, 8);
            x = spread8<B>(x);
            std::memcpy(out + g * 8, &x, 8);
        }
    }
}

template <int B> void unpack_rows_fixed(const uint64_t* words, int row0, int count, int step, uint8_t* out) {
    const uint8_t* src = reinterpret_cast<const uint8_t*>(words) + size_t(row0) * 4 * B;
    for (int r = 0; r < count; ++r, src += size_t(step) * 4 * B, out += kChunkSize)
        unpack_row<B>(src, out);
}

// Consecutive rows: a row whose packed bytes equal the previous row's copies its entries (most
// rows of terrain repeat the one before: air above the ground, stone under it).
template <int B> void unpack_rows_repeat(const uint64_t* words, int count, uint8_t* out) {
    constexpr size_t kRowBytes = 4 * B;
    const uint8_t* src = reinterpret_cast<const uint8_t*>(words);
    unpack_row<B>(src, out);
    for (int r = 1; r < count; ++r) {
        src += kRowBytes, out += kChunkSize;
        if (std::memcmp(src, src - kRowBytes, kRowBytes) == 0)
            std::memcpy(out, out - kChunkSize, kChunkSize);
        else
            unpack_row<B>(src, out);
    }
}

} // namespace

void unpack_rows8(const PackedArray& a, int row0, int count, uint8_t* out, int step) {
    switch (a.bits()) {
    case 1: unpack_rows_fixed<1>(a.words(), row0, count, step, out); break;
    case 2: unpack_rows_fixed<2>(a.words(), row0, count, step, out); break;
    case 3: unpack_rows_fixed<3>(a.words(), row0, count, step, out); break;
    case 4: unpack_rows_fixed<4>(a.words(), row0, count, step, out); break;
    case 5: unpack_rows_fixed<5>(a.words(), row0, count, step, out); break;
    case 6: unpack_rows_fixed<6>(a.words(), row0, count, step, out); break;
    case 7: unpack_rows_fixed<7>(a.words(), row0, count, step, out); break;
    case 8: unpack_rows_fixed<8>(a.words(), row0, count, step, out); break;
    default: VX_ASSERT(false && "unpack_rows8: more than 8 bits");
    }
}

void unpack_chunk8(const PackedArray& a, int count, uint8_t* out) {
    switch (a.bits()) {
    case 1: unpack_rows_repeat<1>(a.words(), count, out); break;
    case 2: unpack_rows_repeat<2>(a.words(), count, out); break;
    case 3: unpack_rows_repeat<3>(a.words(), count, out); break;
    case 4: unpack_rows_repeat<4>(a.words(), count, out); break;
    case 5: unpack_rows_repeat<5>(a.words(), count, out); break;
    case 6: unpack_rows_repeat<6>(a.words(), count, out); break;
    case 7: unpack_rows_repeat<7>(a.words(), count, out); break;
    case 8: unpack_rows_repeat<8>(a.words(), count, out); break;
    default: VX_ASSERT(false && "unpack_chunk8: more than 8 bits");
    }
}

void unpack_rows16(const PackedArray& a, int row0, int count, uint16_t* out) {
    const uint32_t end = uint32_t(row0 + count) * kChunkSize;
    for (uint32_t i = uint32_t(row0) * kChunkSize; i < end; ++i)
        *out++ = uint16_t(a.get(i));
}

#if defined(__SSE2__)
namespace {
// 16 x 16 bytes: four rounds of interleaving rows i and i + 8 rotate the 8-bit (row, column)
// index by one bit each, so four rounds swap row and column.
inline void transpose16(const uint8_t* src, int src_stride, uint8_t* dst, int dst_stride) {
    __m128i r[16], t[16];
    for (int i = 0; i < 16; ++i)
        r[i] = _mm_loadu_si128((const __m128i*)(src + i * src_stride));
    for (int round = 0; round < 4; ++round) {
        for (int i = 0; i < 8; ++i) {
            t[2 * i] = _mm_unpacklo_epi8(r[i], r[i + 8]);
            t[2 * i + 1] = _mm_unpackhi_epi8(r[i], r[i + 8]);
        }
        for (int i = 0; i < 16; ++i)
            r[i] = t[i];
    }
    for (int i = 0; i < 16; ++i)
        _mm_storeu_si128((__m128i*)(dst + i * dst_stride), r[i]);
}
} // namespace
#endif

void transpose_slabs(const uint8_t* d, uint8_t* dt) {
    for (int z = 0; z < kChunkSize; ++z, d += kChunkSize * kChunkSize, dt += kChunkSize * kChunkSize) {
#if defined(__SSE2__)
        for (int by = 0; by < 2; ++by)
            for (int bx = 0; bx < 2; ++bx)
                transpose16(d + by * 16 * kChunkSize + bx * 16, kChunkSize, dt + bx * 16 * kChunkSize + by * 16,
                            kChunkSize);
#else
        for (int y = 0; y < kChunkSize; ++y)
            for (int x = 0; x < kChunkSize; ++x)
                dt[x * kChunkSize + y] = d[y * kChunkSize + x];
#endif
    }
}

void transpose_slabs(const uint16_t* d, uint16_t* dt) {
    for (int z = 0; z < kChunkSize; ++z, d += kChunkSize * kChunkSize, dt += kChunkSize * kChunkSize)
        for (int y = 0; y < kChunkSize; ++y)
            for (int x = 0; x < kChunkSize; ++x)
                dt[x * kChunkSize + y] = d[y * kChunkSize + x];
}

// LSB-first variant of Hacker's Delight 7-3: swap ever smaller off-diagonal blocks.
void transpose32(uint32_t a[32]) {
    uint32_t m = 0x0000FFFFu;
    for (int j = 16; j != 0; j >>= 1, m ^= m << j) {
        for (int k = 0; k < 32; k = (k + j + 1) & ~j) {
            const uint32_t t = ((a[k] >> j) ^ a[k + j]) & m;
            a[k] ^= t << j;
            a[k + j] ^= t;
        }
    }
}

uint32_t column_bits(const uint32_t* rows, int x) {
    uint32_t m = 0;
#if defined(__SSE2__)
    // Bit x to the sign bit of each 32-bit lane; movmskps gathers four rows at a time.
    const __m128i sh = _mm_cvtsi32_si128(31 - x);
    for (int k = 0; k < 8; ++k) {
        const __m128i r = _mm_sll_epi32(_mm_loadu_si128((const __m128i*)(rows + 4 * k)), sh);
        m |= uint32_t(_mm_movemask_ps(_mm_castsi128_ps(r))) << (4 * k);
    }
#else
    for (int y = 0; y < kChunkSize; ++y)
        m |= ((rows[y] >> x) & 1u) << y;
#endif
    return m;
}

} // namespace vx::world::mesher_detail
