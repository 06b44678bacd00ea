#include "world/mesh/mesher.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <span>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "world/mesh/index_unpack.h"
#include "world/mesh/mesher_layers.h"

// Data flow (after the bitmask meshers that cull whole columns with shifts, e.g.
// cgerikj/binary-greedy-meshing): palette indices are unpacked once into rows of 32 entries along
// x (a row whose packed bits equal the previous row's is copied: most rows of terrain), and
// transposed per z slab into rows along y; byte compares turn each row into non-air and
// transparent bits, stored in every axis's line layout. A plane's face mask is then one AND-NOT
// of two rows per line (its non-empty lines found in the same SSE2 pass), and merging runs on
// bits: runs and heights of one id come from 32-entry compares, 1 x 1 quads (most faces of noisy
// chunks) are emitted straight from bit tests.

namespace vx::world {
using namespace mesher_detail;
namespace {

constexpr int kPad = 32; // Entries before each entry array: merging reads row[-1].

// Rows of one axis's layers l0, l0 + 1, ...: the masks of (layer l, line v) are at index
// (l - l0) * 32 + v, its entries (multi-id chunks only) at entry row (l - l0) * els + v * ers.
struct AxisRows {
    const uint32_t* n = nullptr;
    const uint32_t* o = nullptr;
    const uint32_t* t = nullptr;
    const void* ent = nullptr; // Entry rows, uint8_t or uint16_t.
    int l0 = 0, els = kChunkSize, ers = 1;
    int row(int l, int v) const { return (l - l0) * kChunkSize + v; }
    template <class E> const E* entries(int l, int v) const {
        return static_cast<const E*>(ent) + ((l - l0) * els + v * ers) * kChunkSize;
    }
    // Entries of layer l's line 0 and the step between its lines.
    template <class E> const E* line0_entries(int l) const { return entries<E>(l, 0); }
    int line_step() const { return ers * kChunkSize; }
};

// Built as one 64-bit word (packed, block, reserved 0: the little-endian layout of Quad), so a
// quad is one store, not three.
inline Quad make_quad(uint32_t packed, BlockId block) {
    static_assert(std::endian::native == std::endian::little && offsetof(Quad, block) == 4);
    return std::bit_cast<Quad>(packed | uint64_t(block) << 32);
}

// F[v] = x[v] & ~y[v] (kAndNot) or x[v] & y[v], for the 32 lines of a plane; returns the lines
// where F[v] != 0 (bit v).
template <bool kAndNot>
inline uint32_t combine_lines(const uint32_t* x, const uint32_t* y, uint32_t F[kChunkSize]) {
#if defined(__SSE2__)
    uint32_t zero = 0;
    for (int k = 0; k < kChunkSize / 4; ++k) {
        const __m128i a = _mm_loadu_si128((const __m128i*)(x + 4 * k));
        const __m128i b = _mm_loadu_si128((const __m128i*)(y + 4 * k));
        const __m128i f = kAndNot ? _mm_andnot_si128(b, a) : _mm_and_si128(a, b);
        _mm_storeu_si128((__m128i*)(F + 4 * k), f);
        const __m128i z = _mm_cmpeq_epi32(f, _mm_setzero_si128());
        zero |= uint32_t(_mm_movemask_ps(_mm_castsi128_ps(z))) << (4 * k);
    }
    return ~zero;
#else
    uint32_t lines = 0;
    for (int v = 0; v < kChunkSize; ++v) {
        F[v] = kAndNot ? x[v] & ~y[v] : x[v] & y[v];
        lines |= uint32_t(F[v] != 0) << v;
    }
    return lines;
#endif
}

// Removes from F (faces on `lines`) the faces between two blocks of one transparent id; returns
// the lines that still hold faces.
template <class E>
[[gnu::noinline]] uint32_t hide_same_transparent(const ChunkView& cv, const AxisRows& a, int l, int nl,
                                                 Face f, uint32_t F[kChunkSize], uint32_t lines) {
    if (nl >= 0 && nl < kChunkSize) {
        uint32_t H[kChunkSize]; // With one id, two transparent blocks are equal.
        uint32_t hl = combine_lines<false>(a.t + a.row(l, 0), a.t + a.row(nl, 0), H) & lines;
        for (; hl; hl &= hl - 1) {
            const int v = std::countr_zero(hl);
            const uint32_t h = cv.multi ? H[v] & eq_rows(a.entries<E>(l, v), a.entries<E>(nl, v)) : H[v];
            if (!(F[v] &= ~h))
                lines &= ~(1u << v);
        }
        return lines;
    }
    if (!cv.apron->any_transparent[int(f)])
        return lines;
    const auto& ids = cv.apron->ids[int(f)];
    for (uint32_t todo = lines; todo; todo &= todo - 1) {
        const int v = std::countr_zero(todo);
        uint32_t cand = F[v] & a.t[a.row(l, v)];
        while (cand) {
            const int u = std::countr_zero(cand);
            cand &= cand - 1;
            const BlockId id = cv.multi ? cv.pal->ids[a.entries<E>(l, v)[u]] : cv.single;
            if (id == ids[u + kChunkSize * v])
                F[v] &= ~(1u << u);
        }
        if (!F[v])
            lines &= ~(1u << v);
    }
    return lines;
}

// Faces of layer l towards l + 1 (positive) or l - 1: non-air here, not opaque there (the apron
// past the chunk's border). Returns the lines holding faces (bit v).
template <class E>
[[gnu::always_inline]] inline uint32_t face_mask(const ChunkView& cv, const AxisRows& a, int axis, int l,
                                                bool positive, uint32_t F[kChunkSize]) {
    const int nl = positive ? l + 1 : l - 1;
    const Face f = make_face(axis, positive);
    const uint32_t* here = a.n + a.row(l, 0);
    const uint32_t* occ = cv.transparent ? a.o : a.n; // Without transparent blocks, opaque = non-air.
    const uint32_t* there = nl >= 0 && nl < kChunkSize ? occ + a.row(nl, 0) : cv.apron->opaque[int(f)].data();
    const uint32_t lines = combine_lines<true>(here, there, F);
    if (!lines || !cv.transparent)
        return lines;
    return hide_same_transparent<E>(cv, a, l, nl, f, F, lines);
}

inline uint32_t run_mask(int u0, int w) { return uint32_t(((uint64_t(1) << w) - 1) << u0); }

// Classic greedy merge of one plane's faces F (consumed): line by line, a quad starts at the
// lowest free face, takes the whole run of equal faces along u, then grows along v while the next
// line holds the same run. Runs of one line never overlap, so they are independent: width-1 runs
// that cannot grow are emitted first, straight from bit tests. Returns the end of the output.
// Output order (edits rely on it to put a 1 x 1 quad back where a merge would): by line, then
// 1 x 1 quads before larger ones, then by u (see quad_order).
template <class E, bool kMulti>
Quad* merge_plane(const ChunkView& cv, const AxisRows& a, uint32_t F[kChunkSize], uint32_t lines, int l, uint32_t base,
                  Quad* q) {
    const BlockId* ids = kMulti ? cv.pal->ids.data() : nullptr;
    const E* ent = kMulti ? a.line0_entries<E>(l) : nullptr;
    const int step = a.line_step();
    for (; lines; lines &= lines - 1) {
        const int v = std::countr_zero(lines);
        uint32_t m = F[v]; // Lines below may have been used up by quads from above.
        if (!m)
            continue;
        const uint32_t next = v + 1 < kChunkSize ? F[v + 1] : 0u;
        const uint32_t line = base | uint32_t(v) << 5;
        if constexpr (!kMulti) {
            uint32_t lone = m & ~(m << 1) & ~(m >> 1) & ~next;
            m &= ~lone;
            while (lone) {
                *q++ = make_quad(line | uint32_t(std::countr_zero(lone)), cv.single);
                lone &= lone - 1;
            }
            while (m) {
                const int u0 = std::countr_zero(m);
                const int w = std::countr_zero(~(uint64_t(m) >> u0));
                const uint32_t run = run_mask(u0, w);
                int h = 1;
                for (; v + h < kChunkSize && (F[v + h] & run) == run; ++h)
                    F[v + h] &= ~run;
                m &= ~run;
                *q++ = make_quad(line | uint32_t(u0) | uint32_t(w - 1) << 10 | uint32_t(h - 1) << 15, cv.single);
            }
        } else {
            const E* e = ent + v * step;
            // Face u joins the run of u - 1: both faces, equal entries.
            const uint32_t cont = m & (m << 1) & eq_rows(e, e - 1);
            uint32_t lone = m & ~cont & ~(cont >> 1); // Runs of width 1...
            if (lone & next) // ... that cannot grow: no face of the same id below.
                lone &= ~(next & eq_rows(e, e + step));
            m &= ~lone;
            while (lone) {
                const int u = std::countr_zero(lone);
                *q++ = make_quad(line | uint32_t(u), ids[e[u]]);
                lone &= lone - 1;
            }
            while (m) {
                const int u0 = std::countr_zero(m);
                const int w = 1 + std::countr_zero(~(uint64_t(cont) >> (u0 + 1)));
                const uint32_t run = run_mask(u0, w);
                const E id0 = e[u0];
                int h = 1;
                for (; v + h < kChunkSize; ++h) {
                    if ((F[v + h] & run) != run || (eq_value(e + h * step, id0) & run) != run)
                        break;
                    F[v + h] &= ~run;
                }
                m &= ~run;
                *q++ = make_quad(line | uint32_t(u0) | uint32_t(w - 1) << 10 | uint32_t(h - 1) << 15, ids[id0]);
            }
        }
    }
    return q;
}

// Which faces of a slice to emit: bit 0 the negative faces, bit 1 the positive ones.
constexpr uint32_t kNegative = 1, kPositive = 2, kBoth = 3;

// Slice (axis, plane): negative faces of layer `plane`, then positive faces of layer plane - 1
// (always in this order: remeshing finds where the positive faces start by a binary search).
template <class E, bool kMulti>
Quad* emit_slice(const ChunkView& cv, const AxisRows& a, int axis, int plane, uint32_t dirs, Quad* q) {
    uint32_t F[kChunkSize];
    const uint32_t base = uint32_t(plane) << 20 | uint32_t(axis) << 26;
    if (plane < kChunkSize && (dirs & kNegative))
        if (const uint32_t lines = face_mask<E>(cv, a, axis, plane, false, F))
            q = merge_plane<E, kMulti>(cv, a, F, lines, plane, base, q);
    if (plane > 0 && (dirs & kPositive))
        if (const uint32_t lines = face_mask<E>(cv, a, axis, plane - 1, true, F))
            q = merge_plane<E, kMulti>(cv, a, F, lines, plane - 1, base | 1u << 28, q);
    return q;
}

using SliceFn = Quad* (*)(const ChunkView&, const AxisRows&, int, int, uint32_t, Quad*);

SliceFn slice_fn(const ChunkView& cv) {
    if (!cv.multi)
        return emit_slice<uint8_t, false>; // Entries are never read.
    return cv.wide() ? emit_slice<uint16_t, true> : emit_slice<uint8_t, true>;
}

// Row r of 1-bit palette indices.
inline uint32_t bit_row(const uint64_t* words, int r) { return uint32_t(words[r >> 1] >> ((r & 1) * 32)); }

} // namespace

namespace mesher_detail {
struct MesherScratch {
    std::vector<uint8_t> flags;
    // Masks per axis, lines of a layer together (index layer * 32 + line); remesh rows likewise.
    struct Masks {
        uint32_t n[kRows], o[kRows], t[kRows];
    } m[3];
    uint32_t rn[3 * kChunkSize], ro[3 * kChunkSize], rt[3 * kChunkSize];
    uint32_t bits[kRows];
    alignas(64) uint8_t d8[kPad + kChunkVolume], dt8[kPad + kChunkVolume], r8[kPad + 3 * kRows];
    alignas(64) uint16_t d16[kPad + kChunkVolume], dt16[kPad + kChunkVolume], r16[kPad + 3 * kRows];
    Quad quads[2 * kRows]; // One slice: at most a negative and a positive face per position.
};
} // namespace mesher_detail

struct GreedyMesher::Scratch : MesherScratch {};

GreedyMesher::GreedyMesher() : m_scratch(new Scratch) {
    std::memset(m_scratch->d8, 0, kPad), std::memset(m_scratch->dt8, 0, kPad), std::memset(m_scratch->r8, 0, kPad);
    std::fill_n(m_scratch->d16, kPad, 0), std::fill_n(m_scratch->dt16, kPad, 0), std::fill_n(m_scratch->r16, kPad, 0);
}
GreedyMesher::~GreedyMesher() { delete m_scratch; }

namespace {

// Rows of the whole chunk on all three axes: [2] Z planes (layer z, line y) and [1] Y planes
// (layer y, line z) from the rows along x; [0] X planes (layer x, line z) from rows along y.
template <class E> void entry_axes(const ChunkView& cv, E* d, E* dt, const RowMasks m[3], AxisRows ax[3]) {
    if constexpr (sizeof(E) == 1)
        unpack_chunk8(cv.pal->indices, kRows, d);
    else
        unpack_rows16(cv.pal->indices, 0, kRows, d);
    transpose_slabs(d, dt);
    entry_row_masks(cv, d, kRows, m[2], &m[1]);
    entry_row_masks(cv, dt, kRows, m[0], nullptr);
    ax[2].ent = ax[1].ent = d;
    ax[0].ent = dt;
}

} // namespace

void GreedyMesher::mesh(const MesherInput& in, ChunkMesh& out) {
    Scratch& s = *m_scratch;
    const ChunkView cv = make_view(in, s.flags);
    out.begin(0);
    if (cv.chunk->is_empty()) {
        for (int i = 0; i < kSliceCount; ++i)
            out.begin_slice(i);
        out.end();
        return;
    }
    RowMasks m[3];
    AxisRows ax[3];
    for (int a = 0; a < 3; ++a) {
        auto& sm = s.m[a];
        m[a] = {sm.n, sm.o, sm.t, a != 2};
        ax[a] = {sm.n, sm.o, sm.t, nullptr, 0, a == 2 ? kChunkSize : 1, a == 2 ? 1 : kChunkSize};
    }
    if (!cv.pal) {
        for (const RowMasks& rm : m)
            uniform_row_masks(cv, kRows, rm);
    } else if (cv.bits == 1 && !cv.multi) {
        // One-bit palettes: the packed words are the rows; transposed per slab for the X planes.
        std::memcpy(s.bits, cv.pal->indices.words(), sizeof s.bits);
        bit_row_masks(cv, s.bits, kRows, m[2]);
        bit_row_masks(cv, s.bits, kRows, m[1]);
        for (int z = 0; z < kChunkSize; ++z)
            transpose32(s.bits + z * kChunkSize);
        bit_row_masks(cv, s.bits, kRows, m[0]);
    } else if (!cv.wide()) {
        entry_axes(cv, s.d8 + kPad, s.dt8 + kPad, m, ax);
    } else {
        entry_axes(cv, s.d16 + kPad, s.dt16 + kPad, m, ax);
    }
    const SliceFn emit = slice_fn(cv);
    for (int axis = 0; axis < 3; ++axis)
        for (int plane = 0; plane < kPlanesPerAxis; ++plane) {
            out.begin_slice(slice_index(axis, plane));
            const Quad* end = emit(cv, ax[axis], axis, plane, kBoth, s.quads);
            out.append({s.quads, size_t(end - s.quads)});
        }
    out.end();
}

namespace {

// X layers l0, l0 + 1, l0 + 2: entries l0.. of row r = z * 32 + y go to out[k * 1024 + r] (line
// v = z, entry y). Every row starts on a byte, so entry l0 has the same bit offset in all rows.
// Always three: past the chunk's last layer the values are unused (the buffer holds three).
template <int B> void column_entries(const PackedArray& idx, int l0, uint8_t* out) {
    constexpr uint32_t kMask = (1u << B) - 1;
    const int off = (l0 * B) & 7;
    const auto* bytes = reinterpret_cast<const uint8_t*>(idx.words()) + (l0 * B >> 3);
    for (int r = 0; r < kRows; ++r, bytes += 4 * B) {
        uint32_t w;
        std::memcpy(&w, bytes, 4); // 7 + 3 * 8 bits at most; within the array's padding word.
        w >>= off;
        out[r] = uint8_t(w & kMask);
        out[kRows + r] = uint8_t((w >> B) & kMask);
        out[2 * kRows + r] = uint8_t((w >> (2 * B)) & kMask);
    }
}

// Entry rows of layers l0..l0 + count - 1 on one axis (rows layer * 32 + line), unpacked
// straight from the packed indices: whole rows for Z and Y layers, a few entries per row for X.
void layer_entries(const PackedArray& idx, int axis, int l0, int count, uint8_t* out) {
    if (axis == 2) {
        unpack_rows8(idx, l0 * kChunkSize, count * kChunkSize, out);
        return;
    }
    if (axis == 1) {
        for (int k = 0; k < count; ++k) // Layer y: rows z * 32 + y.
            unpack_rows8(idx, l0 + k, kChunkSize, out + k * kRows, kChunkSize);
        return;
    }
    switch (idx.bits()) {
    case 1: column_entries<1>(idx, l0, out); break;
    case 2: column_entries<2>(idx, l0, out); break;
    case 3: column_entries<3>(idx, l0, out); break;
    case 4: column_entries<4>(idx, l0, out); break;
    case 5: column_entries<5>(idx, l0, out); break;
    case 6: column_entries<6>(idx, l0, out); break;
    case 7: column_entries<7>(idx, l0, out); break;
    default: column_entries<8>(idx, l0, out); break;
    }
}

void layer_entries(const PackedArray& idx, int axis, int l0, int count, uint16_t* out) {
    for (int k = 0; k < count; ++k)
        for (int v = 0; v < kChunkSize; ++v)
            for (int u = 0; u < kChunkSize; ++u)
                *out++ = uint16_t(idx.get(uint32_t(local_index(plane_to_local(axis, l0 + k, u, v)))));
}

// Remeshes planes lo..lo + 1 (or lo alone) of one axis from the layers they touch: of plane
// lo + k only the faces that bits 2k (negative) and 2k + 1 (positive) of `dirs` select; the other
// faces of a slice it touches are kept from `mesh`.
void remesh_planes(MesherScratch& s, const ChunkView& cv, int axis, int lo, uint32_t dirs, ChunkMesh& mesh) {
    if (!dirs)
        return;
    const int first = lo + ((dirs & kBoth) ? 0 : 1), last = lo + ((dirs >> 2) ? 1 : 0);
    const int l0 = std::max(first - 1, 0), count = std::min(last, kChunkSize - 1) - l0 + 1;
    const RowMasks r{s.rn, s.ro, s.rt};
    AxisRows a{s.rn, s.ro, s.rt, nullptr, l0, kChunkSize, 1};
    if (!cv.pal) {
        uniform_row_masks(cv, count * kChunkSize, r);
    } else if (cv.bits == 1 && !cv.multi) {
        const uint64_t* w = cv.pal->indices.words();
        uint32_t* b = s.bits;
        uint32_t slab[kChunkSize];
        for (int l = l0; l < l0 + count; ++l)
            for (int v = 0; v < kChunkSize; ++v) {
                if (axis == 2) {
                    *b++ = bit_row(w, l * kChunkSize + v);
                } else if (axis == 1) {
                    *b++ = bit_row(w, v * kChunkSize + l);
                } else {
                    std::memcpy(slab, w + v * kChunkSize / 2, sizeof slab); // Rows of slab z = v.
                    *b++ = column_bits(slab, l);
                }
            }
        bit_row_masks(cv, s.bits, count * kChunkSize, r);
    } else if (!cv.wide()) {
        layer_entries(cv.pal->indices, axis, l0, count, s.r8 + kPad);
        entry_row_masks(cv, s.r8 + kPad, count * kChunkSize, r, nullptr);
        a.ent = s.r8 + kPad;
    } else {
        layer_entries(cv.pal->indices, axis, l0, count, s.r16 + kPad);
        entry_row_masks(cv, s.r16 + kPad, count * kChunkSize, r, nullptr);
        a.ent = s.r16 + kPad;
    }
    const SliceFn emit = slice_fn(cv);
    for (int plane = first; plane <= last; ++plane) {
        const uint32_t d = (dirs >> (2 * (plane - lo))) & kBoth;
        if (!d)
            continue;
        const int si = slice_index(axis, plane);
        const std::span<const Quad> quads{s.quads, size_t(emit(cv, a, axis, plane, d, s.quads) - s.quads)};
        if (d == kBoth) {
            mesh.replace_slice(si, quads);
            continue;
        }
        // The slice holds its negative faces first (emit_slice); the unchanged side stays.
        const std::span<const Quad> old = mesh.slice(si);
        const uint32_t split = uint32_t(
            std::partition_point(old.begin(), old.end(), [](const Quad& x) { return !x.positive(); }) - old.begin());
        if (d == kNegative)
            mesh.replace_slice_range(si, 0, split, quads);
        else
            mesh.replace_slice_range(si, split, uint32_t(old.size()), quads);
    }
}

// The block at (layer, u, v) of planes perpendicular to `axis`; layers -1 and 32 are the apron.
BlockId block_at(const MesherInput& in, int axis, int layer, int u, int v) {
    if (layer >= 0 && layer < kChunkSize)
        return in.chunk.get(plane_to_local(axis, layer, u, v));
    return in.apron.ids[int(make_face(axis, layer >= kChunkSize))][u + kChunkSize * v];
}

// One face of a plane side: shown or not, and the block it belongs to.
struct Cell {
    bool shown = false;
    BlockId id = kAir;
};

// Whether a face `c` shown at (u, v) on the side of layer `layer` facing layer + d has no face of
// its id beside it in the plane: then the greedy merge makes it a 1 x 1 quad and no other quad
// depends on it (no run reaches through it, none grows into or out of it).
bool alone(const MesherInput& in, int axis, int layer, int d, int u, int v, Cell c) {
    const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
    for (int k = 0; k < 4; ++k) {
        const int nu = u + du[k], nv = v + dv[k];
        if (nu < 0 || nu >= kChunkSize || nv < 0 || nv >= kChunkSize)
            continue;
        if (block_at(in, axis, layer, nu, nv) == c.id &&
            face_visible(c.id, block_at(in, axis, layer + d, nu, nv), in.registry))
            return false;
    }
    return true;
}

// The order merge_plane emits one side's quads in: by line v, 1 x 1 quads first, then by u.
inline uint32_t quad_order(const Quad& q) {
    const bool big = (q.packed & (0x3ffu << 10)) != 0; // Width or height above 1.
    return uint32_t(q.v0()) << 6 | uint32_t(big) << 5 | uint32_t(q.u0());
}

// Replaces the 1 x 1 quad of face (u, v) on one side of slice (axis, plane): `was` out, `is` in,
// at the place a merge would give it (so an edit and its undo restore the slice exactly).
// False (nothing changed) when the mesh lacks the quad `was` says it holds.
bool replace_cell(ChunkMesh& mesh, int axis, int plane, bool positive, int u, int v, Cell was, Cell is) {
    const int si = slice_index(axis, plane);
    const uint32_t packed = uint32_t(u) | uint32_t(v) << 5 | uint32_t(plane) << 20 | uint32_t(axis) << 26 |
                            uint32_t(positive) << 28;
    const std::span<const Quad> old = mesh.slice(si);
    // The slice holds its negative faces first (emit_slice), each side in quad_order.
    const auto split = std::partition_point(old.begin(), old.end(), [](const Quad& x) { return !x.positive(); });
    const auto begin = positive ? split : old.begin(), end = positive ? old.end() : split;
    const uint32_t key = uint32_t(v) << 6 | uint32_t(u);
    const auto at = std::partition_point(begin, end, [key](const Quad& x) { return quad_order(x) < key; });
    const uint32_t k = uint32_t(at - old.begin());
    const Quad add = make_quad(packed, is.id);
    const uint32_t n_add = is.shown ? 1u : 0u;
    if (!was.shown) {
        mesh.replace_slice_range(si, k, k, {&add, n_add});
        return true;
    }
    if (at == end || !(*at == make_quad(packed, was.id)))
        return false;
    mesh.replace_slice_range(si, k, k + 1, {&add, n_add});
    return true;
}

// After block p changed from `old` to its id in the chunk, updates the sides of planes p[axis]
// and p[axis] + 1 whose face at or towards p changed and stays alone in the plane (one quad in or
// out: most faces of noisy or checkered chunks), and returns the sides that changed otherwise, as
// remesh_planes' `dirs`. Only p's faces and the faces towards p change, one per plane side; a
// side whose face there keeps its presence and its block id keeps its quads.
// `changed` gets every side whose face changed (swapped in place or returned for a merge).
uint32_t update_cells(const MesherInput& in, LocalPos p, BlockId old, int axis, ChunkMesh& mesh, uint32_t* changed) {
    const BlockRegistry& r = in.registry;
    const BlockId now = in.chunk.get(p);
    const int l = p[axis], u = p[plane_u_axis(axis)], v = p[plane_v_axis(axis)];
    uint32_t dirs = 0;
    for (uint32_t b = 0; b < 4; ++b) {
        // Side b: plane l + b / 2, faces of `layer` towards layer + d (positive when b is odd).
        const bool positive = b & 1;
        const int plane = l + int(b >> 1), layer = positive ? plane - 1 : plane, d = positive ? 1 : -1;
        if (layer < 0 || layer >= kChunkSize)
            continue;
        Cell was, is;
        if (layer == l) { // p's own face.
            const BlockId across = block_at(in, axis, layer + d, u, v);
            was = {face_visible(old, across, r), old};
            is = {face_visible(now, across, r), now};
        } else { // The neighbour's face towards p.
            const BlockId id = block_at(in, axis, layer, u, v);
            was = {face_visible(id, old, r), id};
            is = {face_visible(id, now, r), id};
        }
        if (was.shown == is.shown && (!is.shown || was.id == is.id))
            continue;
        *changed |= 1u << b;
        const bool local = (!was.shown || alone(in, axis, layer, d, u, v, was)) &&
                           (!is.shown || alone(in, axis, layer, d, u, v, is));
        if (!local || !replace_cell(mesh, axis, plane, positive, u, v, was, is))
            dirs |= 1u << b;
    }
    return dirs;
}

} // namespace

void GreedyMesher::remesh_slice(const MesherInput& in, int axis, int plane, ChunkMesh& mesh) {
    const ChunkView cv = make_view(in, m_scratch->flags);
    remesh_planes(*m_scratch, cv, axis, plane, kBoth, mesh);
}

void GreedyMesher::remesh_block(const MesherInput& in, LocalPos p, ChunkMesh& mesh) {
    const ChunkView cv = make_view(in, m_scratch->flags);
    for (int axis = 0; axis < 3; ++axis)
        remesh_planes(*m_scratch, cv, axis, p[axis], kBoth | kBoth << 2, mesh);
}

uint32_t GreedyMesher::remesh_block(const MesherInput& in, LocalPos p, BlockId old, ChunkMesh& mesh) {
    const ChunkView cv = make_view(in, m_scratch->flags);
    uint32_t changed = 0;
    for (int axis = 0; axis < 3; ++axis) {
        uint32_t sides = 0; // Sides (as update_cells' bits) that changed, in place or merged again.
        const uint32_t dirs = update_cells(in, p, old, axis, mesh, &sides);
        remesh_planes(*m_scratch, cv, axis, p[axis], dirs, mesh);
        changed |= ((sides & 3u) != 0 ? 1u : 0u) << (2 * axis) | ((sides & 12u) != 0 ? 1u : 0u) << (2 * axis + 1);
    }
    return changed;
}

} // namespace vx::world
