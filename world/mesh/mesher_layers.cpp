#include "world/mesh/mesher_layers.h"

#include <algorithm>
#include <bit>

namespace vx::world::mesher_detail {

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
    case 1: return extract_layer_fixed<1>;
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

} // namespace vx::world::mesher_detail
