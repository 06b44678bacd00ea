#pragma once
// Deterministic noise for terrain generation: integer hashing and gradient noise.
//
// Gradient noise after K. Perlin, "Improving Noise", SIGGRAPH 2002: pseudo-random gradients on the
// integer lattice, the quintic fade 6t^5 - 15t^4 + 10t^3 and multilinear blending. The gradients
// come from an integer hash of (seed, lattice cell) instead of a permutation table, so any seed
// works without setup and there is no shared state. Only +, -, * and integer operations are used
// (no libm), so the results depend on nothing but the inputs: the same on every thread and run.
//
// Coordinates: lattice cells are 64-bit integers and the position inside a cell is a float
// fraction in [0, 1), so precision does not degrade far from the origin. The *_at helpers sample
// at integer block positions with power-of-two wavelengths, where the fraction is exact.
// All functions are pure. Thread-safe.

#include <cstdint>

namespace vx::world::noise {

// 64-bit hash of a seed and up to three integer coordinates. The final mix is the splitmix64
// finalizer (Steele, Lea & Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA 2014).
inline uint64_t mix64(uint64_t h) {
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return h;
}
inline uint64_t hash_coords(uint64_t seed, int64_t x, int64_t y = 0, int64_t z = 0) {
    return mix64(seed * 0xD6E8FEB86659FD93ull ^ uint64_t(x) * 0x9E3779B97F4A7C15ull ^
                 uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^ uint64_t(z) * 0x165667B19E3779F9ull);
}
// A float in [0, 1) from the top 24 bits of a hash.
inline float hash_unit(uint64_t h) { return float(h >> 40) * (1.0f / 16777216.0f); }

// 2D gradient noise at lattice cell (cx, cz) plus fraction (fx, fz) in [0, 1). Result in about
// [-1, 1]; zero on lattice points.
float gradient_2d(uint64_t seed, int64_t cx, int64_t cz, float fx, float fz);

// Two independent 3D gradient noises at the same point, sharing one hash per lattice corner
// (different hash bits pick each gradient): caves need a pair and this halves the hashing.
// Results in about [-1, 1].
struct Noise3Pair {
    float a, b;
};
Noise3Pair gradient_3d_pair(uint64_t seed, int64_t cx, int64_t cy, int64_t cz, float fx, float fy, float fz);

// 2D gradient noise at integer block (x, z) with wavelength 2^shift blocks (1 <= shift <= 30).
float gradient_2d_at(uint64_t seed, int64_t x, int64_t z, int shift);

// Fractal Brownian motion (Musgrave et al., "Texturing and Modeling", 1994): `octaves` layers of
// gradient_2d_at, the first with wavelength 2^shift, each next one half the wavelength and
// `gain` times the amplitude; each octave gets its own lattice offset so lattice points of
// different octaves do not line up. Normalized by the amplitude sum: about [-1, 1].
// Requires shift - octaves + 1 >= 1.
float fbm_2d_at(uint64_t seed, int64_t x, int64_t z, int shift, int octaves, float gain);

// The pair of 3D noises at integer block (x, y, z) with wavelengths 2^shift_xz (x, z) and
// 2^shift_y (y).
Noise3Pair gradient_3d_pair_at(uint64_t seed, int64_t x, int64_t y, int64_t z, int shift_xz, int shift_y);

// gradient_3d_pair_at on the grid (x0 + step*i, y0 + step*j, z0 + step*k), i < nx, j < ny,
// k < nz, written to out[(k * ny + j) * nx + i]; bit-identical to the pointwise calls, several
// times faster for grids finer than the wavelength (each cell's corners are hashed once).
void gradient_3d_pair_grid(uint64_t seed, int64_t x0, int64_t y0, int64_t z0, int step, int nx, int ny, int nz,
                           int shift_xz, int shift_y, Noise3Pair* out);

} // namespace vx::world::noise
