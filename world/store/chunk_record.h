#pragma once
// Chunk records: the on-disk form of one chunk, as stored by a ChunkStore.
//
// Layout (all integers little-endian), 40-byte header then payload:
//   0  u32 magic "VXCR"          20 u32 palette entries (1 for a uniform chunk)
//   4  u16 format version (1)    24 u32 raw payload bytes (before compression)
//   6  u8  kind (RecordKind)     28 u32 stored payload bytes (after compression)
//   7  u8  codec (RecordCodecId) 32 u64 checksum
//   8  i32 chunk x, y, z
// checksum = XXH64(payload, seed = XXH64(header bytes 0..31, seed = level)): it covers the header,
// the payload and the chunk's level of detail (world/lod/lod_coords.h), so a flipped bit, a
// truncation or a record filed under other coordinates or another level is caught. The level has
// no header field: level 0 (seed 0) keeps the records of worlds written before levels existed,
// and a coarse record read as another level fails as a checksum mismatch.
// Raw payload: a uniform chunk is its u16 block id (stored raw, 42 bytes in all); a palette chunk is
// n u16 ids followed by kChunkVolume indices in local-index order, u8 when n <= 256 else u16,
// compressed with zstd (byte-aligned indices compress far better than bit-packed ones).
// Decoding validates every field before allocating (at most 64 KiB + 128 KiB of scratch) and
// the content (indices < n, no repeated or unused entry) even when the checksum matches, since
// XXH64 guards against accidents, not forgery: hostile input yields an error, never a crash.

#include <cstdint>
#include <span>
#include <vector>

#include "world/base/result.h"
#include "world/chunk.h"
#include "world/coords.h"
#include "world/lod/lod_coords.h"

struct ZSTD_CCtx_s;
struct ZSTD_DCtx_s;

namespace vx::world {

inline constexpr uint32_t kRecordMagic = 0x52435856u; // "VXCR" read as a little-endian u32.
inline constexpr uint16_t kRecordFormatVersion = 1;
inline constexpr size_t kRecordHeaderSize = 40;
inline constexpr uint32_t kMaxPaletteEntries = uint32_t(kChunkVolume); // 32768: one id per block.

enum class RecordKind : uint8_t {
    Uniform = 0,   // Payload: one u16 block id.
    Palette8 = 1,  // Payload: n u16 ids, kChunkVolume u8 indices.
    Palette16 = 2, // Payload: n u16 ids, kChunkVolume u16 indices.
};

enum class RecordCodecId : uint8_t {
    Raw = 0,  // Payload stored as is.
    Zstd = 1, // One zstd frame (simple API, ZSTD_compress / ZSTD_decompress).
};

// Fields of a record header, as read (not validated beyond the magic and the checksum).
struct RecordHeader {
    ChunkCoord coord{0};
    uint16_t version = 0;
    RecordKind kind = RecordKind::Uniform;
    RecordCodecId codec = RecordCodecId::Raw;
    uint32_t palette_entries = 0;
    uint32_t raw_size = 0;    // Bytes.
    uint32_t stored_size = 0; // Bytes following the header.
};

// Encoder/decoder with reusable zstd contexts and scratch buffers (avoids a context allocation
// per chunk). Not thread-safe: one per thread; a store owns one for its I/O lane.
class RecordCodec {
public:
    // zstd level 1..3 (1 is the fastest; 3 saves a few percent more).
    explicit RecordCodec(int zstd_level = 1);
    ~RecordCodec();
    RecordCodec(const RecordCodec&) = delete;
    RecordCodec& operator=(const RecordCodec&) = delete;

    // Writes the record of `chunk` at chunk coordinates `coord` into `out` (replacing its
    // contents). Unused palette entries are dropped and indices renumbered; the chunk is untouched.
    void encode(ChunkCoord coord, const Chunk& chunk, std::vector<uint8_t>& out);
    // The same for a chunk of any level (coord.level 0..kMaxLodLevel; level 0 is encode()).
    void encode_lod(LodCoord coord, const Chunk& chunk, std::vector<uint8_t>& out);

    // Decodes a record that must hold chunk `expected`. An error message says what is wrong
    // (truncated, checksum mismatch, wrong coordinates, bad palette...).
    Result<Chunk> decode(std::span<const uint8_t> record, ChunkCoord expected);
    // The same for a chunk of any level: a record of another level fails (checksum mismatch).
    Result<Chunk> decode_lod(std::span<const uint8_t> record, LodCoord expected);

private:
    Result<Chunk> decode_palette(const RecordHeader& h, std::span<const uint8_t> payload);

    ZSTD_CCtx_s* m_cctx = nullptr;
    ZSTD_DCtx_s* m_dctx = nullptr;
    int m_level = 1;
    std::vector<uint8_t> m_raw;      // Uncompressed payload scratch.
    std::vector<uint8_t> m_zbuf;     // Compressed payload scratch.
    std::vector<uint16_t> m_indices; // kChunkVolume palette indices scratch.
};

// Largest record the encoder can produce (a 32768-entry palette, u16 indices, incompressible):
// anything longer is corrupt without looking further. Thread-safe.
size_t max_record_bytes();

// Reads and verifies the header and checksum of a record of level `level` (not its content).
// Thread-safe.
Result<RecordHeader> read_record_header(std::span<const uint8_t> record, int level = 0);

// One-shot helpers with a temporary codec (slower: a zstd context per call). Thread-safe.
std::vector<uint8_t> encode_chunk_record(ChunkCoord coord, const Chunk& chunk);
Result<Chunk> decode_chunk_record(std::span<const uint8_t> record, ChunkCoord expected);

} // namespace vx::world
