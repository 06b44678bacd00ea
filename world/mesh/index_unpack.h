#pragma once
// Palette indices to entry rows, and transposes: the greedy mesher's data movement. Internal to
// vx_world (the greedy mesher; LOD downsampling unpacks with it). Not thread-safe: plain
// functions on caller data.
//
// A row is 32 consecutive blocks along x (local index r * 32 .. r * 32 + 31, r = z * 32 + y).
// The transposed rows of a chunk hold the same blocks along y: row z * 32 + x, entry y.

#include <cstdint>

#include "world/packed_array.h"

namespace vx::world::mesher_detail {

// Unpacks rows row0, row0 + step, ... (count of them) of B-bit palette indices (B = a.bits() <=
// 8) to one byte per block, row i at out[i * 32 + x]. SIMD or shift-and-mask spreading, no
// per-entry loop. Step 32 reads the rows of one y layer (rows z * 32 + y, z = 0..31).
void unpack_rows8(const PackedArray& a, int row0, int count, uint8_t* out, int step = 1);
// Rows 0..count - 1, the same bytes; cheaper where rows repeat the previous one (terrain).
void unpack_chunk8(const PackedArray& a, int count, uint8_t* out);
// The same for any width (palettes of more than 256 entries), 16 bits per block.
void unpack_rows16(const PackedArray& a, int row0, int count, uint16_t* out);

// Transposes the 32 x 32 entries of each z slab: dt[z][x][y] = d[z][y][x] (1024 rows in all).
void transpose_slabs(const uint8_t* d, uint8_t* dt);
void transpose_slabs(const uint16_t* d, uint16_t* dt);

// 32 x 32 bit-matrix transpose: bit j of row i moves to bit i of row j.
void transpose32(uint32_t a[32]);
// Bit x of each of 32 rows of bits, as one row (bit y from rows[y]).
uint32_t column_bits(const uint32_t* rows, int x);

} // namespace vx::world::mesher_detail
