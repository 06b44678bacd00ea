#include "world/gen/noise.h"

#include "world/base/assert.h"

namespace vx::world::noise {

namespace {

constexpr uint64_t kSeedMul = 0xD6E8FEB86659FD93ull;
constexpr uint64_t kXMul = 0x9E3779B97F4A7C15ull;
constexpr uint64_t kYMul = 0xC2B2AE3D27D4EB4Full;
constexpr uint64_t kZMul = 0x165667B19E3779F9ull;

// Perlin's quintic fade: C2-continuous blending, so the noise has no visible lattice creases.
inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float lerp(float a, float b, float t) { return a + t * (b - a); }

// Eight unit directions, 45° apart.
constexpr float kDiag = 0.70710678f;
constexpr float kGrad2[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {kDiag, kDiag}, {-kDiag, kDiag}, {kDiag, -kDiag}, {-kDiag, -kDiag}};

inline float grad2(uint64_t h, float x, float z) {
    const float* g = kGrad2[h & 7];
    return g[0] * x + g[1] * z;
}

// Perlin 2002: the twelve cube-edge directions, four of them repeated to make sixteen, so a
// 4-bit index picks one without bias towards any axis.
constexpr int8_t kGrad3[16][3] = {{1, 1, 0},  {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                  {1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1},  {0, 1, -1}, {0, -1, -1},
                                  {1, 1, 0},  {0, -1, 1}, {-1, 1, 0}, {0, -1, -1}};

inline float grad3(unsigned index, float x, float y, float z) {
    const int8_t* g = kGrad3[index & 15];
    return float(g[0]) * x + float(g[1]) * y + float(g[2]) * z;
}

// Block coordinate -> lattice cell and exact fraction for wavelength 2^shift.
inline int64_t cell_of(int64_t v, int shift) { return v >> shift; } // Arithmetic shift floors.
inline float frac_of(int64_t v, int shift) {
    return float(v & ((int64_t(1) << shift) - 1)) * (1.0f / float(int64_t(1) << shift));
}

} // namespace

float gradient_2d(uint64_t seed, int64_t cx, int64_t cz, float fx, float fz) {
    const uint64_t s = seed * kSeedMul;
    const uint64_t x0 = uint64_t(cx) * kXMul, x1 = uint64_t(cx + 1) * kXMul;
    const uint64_t z0 = uint64_t(cz) * kZMul, z1 = uint64_t(cz + 1) * kZMul;
    const float n00 = grad2(mix64(s ^ x0 ^ z0), fx, fz);
    const float n10 = grad2(mix64(s ^ x1 ^ z0), fx - 1.0f, fz);
    const float n01 = grad2(mix64(s ^ x0 ^ z1), fx, fz - 1.0f);
    const float n11 = grad2(mix64(s ^ x1 ^ z1), fx - 1.0f, fz - 1.0f);
    const float u = fade(fx), v = fade(fz);
    // With unit gradients the 2D extremes are about ±0.71; scale to about ±1.
    return 1.4142135f * lerp(lerp(n00, n10, u), lerp(n01, n11, u), v);
}

namespace {

// The eight corner hashes of a lattice cell, x fastest.
void corner_hashes(uint64_t seed, int64_t cx, int64_t cy, int64_t cz, uint64_t h[8]) {
    const uint64_t s = seed * kSeedMul;
    const uint64_t xs[2] = {uint64_t(cx) * kXMul, uint64_t(cx + 1) * kXMul};
    const uint64_t ys[2] = {uint64_t(cy) * kYMul, uint64_t(cy + 1) * kYMul};
    const uint64_t zs[2] = {uint64_t(cz) * kZMul, uint64_t(cz + 1) * kZMul};
    for (int k = 0; k < 8; ++k)
        h[k] = mix64(s ^ xs[k & 1] ^ ys[(k >> 1) & 1] ^ zs[k >> 2]);
}

// The pair from a cell's corner hashes; the single evaluation path for gradient_3d_pair and
// the grid version, so both give the same bits.
Noise3Pair pair_from_hashes(const uint64_t h[8], float fx, float fy, float fz) {
    float a[8], b[8];
    for (int k = 0; k < 8; ++k) {
        const float x = fx - float(k & 1), y = fy - float((k >> 1) & 1), z = fz - float(k >> 2);
        a[k] = grad3(unsigned(h[k]), x, y, z);
        b[k] = grad3(unsigned(h[k] >> 4), x, y, z);
    }
    const float u = fade(fx), v = fade(fy), w = fade(fz);
    auto blend = [&](const float* n) {
        const float y0 = lerp(lerp(n[0], n[1], u), lerp(n[2], n[3], u), v);
        const float y1 = lerp(lerp(n[4], n[5], u), lerp(n[6], n[7], u), v);
        return lerp(y0, y1, w);
    };
    return {blend(a), blend(b)};
}

} // namespace

Noise3Pair gradient_3d_pair(uint64_t seed, int64_t cx, int64_t cy, int64_t cz, float fx, float fy, float fz) {
    uint64_t h[8];
    corner_hashes(seed, cx, cy, cz, h);
    return pair_from_hashes(h, fx, fy, fz);
}

float gradient_2d_at(uint64_t seed, int64_t x, int64_t z, int shift) {
    VX_DEBUG_ASSERT(shift >= 1 && shift <= 30);
    return gradient_2d(seed, cell_of(x, shift), cell_of(z, shift), frac_of(x, shift), frac_of(z, shift));
}

float fbm_2d_at(uint64_t seed, int64_t x, int64_t z, int shift, int octaves, float gain) {
    VX_DEBUG_ASSERT(shift - octaves + 1 >= 1);
    float sum = 0.0f, amp = 1.0f, norm = 0.0f;
    for (int o = 0; o < octaves; ++o) {
        // A per-octave integer offset (exact) decorrelates the octaves' lattices.
        const uint64_t h = hash_coords(seed, o, 0x6F63);
        const int64_t ox = int64_t(h & 0xFFFFF), oz = int64_t((h >> 20) & 0xFFFFF);
        sum += amp * gradient_2d_at(seed + uint64_t(o), x + ox, z + oz, shift - o);
        norm += amp;
        amp *= gain;
    }
    return sum / norm;
}

Noise3Pair gradient_3d_pair_at(uint64_t seed, int64_t x, int64_t y, int64_t z, int shift_xz, int shift_y) {
    VX_DEBUG_ASSERT(shift_xz >= 1 && shift_xz <= 30 && shift_y >= 1 && shift_y <= 30);
    return gradient_3d_pair(seed, cell_of(x, shift_xz), cell_of(y, shift_y), cell_of(z, shift_xz), frac_of(x, shift_xz),
                            frac_of(y, shift_y), frac_of(z, shift_xz));
}

void gradient_3d_pair_grid(uint64_t seed, int64_t x0, int64_t y0, int64_t z0, int step, int nx, int ny, int nz,
                           int shift_xz, int shift_y, Noise3Pair* out) {
    VX_DEBUG_ASSERT(shift_xz >= 1 && shift_xz <= 30 && shift_y >= 1 && shift_y <= 30 && step > 0);
    uint64_t h[8];
    int64_t hx = 0, hy = 0, hz = 0;
    bool have = false;
    for (int k = 0; k < nz; ++k) {
        const int64_t z = z0 + int64_t(step) * k;
        for (int j = 0; j < ny; ++j) {
            const int64_t y = y0 + int64_t(step) * j;
            for (int i = 0; i < nx; ++i) {
                const int64_t x = x0 + int64_t(step) * i;
                const int64_t cx = cell_of(x, shift_xz), cy = cell_of(y, shift_y), cz = cell_of(z, shift_xz);
                // Neighbouring samples mostly share a cell: hash its corners once.
                if (!have || cx != hx || cy != hy || cz != hz) {
                    corner_hashes(seed, cx, cy, cz, h);
                    hx = cx, hy = cy, hz = cz;
                    have = true;
                }
                *out++ = pair_from_hashes(h, frac_of(x, shift_xz), frac_of(y, shift_y), frac_of(z, shift_xz));
            }
        }
    }
}

} // namespace vx::world::noise
