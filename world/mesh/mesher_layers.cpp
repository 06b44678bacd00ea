#include "world/mesh/mesher_layers.h"

#include <algorithm>
#include <type_traits>

namespace vx::world::mesher_detail {

uint8_t block_flags(BlockId id, const BlockRegistry& r) {
    if (id == kAir)
        return 0;
    return r.is_opaque(id) ? uint8_t(kNonAir | kOpaque) : uint8_t(kNonAir | kTransparent);
}

ChunkView make_view(const MesherInput& in, std::vector<uint8_t>& flags) {
    ChunkView cv;
    cv.chunk = &in.chunk;
    cv.apron = &in.apron;
    cv.pal = in.chunk.palette();
    if (!cv.pal) {
        cv.uniform_flags = block_flags(in.chunk.uniform_id(), in.registry);
        cv.single = in.chunk.uniform_id();
        cv.transparent = (cv.uniform_flags & kTransparent) != 0;
        return cv;
    }
    const ChunkPalette& p = *cv.pal;
    cv.bits = p.indices.bits();
    flags.resize(p.ids.size());
    int non_air = 0;
    for (size_t e = 0; e < p.ids.size(); ++e) {
        flags[e] = block_flags(p.ids[e], in.registry);
        if (p.counts[e] == 0)
            continue;
        if (!(flags[e] & kNonAir)) {
            if (cv.n_air < kMaxClasses)
                cv.air[cv.n_air] = uint16_t(e);
            ++cv.n_air;
            continue;
        }
        ++non_air;
        cv.single = p.ids[e];
        if (flags[e] & kTransparent) {
            cv.transparent = true;
            if (cv.n_clear < kMaxClasses)
                cv.clear[cv.n_clear] = uint16_t(e);
            ++cv.n_clear;
        }
    }
    cv.flags = flags.data();
    cv.multi = non_air > 1;
    return cv;
}

namespace {

#if defined(__SSE2__)
// A row of 32 entries in registers, compared as a whole.
struct Row8 {
    __m128i v[2];
    explicit Row8(const uint8_t* p) : v{_mm_loadu_si128((const __m128i*)p), _mm_loadu_si128((const __m128i*)(p + 16))} {}
    static __m128i splat(uint16_t e) { return _mm_set1_epi8(char(e)); }
    uint32_t eq(__m128i e) const {
        return uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v[0], e))) |
               uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v[1], e))) << 16;
    }
    uint32_t eq(const Row8& o) const {
        return uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v[0], o.v[0]))) |
               uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v[1], o.v[1]))) << 16;
    }
};
struct Row16 {
    __m128i v[4];
    explicit Row16(const uint16_t* p) {
        for (int i = 0; i < 4; ++i)
            v[i] = _mm_loadu_si128((const __m128i*)(p + 8 * i));
    }
    static __m128i splat(uint16_t e) { return _mm_set1_epi16(short(e)); }
    static uint32_t pack(__m128i a, __m128i b) { return uint32_t(_mm_movemask_epi8(_mm_packs_epi16(a, b))); }
    uint32_t eq(__m128i e) const {
        return pack(_mm_cmpeq_epi16(v[0], e), _mm_cmpeq_epi16(v[1], e)) |
               pack(_mm_cmpeq_epi16(v[2], e), _mm_cmpeq_epi16(v[3], e)) << 16;
    }
    uint32_t eq(const Row16& o) const {
        return pack(_mm_cmpeq_epi16(v[0], o.v[0]), _mm_cmpeq_epi16(v[1], o.v[1])) |
               pack(_mm_cmpeq_epi16(v[2], o.v[2]), _mm_cmpeq_epi16(v[3], o.v[3])) << 16;
    }
};
#else
template <class E> struct RowScalar {
    const E* p;
    explicit RowScalar(const E* q) : p(q) {}
    static E splat(uint16_t e) { return E(e); }
    uint32_t eq(E e) const {
        uint32_t m = 0;
        for (int i = 0; i < kChunkSize; ++i)
            m |= uint32_t(p[i] == e) << i;
        return m;
    }
    uint32_t eq(const RowScalar& o) const { return eq_rows(p, o.p); }
};
using Row8 = RowScalar<uint8_t>;
using Row16 = RowScalar<uint16_t>;
#endif

template <class E> using RowOf = std::conditional_t<sizeof(E) == 1, Row8, Row16>;

// Where row i of slab z goes in the layout of `m`, and the step to row i + 1.
inline int slab_base(const RowMasks& m, int z) { return m.swap ? z : z * kChunkSize; }
inline int slab_step(const RowMasks& m) { return m.swap ? kChunkSize : 1; }

// Stores one row's masks. Without transparent blocks o and t are left alone: the mesher reads n
// for o then, and never reads t.
template <bool kClear> inline void store_row(const RowMasks& m, int j, uint32_t n, uint32_t clear) {
    m.n[j] = n;
    if constexpr (kClear) {
        m.o[j] = n & ~clear;
        m.t[j] = clear;
    }
}

// Non-air: the air entry does not match (a palette holds air at most once). Transparent: one
// of the transparent entries matches; with too many of them, flags one by one. Each row is
// loaded once and compared in registers.
// kClear: 0 no transparent entry, 1 a compare per transparent entry, 2 flags one by one, 3 one
// transparent entry (water in terrain).
// kTwo: also store to b.
template <class E, int kClear, bool kTwo>
void rows_masks(const ChunkView& cv, const E* rows, int count, const RowMasks& a, const RowMasks& b) {
    using Row = RowOf<E>;
    const auto air = Row::splat(cv.n_air ? cv.air[0] : 0);
    const bool has_air = cv.n_air != 0;
    const auto clear0 = Row::splat(cv.n_clear ? cv.clear[0] : 0);
    const int sa = slab_step(a), sb = slab_step(b);
    for (int z = 0; z < count / kChunkSize; ++z) {
        int ja = slab_base(a, z), jb = slab_base(b, z);
        for (int i = 0; i < kChunkSize; ++i, rows += kChunkSize, ja += sa, jb += sb) {
            const Row row(rows);
            const uint32_t n = has_air ? ~row.eq(air) : ~0u;
            uint32_t clear = 0;
            if constexpr (kClear == 3) {
                clear = row.eq(clear0);
            } else if constexpr (kClear == 1) {
                for (int k = 0; k < cv.n_clear; ++k)
                    clear |= row.eq(Row::splat(cv.clear[k]));
            } else if constexpr (kClear == 2) {
                for (int x = 0; x < kChunkSize; ++x)
                    clear |= uint32_t((cv.flags[rows[x]] & kTransparent) != 0) << x;
            }
            store_row<kClear != 0>(a, ja, n, clear);
            if constexpr (kTwo)
                store_row<kClear != 0>(b, jb, n, clear);
        }
    }
}

template <class E, int kClear>
void masks_of(const ChunkView& cv, const E* rows, int count, const RowMasks& a, const RowMasks* b) {
    if (b)
        rows_masks<E, kClear, true>(cv, rows, count, a, *b);
    else
        rows_masks<E, kClear, false>(cv, rows, count, a, a);
}

template <class E> void masks_of(const ChunkView& cv, const E* rows, int count, const RowMasks& a, const RowMasks* b) {
    if (cv.n_clear == 0)
        masks_of<E, 0>(cv, rows, count, a, b);
    else if (cv.n_clear == 1)
        masks_of<E, 3>(cv, rows, count, a, b);
    else if (cv.n_clear <= kMaxClasses)
        masks_of<E, 1>(cv, rows, count, a, b);
    else
        masks_of<E, 2>(cv, rows, count, a, b);
}

} // namespace

void entry_row_masks(const ChunkView& cv, const uint8_t* rows, int count, const RowMasks& a, const RowMasks* b) {
    masks_of(cv, rows, count, a, b);
}

void entry_row_masks(const ChunkView& cv, const uint16_t* rows, int count, const RowMasks& a, const RowMasks* b) {
    masks_of(cv, rows, count, a, b);
}

void bit_row_masks(const ChunkView& cv, const uint32_t* bits, int count, const RowMasks& out) {
    const uint8_t f0 = cv.flags[0], f1 = cv.flags[1];
    for (int r = 0; r < count; ++r) {
        const uint32_t row = bits[r];
        auto sel = [&](uint8_t bit) { return ((f0 & bit) ? ~row : 0u) | ((f1 & bit) ? row : 0u); };
        const int i = out.swap ? (r & (kChunkSize - 1)) * kChunkSize + (r >> kChunkBits) : r;
        out.n[i] = sel(kNonAir);
        out.o[i] = sel(kOpaque);
        out.t[i] = sel(kTransparent);
    }
}

void uniform_row_masks(const ChunkView& cv, int count, const RowMasks& out) {
    const uint8_t f = cv.uniform_flags;
    std::fill_n(out.n, count, (f & kNonAir) ? ~0u : 0u);
    std::fill_n(out.o, count, (f & kOpaque) ? ~0u : 0u);
    std::fill_n(out.t, count, (f & kTransparent) ? ~0u : 0u);
}

} // namespace vx::world::mesher_detail
