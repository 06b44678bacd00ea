// Deterministic sampling for the ray-tracing shaders, shared by GLSL and C++ (the C++ side is
// the test oracle: tests/render/sampling_test.cpp checks the pattern this exact code makes).
// Only the common subset of C++ and GLSL.
#ifndef VX_SHADERS_SAMPLING_H
#define VX_SHADERS_SAMPLING_H

#ifdef __cplusplus
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
namespace vx::render::gpu {
#define VX_S_FN inline
using s_uint = uint32_t;
using s_vec2 = glm::vec2;
using std::sqrt;
#else
#define VX_S_FN
#define s_uint uint
#define s_vec2 vec2
#endif

// A 32-bit integer hash (PCG output permutation; Jarzynski & Olano, JCGT 2020).
VX_S_FN s_uint vx_hash(s_uint v) {
    s_uint state = v * 747796405u + 2891336453u;
    s_uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Kensler, "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01 (2013):
// permute() is a hash-based permutation of [0, l) selected by pattern p.
VX_S_FN s_uint vx_permute(s_uint i, s_uint l, s_uint p) {
    s_uint w = l - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    do {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16u;
        i ^= (i & w) >> 4u;
        i ^= p >> 8u;
        i *= 0x0929eb3fu;
        i ^= p >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | p >> 27u;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
    } while (i >= l);
    return (i + p) % l;
}

VX_S_FN float vx_randfloat(s_uint i, s_uint p) {
    i ^= p;
    i ^= i >> 17u;
    i ^= i >> 10u;
    i *= 0xb36534e5u;
    i ^= i >> 12u;
    i ^= i >> 21u;
    i *= 0x93fc4795u;
    i ^= 0xdf6e307fu;
    i ^= i >> 17u;
    i *= 1u | p >> 18u;
    return float(i) * (1.0f / 4294967808.0f);
}

// Sample s (0 <= s < n) of Kensler's correlated multi-jittered sampling for an arbitrary count n
// (the memo's final cmj(), aspect 1): a grid of m = floor(sqrt(n)) columns and ceil(n / m) rows.
// y is stratified over n strata (s is first permuted over [0, n)), x over the grid's columns
// with the row's jitter: both coordinates have mean 0.5 for every n, also when n is not a
// product of the grid (the earlier variant left the last row partly empty and was biased
// towards (0.46, 0.43) then). Result in [0, 1)^2.
//
// Two patterns: `coarse` picks where sample s lies at the grid's scale (its y stratum and its
// column), `fine` where within them (the x offset inside the column and both jitters). Each
// point is uniform and the set stratified for any pair; pixels that share `coarse` and not
// `fine` trace their sample s towards the same 1/n by 1/m of the domain (coherent rays, which
// a GPU traverses together) while their errors stay independent at the finer scale.
VX_S_FN s_vec2 vx_cmj2(s_uint s, s_uint n, s_uint coarse, s_uint fine) {
    s_uint m = s_uint(sqrt(float(n)));
    m = m < 1u ? 1u : m;
    s_uint rows = (n + m - 1u) / m;
    s = vx_permute(s, n, coarse * 0x51633e2du);
    s_uint sx = vx_permute(s % m, m, coarse * 0x68bc21ebu);
    s_uint sy = vx_permute(s / m, rows, fine * 0x02e5be93u);
    float jx = vx_randfloat(s, fine * 0x967a889bu);
    float jy = vx_randfloat(s, fine * 0x368cc8b7u);
    return s_vec2((float(sx) + (float(sy) + jx) / float(rows)) / float(m), (float(s) + jy) / float(n));
}

// Pattern p alone (Kensler's: one pattern for all of it).
VX_S_FN s_vec2 vx_cmj(s_uint s, s_uint n, s_uint p) { return vx_cmj2(s, n, p, p); }

// Interleaves the low 16 bits of x (even bits) and y (odd bits): the Morton (Z-order) index.
VX_S_FN s_uint vx_morton(s_uint x, s_uint y) {
    x &= 0xffffu;
    y &= 0xffffu;
    x = (x | (x << 8u)) & 0x00ff00ffu;
    x = (x | (x << 4u)) & 0x0f0f0f0fu;
    x = (x | (x << 2u)) & 0x33333333u;
    x = (x | (x << 1u)) & 0x55555555u;
    y = (y | (y << 8u)) & 0x00ff00ffu;
    y = (y | (y << 4u)) & 0x0f0f0f0fu;
    y = (y | (y << 2u)) & 0x33333333u;
    y = (y | (y << 1u)) & 0x55555555u;
    return x | (y << 1u);
}

VX_S_FN s_uint vx_reverse_bits(s_uint v) {
    v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
    v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
    v = ((v >> 4u) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4u);
    v = ((v >> 8u) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8u);
    return (v >> 16u) | (v << 16u);
}

// Owen scrambling of a 32-bit binary fraction x (a random permutation of each level's halves,
// keyed by the bits above): Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020, his
// hash on the reversed bits, in which every bit depends only on the bits below it (Laine &
// Karras 2011). It keeps a (t, m, s)-net a net, and makes each point uniform on [0, 1).
VX_S_FN s_uint vx_owen_scramble(s_uint x, s_uint seed) {
    x = vx_reverse_bits(x);
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return vx_reverse_bits(x);
}

// The second coordinate of point i of the 2D Sobol (0, 2)-sequence (the first is the van der
// Corput radical inverse, vx_reverse_bits(i)): generator matrix Pascal's triangle mod 2.
VX_S_FN s_uint vx_sobol_y(s_uint i) {
    s_uint r = 0u;
    s_uint v = 0x80000000u;
    while (i != 0u) {
        if ((i & 1u) != 0u)
            r ^= v;
        i >>= 1u;
        v ^= v >> 1u;
    }
    return r;
}

// Pixels in aligned squares of 2^kSampleTileShift share vx_cmj2's coarse pattern (8 x 8: a warp
// of 32 rays in any 2D arrangement lies in one or two; 4 x 4 and 32 x 32 timed within 1%).
#ifdef __cplusplus
inline constexpr uint32_t kSampleTileShift = 3u;
#else
const uint kSampleTileShift = 3u;
#endif

// Sample s (0 <= s < n) of pixel (x, y)'s estimator `seed` (one light at one bounce of one
// frame: raygen.rgen derives it), in [0, 1)^2. For n a power of two the pixel takes points
// [m n, m n + n) of the Owen-scrambled 2D Sobol sequence, m its Morton index (Ahmed & Wonka,
// "Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling Error via Hierarchical Ordering of
// Pixels", SIGGRAPH Asia 2020): its n points are a (0, log2 n, 2)-net, stratified in every
// elementary interval of area 1/n, and the points of each aligned 2x2, 4x4, ... block of pixels
// together form a net too, so neighbouring pixels' errors cancel in a spatial filter (blue-noise
// error). The scramble is the estimator's seed: each point is uniform (unbiased), and frames and
// estimators are independent. Other n have no such nets (measured: a shifted or truncated net
// did worse), so they keep a correlated multi-jittered pattern of the pixel's own, but for its
// coarse part, which the pixel's tile shares (vx_cmj2): at step s of the estimator's loop the
// rays of a tile head for the same small part of a light (less divergent traversal), each
// pixel's points are distributed as before, and their errors stay independent at the finer
// scale. Measured (docs/render_report.md, stop 26): the same raw error (denoised +2% on
// terrain); 25 spp traced 2-23% faster on the H200, 12% on lavapipe.
VX_S_FN s_vec2 vx_pixel_sample(s_uint s, s_uint n, s_uint x, s_uint y, s_uint seed) {
    if ((n & (n - 1u)) != 0u)
        return vx_cmj2(s, n, vx_hash((x >> kSampleTileShift) + vx_hash((y >> kSampleTileShift) + (seed ^ 0x85ebca6bu))),
                       vx_hash(x + vx_hash(y + seed)));
    s_uint i = vx_morton(x, y) * n + s;
    s_uint u = vx_owen_scramble(vx_reverse_bits(i), vx_hash(seed));
    s_uint v = vx_owen_scramble(vx_sobol_y(i), vx_hash(seed ^ 0x9e3779b9u));
    return s_vec2(float(u >> 8u), float(v >> 8u)) * (1.0f / 16777216.0f);
}

#ifdef __cplusplus
} // namespace vx::render::gpu
#else
#undef s_uint
#undef s_vec2
#endif
#endif
