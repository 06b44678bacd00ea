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

// Sample s (0 <= s < n) of pattern p of Kensler's correlated multi-jittered sampling for an
// arbitrary count n (the memo's final cmj(), aspect 1): a grid of m = floor(sqrt(n)) columns and
// ceil(n / m) rows. y is stratified over n strata (s is first permuted over [0, n)), x over the
// grid's columns with the row's jitter: both coordinates have mean 0.5 for every n, also when
// n is not a product of the grid (the earlier variant left the last row partly empty and was
// biased towards (0.46, 0.43) then). Result in [0, 1)^2.
VX_S_FN s_vec2 vx_cmj(s_uint s, s_uint n, s_uint p) {
    s_uint m = s_uint(sqrt(float(n)));
    m = m < 1u ? 1u : m;
    s_uint rows = (n + m - 1u) / m;
    s = vx_permute(s, n, p * 0x51633e2du);
    s_uint sx = vx_permute(s % m, m, p * 0x68bc21ebu);
    s_uint sy = vx_permute(s / m, rows, p * 0x02e5be93u);
    float jx = vx_randfloat(s, p * 0x967a889bu);
    float jy = vx_randfloat(s, p * 0x368cc8b7u);
    return s_vec2((float(sx) + (float(sy) + jx) / float(rows)) / float(m), (float(s) + jy) / float(n));
}

#ifdef __cplusplus
} // namespace vx::render::gpu
#else
#undef s_uint
#undef s_vec2
#endif
#endif
