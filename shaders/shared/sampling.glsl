// Deterministic sampling for the ray-tracing shaders.

// A 32-bit integer hash (PCG output permutation; Jarzynski & Olano, JCGT 2020).
uint vx_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Kensler, "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01 (2013):
// permute() is a hash-based permutation of [0, l) selected by pattern p.
uint vx_permute(uint i, uint l, uint p) {
    uint w = l - 1u;
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

float vx_randfloat(uint i, uint p) {
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
    return float(i) * (1.0 / 4294967808.0);
}

// Sample s of an m x n correlated multi-jittered pattern p, in [0, 1)^2.
vec2 vx_cmj(uint s, uint m, uint n, uint p) {
    uint sx = vx_permute(s % m, m, p * 0xa511e9b3u);
    uint sy = vx_permute(s / m, n, p * 0x63d83595u);
    float jx = vx_randfloat(s, p * 0xa399d265u);
    float jy = vx_randfloat(s, p * 0x711ad6a5u);
    return vec2((float(s % m) + (float(sy) + jx) / float(n)) / float(m),
                (float(s / m) + (float(sx) + jy) / float(m)) / float(n));
}
