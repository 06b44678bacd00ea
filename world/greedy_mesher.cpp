#include "world/mesher.h"

#include <algorithm>
#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace vx::world {
namespace {

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

uint8_t block_flags(BlockId id, const BlockRegistry& r) {
    if (id == kAir)
        return 0;
    return r.is_opaque(id) ? uint8_t(kNonAir | kOpaque) : uint8_t(kNonAir | kTransparent);
}

// 32×32 bit-matrix transpose, bit j of row i moves to bit i of row j (LSB-first variant of
// Hacker's Delight 7-3: swap ever smaller off-diagonal blocks).
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

// Bits of 32 consecutive entries (along x) starting at local index i0.
inline void row_bits_x(const ChunkView& cv, uint32_t i0, uint32_t& n, uint32_t& o, uint32_t& t) {
    const PackedArray& idx = cv.pal->indices;
    if (idx.bits() == 1) {
        // One bit per block: the 32 indices are the row itself.
        const uint32_t row = uint32_t(idx.words()[i0 >> 6] >> (i0 & 63));
        const uint8_t f0 = cv.flags[0], f1 = cv.flags[1];
        auto sel = [&](uint8_t bit) {
            return ((f0 & bit) ? ~row : 0u) | ((f1 & bit) ? row : 0u);
        };
        n = sel(kNonAir), o = sel(kOpaque), t = sel(kTransparent);
        return;
    }
    // Stream the packed bits through a 64-bit window.
    const uint32_t bits = idx.bits();
    const uint64_t mask = (uint64_t(1) << bits) - 1;
    const uint64_t* w = idx.words();
    uint64_t pos = uint64_t(i0) * bits;
    uint32_t rn = 0, ro = 0, rt = 0;
    for (uint32_t x = 0; x < uint32_t(kChunkSize); ++x, pos += bits) {
        const uint64_t* p = w + (pos >> 6);
        const uint32_t off = uint32_t(pos & 63);
        const uint32_t e = uint32_t(((p[0] >> off) | ((p[1] << 1) << (63 - off))) & mask);
        const uint32_t f = cv.flags[e];
        rn |= (f & 1u) << x;
        ro |= ((f >> 1) & 1u) << x;
        rt |= ((f >> 2) & 1u) << x;
    }
    n = rn, o = ro, t = rt;
}

// One layer's bits read straight from the chunk (for incremental remeshing).
void extract_layer(const ChunkView& cv, int axis, int layer, LayerBits& out) {
    if (!cv.pal) {
        const uint8_t f = cv.uniform_flags;
        std::fill_n(out.n, kChunkSize, (f & kNonAir) ? ~0u : 0u);
        std::fill_n(out.o, kChunkSize, (f & kOpaque) ? ~0u : 0u);
        std::fill_n(out.t, kChunkSize, (f & kTransparent) ? ~0u : 0u);
        return;
    }
    if (axis != 0) {
        // Rows run along x (u = x): contiguous indices.
        for (uint32_t v = 0; v < uint32_t(kChunkSize); ++v)
            row_bits_x(cv, uint32_t(layer) * kLayerStep[axis] + v * kVStep[axis], out.n[v], out.o[v], out.t[v]);
        return;
    }
    const PackedArray& idx = cv.pal->indices;
    for (uint32_t v = 0; v < uint32_t(kChunkSize); ++v) {
        uint32_t rn = 0, ro = 0, rt = 0;
        uint32_t i = uint32_t(layer) + v * kVStep[0];
        for (uint32_t u = 0; u < uint32_t(kChunkSize); ++u, i += kUStep[0]) {
            const uint32_t f = cv.flags[idx.get(i)];
            rn |= (f & 1u) << u;
            ro |= ((f >> 1) & 1u) << u;
            rt |= ((f >> 2) & 1u) << u;
        }
        out.n[v] = rn, out.o[v] = ro, out.t[v] = rt;
    }
}

// Unpacks B-bit palette indices to bytes. 64 entries of B bits fill exactly B words, so every
// shift below is a compile-time constant once the inner loop is unrolled.
template <int B> void unpack_fixed(const uint64_t* w, uint8_t* out) {
    constexpr uint64_t kMask = (uint64_t(1) << B) - 1;
    for (int g = 0; g < kChunkVolume / 64; ++g, w += B, out += 64) {
#pragma GCC unroll 64
        for (int k = 0; k < 64; ++k) {
            const int bit = k * B, word = bit >> 6, off = bit & 63;
            uint64_t v = w[word] >> off;
            if (off + B > 64)
                v |= w[word + 1] << (64 - off);
            out[k] = uint8_t(v & kMask);
        }
    }
}

bool unpack_indices(const PackedArray& a, uint8_t* out) {
    switch (a.bits()) {
    case 1: unpack_fixed<1>(a.words(), out); return true;
    case 2: unpack_fixed<2>(a.words(), out); return true;
    case 3: unpack_fixed<3>(a.words(), out); return true;
    case 4: unpack_fixed<4>(a.words(), out); return true;
    case 5: unpack_fixed<5>(a.words(), out); return true;
    case 6: unpack_fixed<6>(a.words(), out); return true;
    case 7: unpack_fixed<7>(a.words(), out); return true;
    case 8: unpack_fixed<8>(a.words(), out); return true;
    default: return false;
    }
}

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

// Masks of one row of 32 unpacked indices: a compare per air entry (non-air = none of them)
// and, only when some non-air entry is not opaque, a compare per opaque entry.
inline void row_bits_dense(const ChunkView& cv, const uint8_t* row, uint32_t& n, uint32_t& o, uint32_t& t) {
    uint32_t a = 0;
    for (int k = 0; k < cv.n_air; ++k)
        a |= eq_mask(row, cv.air_entries[k]);
    n = ~a;
    o = n;
    if (!cv.all_opaque) {
        o = 0;
        for (int k = 0; k < cv.n_opaque; ++k)
            o |= eq_mask(row, cv.opaque_entries[k]);
    }
    t = n & ~o;
}

void dense_rows(const ChunkView& cv, LayerBits* lz) {
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < kChunkSize; ++y)
            row_bits_dense(cv, cv.dense + z * kChunkSize * kChunkSize + y * kChunkSize, lz[z].n[y], lz[z].o[y],
                           lz[z].t[y]);
}

static_assert(std::endian::native == std::endian::little, "row unpacking reads packed words as bytes");

// Unpacks the 32 B-bit indices of the row starting at i0 (a multiple of 32, so the row starts
// on a 32-bit boundary and all shifts are constants).
template <int B> inline void unpack_row(const uint64_t* w, uint32_t i0, uint8_t* out) {
    uint64_t buf[6] = {};
    // 4B bytes of row plus 8 bytes: within the array's padding word at the very end.
    std::memcpy(buf, reinterpret_cast<const char*>(w) + size_t(i0) * B / 8, 4 * B + 8);
    constexpr uint64_t kMask = (uint64_t(1) << B) - 1;
#pragma GCC unroll 32
    for (int k = 0; k < kChunkSize; ++k) {
        const int bit = k * B, word = bit >> 6, off = bit & 63;
        uint64_t v = buf[word] >> off;
        if (off + B > 64)
            v |= buf[word + 1] << (64 - off);
        out[k] = uint8_t(v & kMask);
    }
}

template <int B> inline uint32_t get_fixed(const uint64_t* w, uint32_t i) {
    const uint32_t pos = i * B, off = pos & 63;
    const uint64_t* p = w + (pos >> 6);
    return uint32_t(((p[0] >> off) | ((p[1] << 1) << (63 - off))) & ((uint64_t(1) << B) - 1));
}

// One layer for incremental remeshing: unpacks its indices into `dense` (at their chunk
// indices, for the merge's id compares) and builds its bits.
template <int B> void extract_layer_fixed(const ChunkView& cv, int axis, int layer, uint8_t* dense, LayerBits& out) {
    const uint64_t* w = cv.pal->indices.words();
    if (axis != 0) {
        for (uint32_t v = 0; v < uint32_t(kChunkSize); ++v) {
            const uint32_t i0 = uint32_t(layer) * kLayerStep[axis] + v * kVStep[axis];
            unpack_row<B>(w, i0, dense + i0);
            row_bits_dense(cv, dense + i0, out.n[v], out.o[v], out.t[v]);
        }
        return;
    }
    for (uint32_t v = 0; v < uint32_t(kChunkSize); ++v) {
        uint32_t rn = 0, ro = 0, rt = 0;
        uint32_t i = uint32_t(layer) + v * kVStep[0];
        for (uint32_t u = 0; u < uint32_t(kChunkSize); ++u, i += kUStep[0]) {
            const uint32_t e = get_fixed<B>(w, i);
            dense[i] = uint8_t(e);
            const uint32_t f = cv.flags[e];
            rn |= (f & 1u) << u;
            ro |= ((f >> 1) & 1u) << u;
            rt |= ((f >> 2) & 1u) << u;
        }
        out.n[v] = rn, out.o[v] = ro, out.t[v] = rt;
    }
}

using ExtractFn = void (*)(const ChunkView&, int, int, uint8_t*, LayerBits&);
ExtractFn extract_fixed_for(uint32_t bits) {
    switch (bits) {
    case 2: return extract_layer_fixed<2>;
    case 3: return extract_layer_fixed<3>;
    case 4: return extract_layer_fixed<4>;
    case 5: return extract_layer_fixed<5>;
    case 6: return extract_layer_fixed<6>;
    case 7: return extract_layer_fixed<7>;
    case 8: return extract_layer_fixed<8>;
    default: return nullptr;
    }
}

// All 3×32 layers at once: rows along x are read once, the X layers come from transposes.
void extract_all_layers(const ChunkView& cv, LayerBits (*layers)[kChunkSize]) {
    LayerBits* lz = layers[2];
    if (!cv.pal) {
        for (int l = 0; l < kChunkSize; ++l)
            extract_layer(cv, 2, l, lz[l]);
    } else if (cv.dense) {
        dense_rows(cv, lz);
    } else {
        for (uint32_t z = 0; z < uint32_t(kChunkSize); ++z)
            for (uint32_t y = 0; y < uint32_t(kChunkSize); ++y)
                row_bits_x(cv, z * kVStep[1] + y * kChunkSize, lz[z].n[y], lz[z].o[y], lz[z].t[y]);
    }
    // Y layer y, row z = Z layer z, row y (both have u = x).
    for (int y = 0; y < kChunkSize; ++y)
        for (int z = 0; z < kChunkSize; ++z) {
            layers[1][y].n[z] = lz[z].n[y];
            layers[1][y].o[z] = lz[z].o[y];
            layers[1][y].t[z] = lz[z].t[y];
        }
    // X layer x, row z, bit y = Z layer z, row y, bit x: a bit transpose per z.
    uint32_t tn[kChunkSize], to[kChunkSize], tt[kChunkSize];
    for (int z = 0; z < kChunkSize; ++z) {
        std::memcpy(tn, lz[z].n, sizeof tn);
        std::memcpy(to, lz[z].o, sizeof to);
        transpose32(tn);
        transpose32(to);
        if (cv.transparent) {
            std::memcpy(tt, lz[z].t, sizeof tt);
            transpose32(tt);
        }
        for (int x = 0; x < kChunkSize; ++x) {
            layers[0][x].n[z] = tn[x];
            layers[0][x].o[z] = to[x];
            layers[0][x].t[z] = cv.transparent ? tt[x] : 0u;
        }
    }
}

// Removes from `mask` the faces between two blocks of one transparent id.
void hide_same_transparent(const ChunkView& cv, int axis, int block_layer, const LayerBits* neighbour,
                           Face apron_face, uint32_t mask[kChunkSize]) {
    const uint32_t base = uint32_t(block_layer) * kLayerStep[axis];
    const int nl = block_layer + (face_positive(apron_face) ? 1 : -1);
    for (int v = 0; v < kChunkSize; ++v) {
        uint32_t cand = neighbour ? (mask[v] & neighbour->t[v])
                                  : (cv.apron->any_transparent[int(apron_face)] ? mask[v] : 0u);
        while (cand) {
            const int u = std::countr_zero(cand);
            cand &= cand - 1;
            const BlockId a = cv.chunk->get(int(base + u * kUStep[axis] + v * kVStep[axis]));
            const BlockId b = neighbour ? cv.chunk->get(int(uint32_t(nl) * kLayerStep[axis] + u * kUStep[axis] +
                                                            v * kVStep[axis]))
                                        : cv.apron->ids[int(apron_face)][u + kChunkSize * v];
            if (a == b)
                mask[v] &= ~(1u << u);
        }
    }
}

// Greedy merge of one plane's face mask (consumed). Width first along u, then height along v.
template <bool kMulti, class Sink>
void merge_plane(const ChunkView& cv, uint32_t mask[kChunkSize], int axis, int plane, bool positive,
                 int block_layer, Sink& sink) {
    const uint32_t base = uint32_t(block_layer) * kLayerStep[axis];
    const uint32_t su = kUStep[axis], sv = kVStep[axis];
    for (int v = 0; v < kChunkSize; ++v) {
        while (mask[v]) {
            const uint32_t m = mask[v];
            const int u0 = std::countr_zero(m);
            int w = std::countr_zero(~(uint64_t(m) >> u0)); // Run of ones from u0.
            uint32_t id0 = 0;
            const uint32_t row0 = base + uint32_t(v) * sv;
            if constexpr (kMulti) {
                id0 = cv.entry(row0 + uint32_t(u0) * su);
                for (int k = 1; k < w; ++k)
                    if (cv.entry(row0 + uint32_t(u0 + k) * su) != id0) {
                        w = k;
                        break;
                    }
            }
            const uint32_t run = uint32_t((uint64_t(1) << w) - 1) << u0;
            int h = 1;
            for (; v + h < kChunkSize && (mask[v + h] & run) == run; ++h) {
                if constexpr (kMulti) {
                    const uint32_t row = base + uint32_t(v + h) * sv;
                    bool same = true;
                    for (int k = 0; k < w && same; ++k)
                        same = cv.entry(row + uint32_t(u0 + k) * su) == id0;
                    if (!same)
                        break;
                }
                mask[v + h] &= ~run;
            }
            mask[v] &= ~run;
            const BlockId block = kMulti ? cv.pal->ids[id0] : cv.single;
            sink(Quad::make(axis, plane, positive, u0, v, w, h, block));
        }
    }
}

// Emits slice (axis, plane): negative faces of layer `plane`, then positive faces of layer
// `plane - 1`. `layer(l)` returns the bits of layer l (0..31) on this axis.
template <class LayerFn, class Sink>
void emit_slice(const ChunkView& cv, int axis, int plane, LayerFn&& layer, Sink& sink) {
    uint32_t mask[kChunkSize];
    auto merge = [&](bool positive, int block_layer) {
        if (cv.split_count) {
            // Faces of different ids never merge, so merging each id's faces alone gives the
            // same quads as merging all with id compares (only the order within a slice differs).
            ChunkView one = cv;
            for (int k = 0; k < cv.split_count; ++k) {
                const uint32_t* occ = cv.split_layers[k][axis][block_layer];
                uint32_t part[kChunkSize], any = 0;
                for (int v = 0; v < kChunkSize; ++v)
                    any |= part[v] = mask[v] & occ[v];
                if (!any)
                    continue;
                one.single = cv.pal->ids[cv.split_entries[k]];
                merge_plane<false>(one, part, axis, plane, positive, block_layer, sink);
            }
        } else if (cv.multi)
            merge_plane<true>(cv, mask, axis, plane, positive, block_layer, sink);
        else
            merge_plane<false>(cv, mask, axis, plane, positive, block_layer, sink);
    };
    if (plane < kChunkSize) {
        const LayerBits& b = layer(plane);
        const Face nf = make_face(axis, false);
        const LayerBits* nb = plane > 0 ? &layer(plane - 1) : nullptr;
        const uint32_t* occ = nb ? nb->o : cv.apron->opaque[int(nf)].data();
        uint32_t any = 0;
        for (int v = 0; v < kChunkSize; ++v)
            any |= mask[v] = b.n[v] & ~occ[v];
        if (any && cv.transparent)
            hide_same_transparent(cv, axis, plane, nb, nf, mask);
        if (any)
            merge(false, plane);
    }
    if (plane > 0) {
        const LayerBits& b = layer(plane - 1);
        const Face pf = make_face(axis, true);
        const LayerBits* nb = plane < kChunkSize ? &layer(plane) : nullptr;
        const uint32_t* occ = nb ? nb->o : cv.apron->opaque[int(pf)].data();
        uint32_t any = 0;
        for (int v = 0; v < kChunkSize; ++v)
            any |= mask[v] = b.n[v] & ~occ[v];
        if (any && cv.transparent)
            hide_same_transparent(cv, axis, plane - 1, nb, pf, mask);
        if (any)
            merge(true, plane - 1);
    }
}

} // namespace

// Up to this many non-air ids, full meshes merge per id (split mode).
constexpr int kMaxSplit = 12;

// Per-entry occupancy layers on all three axes, from the unpacked indices.
void build_split_layers(ChunkView& cv, uint8_t* entries, uint32_t (*layers)[3][kChunkSize][kChunkSize]) {
    int n = 0;
    for (size_t e = 0; e < cv.pal->ids.size(); ++e)
        if (cv.pal->counts[e] && (cv.flags[e] & kNonAir))
            entries[n++] = uint8_t(e);
    for (int k = 0; k < n; ++k) {
        auto& L = layers[k];
        for (int z = 0; z < kChunkSize; ++z) {
            uint32_t rows[kChunkSize];
            for (int y = 0; y < kChunkSize; ++y) {
                rows[y] = eq_mask(cv.dense + z * kChunkSize * kChunkSize + y * kChunkSize, entries[k]);
                L[2][z][y] = rows[y];
                L[1][y][z] = rows[y];
            }
            transpose32(rows);
            for (int x = 0; x < kChunkSize; ++x)
                L[0][x][z] = rows[x];
        }
    }
    cv.split_count = n;
    cv.split_entries = entries;
    cv.split_layers = layers;
}

// Split mode costs ~4 µs per id up front and saves ~5 ns per face merged. Solid-air transitions
// along x estimate the face count; measured break-even on terrain vs 50% noise lies near 4096.
bool split_pays_off(const ChunkView& cv, const LayerBits* lz) {
    int non_air = 0;
    for (size_t e = 0; e < cv.pal->ids.size(); ++e)
        non_air += cv.pal->counts[e] && (cv.flags[e] & kNonAir);
    if (non_air > kMaxSplit)
        return false;
    int transitions = 0;
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < kChunkSize; ++y)
            transitions += std::popcount(lz[z].n[y] ^ (lz[z].n[y] << 1));
    return transitions > 4096;
}

struct GreedyMesher::Scratch {
    LayerBits layers[3][kChunkSize];
    std::vector<uint8_t> flags;
    std::vector<Quad> quads;
    alignas(64) uint8_t dense[kChunkVolume];
    uint8_t air[256], opaque[256];
    uint8_t split_entries[kMaxSplit];
    uint32_t split_layers[kMaxSplit][3][kChunkSize][kChunkSize];
    LayerBits cache[3];
    int cache_layer[3];
};

// Layer extraction for incremental remeshing: unpacking (2..8-bit indices) or generic.
struct LayerLoader {
    ChunkView& cv;
    uint8_t* dense;
    ExtractFn fixed = nullptr;
    LayerLoader(ChunkView& view, uint8_t* dense_scratch) : cv(view), dense(dense_scratch) {
        if (cv.pal && cv.air_entries)
            fixed = extract_fixed_for(cv.pal->indices.bits());
        if (fixed)
            cv.dense = dense; // Merges read ids only from layers loaded here.
    }
    void load(int axis, int layer, LayerBits& out) const {
        if (fixed)
            fixed(cv, axis, layer, dense, out);
        else
            extract_layer(cv, axis, layer, out);
    }
};

GreedyMesher::GreedyMesher() : m_scratch(new Scratch) {}
GreedyMesher::~GreedyMesher() { delete m_scratch; }

static ChunkView make_view(const MesherInput& in, std::vector<uint8_t>& flags, uint8_t* air, uint8_t* opaque) {
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
    flags.resize(p.ids.size());
    int non_air = 0;
    for (size_t e = 0; e < p.ids.size(); ++e) {
        flags[e] = block_flags(p.ids[e], in.registry);
        if (p.counts[e] == 0)
            continue;
        if (flags[e] & kNonAir) {
            ++non_air;
            cv.single = p.ids[e];
        }
        cv.transparent |= (flags[e] & kTransparent) != 0;
    }
    cv.flags = flags.data();
    cv.multi = non_air > 1;
    if (p.ids.size() <= 256) {
        for (size_t e = 0; e < p.ids.size(); ++e) {
            if (p.counts[e] == 0)
                continue;
            if (!(flags[e] & kNonAir))
                air[cv.n_air++] = uint8_t(e);
            else if (flags[e] & kOpaque)
                opaque[cv.n_opaque++] = uint8_t(e);
            else
                cv.all_opaque = false;
        }
        cv.air_entries = air;
        cv.opaque_entries = opaque;
    }
    return cv;
}

void GreedyMesher::mesh(const MesherInput& in, ChunkMesh& out) {
    Scratch& s = *m_scratch;
    ChunkView cv = make_view(in, s.flags, s.air, s.opaque);
    // One-bit palettes build masks straight from the packed words; wider ones unpack once so
    // masks come from byte compares and merging compares bytes.
    if (cv.pal && cv.pal->indices.bits() > 1 && unpack_indices(cv.pal->indices, s.dense))
        cv.dense = s.dense;
    out.begin(0);
    if (cv.chunk->is_empty()) {
        for (int i = 0; i < kSliceCount; ++i)
            out.begin_slice(i);
        out.end();
        return;
    }
    extract_all_layers(cv, s.layers);
    if (cv.dense && cv.multi && split_pays_off(cv, s.layers[2]))
        build_split_layers(cv, s.split_entries, s.split_layers);
    auto sink = [&out](const Quad& q) { out.push(q); };
    for (int axis = 0; axis < 3; ++axis) {
        auto layer = [&](int l) -> const LayerBits& { return s.layers[axis][l]; };
        for (int plane = 0; plane < kPlanesPerAxis; ++plane) {
            out.begin_slice(slice_index(axis, plane));
            emit_slice(cv, axis, plane, layer, sink);
        }
    }
    out.end();
}

void GreedyMesher::remesh_slice(const MesherInput& in, int axis, int plane, ChunkMesh& mesh) {
    Scratch& s = *m_scratch;
    ChunkView cv = make_view(in, s.flags, s.air, s.opaque);
    const LayerLoader loader(cv, s.dense);
    LayerBits* cache = s.cache;
    int loaded[2] = {-1, -1};
    auto layer = [&](int l) -> const LayerBits& {
        const int slot = l == plane ? 0 : 1;
        if (loaded[slot] != l) {
            loader.load(axis, l, cache[slot]);
            loaded[slot] = l;
        }
        return cache[slot];
    };
    s.quads.clear();
    auto sink = [&s](const Quad& q) { s.quads.push_back(q); };
    emit_slice(cv, axis, plane, layer, sink);
    mesh.replace_slice(slice_index(axis, plane), s.quads);
}

void GreedyMesher::remesh_block(const MesherInput& in, LocalPos p, ChunkMesh& mesh) {
    Scratch& s = *m_scratch;
    ChunkView cv = make_view(in, s.flags, s.air, s.opaque);
    const LayerLoader loader(cv, s.dense);
    auto sink = [&s](const Quad& q) { s.quads.push_back(q); };
    for (int axis = 0; axis < 3; ++axis) {
        // Planes c and c + 1 read layers c - 1, c and c + 1: extract each once.
        const int c = p[axis];
        int loaded[3] = {-1, -1, -1};
        auto layer = [&](int l) -> const LayerBits& {
            const int slot = l - c + 1;
            if (loaded[slot] != l) {
                loader.load(axis, l, s.cache[slot]);
                loaded[slot] = l;
            }
            return s.cache[slot];
        };
        for (int plane = c; plane <= c + 1; ++plane) {
            s.quads.clear();
            emit_slice(cv, axis, plane, layer, sink);
            mesh.replace_slice(slice_index(axis, plane), s.quads);
        }
    }
}

const char* mesher_name(MesherKind kind) {
    switch (kind) {
    case MesherKind::Greedy: return "greedy";
    case MesherKind::Culled: return "culled";
    case MesherKind::Naive: return "naive";
    }
    return "?";
}

} // namespace vx::world
