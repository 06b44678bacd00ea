#include "world/store/chunk_record.h"

#include <bit>
#include <cstring>
#include <string>
#include <utility>

#include <xxhash.h>
#include <zstd.h>

namespace vx::world {

static_assert(std::endian::native == std::endian::little, "records are written with memcpy");

namespace {

template <class T> void put(uint8_t* p, T v) { std::memcpy(p, &v, sizeof(T)); }
template <class T> T get(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

uint64_t record_checksum(const uint8_t* header, const uint8_t* payload, size_t payload_size, int level) {
    return XXH64(payload, payload_size, XXH64(header, 32, XXH64_hash_t(level)));
}

std::string coord_str(ChunkCoord c) {
    std::string s = "("; // (not "(" + ...: trips a GCC 12 -Wrestrict false positive)
    s += std::to_string(c.x) + ", " + std::to_string(c.y) + ", " + std::to_string(c.z) + ")";
    return s;
}

Error fail(const std::string& what) { return Error{"corrupt chunk record: " + what}; }

// Writes the header (checksum included) in front of a payload already placed at out[40..].
void finish_record(std::vector<uint8_t>& out, const RecordHeader& h, int level) {
    uint8_t* p = out.data();
    put<uint32_t>(p + 0, kRecordMagic);
    put<uint16_t>(p + 4, kRecordFormatVersion);
    p[6] = uint8_t(h.kind);
    p[7] = uint8_t(h.codec);
    put<int32_t>(p + 8, h.coord.x);
    put<int32_t>(p + 12, h.coord.y);
    put<int32_t>(p + 16, h.coord.z);
    put<uint32_t>(p + 20, h.palette_entries);
    put<uint32_t>(p + 24, h.raw_size);
    put<uint32_t>(p + 28, h.stored_size);
    put<uint64_t>(p + 32, record_checksum(p, p + kRecordHeaderSize, h.stored_size, level));
}

size_t index_width(RecordKind kind) { return kind == RecordKind::Palette8 ? 1 : 2; }

// Largest of kChunkVolume values (a loop the compiler vectorizes).
template <class T> uint32_t max_value(const T* v) {
    T m = 0;
    for (size_t i = 0; i < size_t(kChunkVolume); ++i)
        m = v[i] > m ? v[i] : m;
    return m;
}

// Counts of each u8 value (all < counts.size()), with four sub-histograms so consecutive equal
// bytes do not serialize on one counter.
void histogram8(const uint8_t* v, std::vector<uint32_t>& counts) {
    uint32_t h[4][256] = {};
    for (size_t i = 0; i < size_t(kChunkVolume); i += 4) {
        ++h[0][v[i]];
        ++h[1][v[i + 1]];
        ++h[2][v[i + 2]];
        ++h[3][v[i + 3]];
    }
    for (size_t e = 0; e < counts.size(); ++e)
        counts[e] = h[0][e] + h[1][e] + h[2][e] + h[3][e];
}

// Palettes up to this size are counted entry by entry with byte compares (one vectorised pass
// per entry) rather than with histogram8's scalar increments: terrain chunks hold 2-8 entries.
constexpr uint32_t kCountByCompare = 8;

// counts[e] = how many of the kChunkVolume bytes equal e, for every e < counts.size().
void count_small8(const uint8_t* v, std::vector<uint32_t>& counts) {
    for (size_t e = 0; e < counts.size(); ++e) {
        const uint8_t want = uint8_t(e);
        uint32_t total = 0;
        for (size_t block = 0; block < size_t(kChunkVolume); block += 128) {
            uint8_t run = 0; // At most 128 per block: a byte cannot overflow.
            for (size_t i = 0; i < 128; ++i)
                run += uint8_t(v[block + i] == want);
            total += run;
        }
        counts[e] = total;
    }
}

// Packs kChunkVolume values of B bits in PackedArray's layout (entry i at bit i*B, straddling
// words). 64 entries fill exactly B words, so each group is a fully unrolled loop with constant
// shifts: ~10x faster than PackedArray::set_all's variable-shift loop.
template <uint32_t B, class T> void pack_fixed(const T* src, uint64_t* w) {
    for (size_t g = 0; g < size_t(kChunkVolume) / 64; ++g, src += 64, w += B) {
        uint64_t acc = 0;
        uint32_t fill = 0, out = 0;
#pragma GCC unroll 64
        for (uint32_t i = 0; i < 64; ++i) {
            const uint64_t v = src[i];
            acc |= v << fill;
            fill += B;
            if (fill >= 64) {
                w[out++] = acc;
                fill -= 64;
                acc = fill ? v >> (B - fill) : 0;
            }
        }
    }
}

template <class T, uint32_t... Bs>
void pack_dispatch(const T* src, uint32_t bits, uint64_t* w, std::integer_sequence<uint32_t, Bs...>) {
    ((bits == Bs + 1 ? pack_fixed<Bs + 1>(src, w) : void()), ...);
}

// Values must be < 2^bits (validated by the caller); bits in 1..16.
template <class T> void pack_indices(const T* src, uint32_t bits, uint64_t* words) {
    VX_ASSERT(bits >= 1 && bits <= 16);
    pack_dispatch(src, bits, words, std::make_integer_sequence<uint32_t, 16>());
}

// Eight u8 entries (each < 2^B, entry 0 in the low byte) squeezed into the low 8*B bits, entry
// 0 lowest: three SWAR folds instead of eight shifts and ors.
template <uint32_t B> uint64_t squeeze8(uint64_t v) {
    v = (v & 0x00FF00FF00FF00FFull) | ((v & 0xFF00FF00FF00FF00ull) >> (8 - B));
    v = (v & 0x0000FFFF0000FFFFull) | ((v & 0xFFFF0000FFFF0000ull) >> (16 - 2 * B));
    return (v & 0x00000000FFFFFFFFull) | ((v & 0xFFFFFFFF00000000ull) >> (32 - 4 * B));
}

// pack_fixed for u8 entries and B <= 8, eight entries at a time (the decode of every record with
// at most 256 palette entries). `w` must be zero.
template <uint32_t B> void pack8_fixed(const uint8_t* src, uint64_t* w) {
    for (size_t g = 0; g < size_t(kChunkVolume) / 64; ++g, src += 64, w += B) {
#pragma GCC unroll 8
        for (uint32_t j = 0; j < 8; ++j) {
            uint64_t v;
            std::memcpy(&v, src + 8 * j, 8);
            const uint64_t packed = squeeze8<B>(v);
            const uint32_t bit = j * 8 * B, word = bit >> 6, off = bit & 63;
            w[word] |= packed << off;
            if (off + 8 * B > 64)
                w[word + 1] |= packed >> (64 - off);
        }
    }
}

template <uint32_t... Bs>
void pack8_dispatch(const uint8_t* src, uint32_t bits, uint64_t* w, std::integer_sequence<uint32_t, Bs...>) {
    ((bits == Bs + 1 ? pack8_fixed<Bs + 1>(src, w) : void()), ...);
}

// u8 entries, bits 1..8, into zeroed words.
void pack_indices8(const uint8_t* src, uint32_t bits, uint64_t* words) {
    VX_ASSERT(bits >= 1 && bits <= 8);
    pack8_dispatch(src, bits, words, std::make_integer_sequence<uint32_t, 8>());
}

// The inverse of pack_fixed, each entry mapped through `remap`: 64 entries per group of B words,
// unrolled with constant shifts (PackedArray::get per entry cost half of encode's time).
template <uint32_t B, class T> void unpack_fixed(const uint64_t* w, const uint16_t* remap, T* dst) {
    constexpr uint64_t kMask = (uint64_t(1) << B) - 1;
    for (size_t g = 0; g < size_t(kChunkVolume) / 64; ++g, dst += 64, w += B) {
#pragma GCC unroll 64
        for (uint32_t i = 0; i < 64; ++i) {
            const uint32_t bit = i * B, word = bit >> 6, off = bit & 63;
            uint64_t v = w[word] >> off;
            if (off + B > 64)
                v |= w[word + 1] << (64 - off);
            dst[i] = T(remap[v & kMask]);
        }
    }
}

template <class T, uint32_t... Bs>
void unpack_dispatch(const uint64_t* w, uint32_t bits, const uint16_t* remap, T* dst,
                     std::integer_sequence<uint32_t, Bs...>) {
    ((bits == Bs + 1 ? unpack_fixed<Bs + 1>(w, remap, dst) : void()), ...);
}

// The inverse of squeeze8: the low 8*B bits spread into eight bytes of B bits, entry 0 lowest.
template <uint32_t B> uint64_t spread8(uint64_t v) {
    constexpr uint64_t k4 = (uint64_t(1) << (4 * B)) - 1, k2 = (uint64_t(1) << (2 * B)) - 1;
    constexpr uint64_t k1 = ((uint64_t(1) << B) - 1) * 0x0001000100010001ull;
    v = (v & k4) | ((v << (32 - 4 * B)) & (k4 << 32));
    v = (v & (k2 | k2 << 32)) | ((v << (16 - 2 * B)) & (k2 << 16 | k2 << 48));
    return (v & k1) | ((v << (8 - B)) & (k1 << 8));
}

// unpack_fixed to u8 without a remap (every palette entry used: the common case), eight entries
// at a time: a few instructions per eight entries instead of several per entry.
template <uint32_t B> void unpack8_fixed(const uint64_t* w, uint8_t* dst) {
    constexpr uint64_t kMask = B == 8 ? ~uint64_t(0) : (uint64_t(1) << (8 * B)) - 1;
    for (size_t g = 0; g < size_t(kChunkVolume) / 64; ++g, dst += 64, w += B) {
#pragma GCC unroll 8
        for (uint32_t j = 0; j < 8; ++j) {
            const uint32_t bit = j * 8 * B, word = bit >> 6, off = bit & 63;
            uint64_t v = w[word] >> off;
            if (off + 8 * B > 64)
                v |= w[word + 1] << (64 - off);
            const uint64_t bytes = spread8<B>(v & kMask);
            std::memcpy(dst + 8 * j, &bytes, 8);
        }
    }
}

template <uint32_t... Bs>
void unpack8_dispatch(const uint64_t* w, uint32_t bits, uint8_t* dst, std::integer_sequence<uint32_t, Bs...>) {
    ((bits == Bs + 1 ? unpack8_fixed<Bs + 1>(w, dst) : void()), ...);
}

// Entries of `indices` (kChunkVolume of them, bits 1..16), each < the size of `remap`, whose
// values fit T.
template <class T> void unpack_indices(const PackedArray& indices, const uint16_t* remap, T* dst) {
    VX_ASSERT(indices.size() == uint32_t(kChunkVolume) && indices.bits() >= 1 && indices.bits() <= 16);
    unpack_dispatch(indices.words(), indices.bits(), remap, dst, std::make_integer_sequence<uint32_t, 16>());
}

} // namespace

RecordCodec::RecordCodec(int zstd_level)
    : m_cctx(ZSTD_createCCtx()), m_dctx(ZSTD_createDCtx()), m_level(zstd_level) {
    VX_ASSERT(m_cctx && m_dctx);
    VX_ASSERT(zstd_level >= 1 && zstd_level <= 19);
}

RecordCodec::~RecordCodec() {
    ZSTD_freeCCtx(m_cctx);
    ZSTD_freeDCtx(m_dctx);
}

void RecordCodec::encode(ChunkCoord coord, const Chunk& chunk, std::vector<uint8_t>& out) {
    encode_lod(LodCoord{0, coord}, chunk, out);
}

void RecordCodec::encode_lod(LodCoord coord, const Chunk& chunk, std::vector<uint8_t>& out) {
    VX_ASSERT(valid_lod_level(coord.level));
    const int level = coord.level;
    RecordHeader h;
    h.coord = coord.chunk;
    const ChunkPalette* pal = chunk.palette();
    // Renumber the used palette entries densely (what compact() would do, without mutating).
    BlockId uniform_id = chunk.uniform_id();
    std::vector<uint16_t> remap;
    std::vector<uint16_t> used_ids;
    if (pal) {
        remap.assign(pal->ids.size(), 0);
        for (size_t e = 0; e < pal->ids.size(); ++e)
            if (pal->counts[e] > 0) {
                remap[e] = uint16_t(used_ids.size());
                used_ids.push_back(pal->ids[e]);
            }
        if (used_ids.size() == 1)
            uniform_id = used_ids[0];
    }
    if (!pal || used_ids.size() == 1) {
        h.kind = RecordKind::Uniform;
        h.codec = RecordCodecId::Raw;
        h.palette_entries = 1;
        h.raw_size = h.stored_size = 2;
        out.resize(kRecordHeaderSize + 2);
        put<uint16_t>(out.data() + kRecordHeaderSize, uniform_id);
        finish_record(out, h, level);
        return;
    }
    const uint32_t n = uint32_t(used_ids.size());
    h.kind = n <= 256 ? RecordKind::Palette8 : RecordKind::Palette16;
    h.palette_entries = n;
    const size_t width = index_width(h.kind);
    h.raw_size = uint32_t(2 * n + width * kChunkVolume);
    m_raw.resize(h.raw_size);
    std::memcpy(m_raw.data(), used_ids.data(), 2 * size_t(n));
    uint8_t* idx = m_raw.data() + 2 * size_t(n);
    if (width == 1 && n == pal->ids.size() && pal->indices.bits() <= 8) { // Identity remap.
        unpack8_dispatch(pal->indices.words(), pal->indices.bits(), idx, std::make_integer_sequence<uint32_t, 8>());
    } else if (width == 1) { // n <= 256: every renumbered index fits a byte.
        unpack_indices(pal->indices, remap.data(), idx);
    } else {
        m_indices.resize(kChunkVolume);
        unpack_indices(pal->indices, remap.data(), m_indices.data());
        std::memcpy(idx, m_indices.data(), 2 * size_t(kChunkVolume)); // Little-endian (asserted).
    }
    // Compress into scratch, then copy: `out` gets exactly the record's size (queued records in
    // a store would otherwise each keep a 64 KiB compress-bound allocation).
    m_zbuf.resize(ZSTD_compressBound(h.raw_size));
    const size_t z = ZSTD_compressCCtx(m_cctx, m_zbuf.data(), m_zbuf.size(), m_raw.data(), h.raw_size, m_level);
    VX_ASSERT_MSG(!ZSTD_isError(z), "zstd compression into a compressBound buffer cannot fail");
    h.codec = RecordCodecId::Zstd;
    h.stored_size = uint32_t(z);
    out.resize(kRecordHeaderSize + z);
    std::memcpy(out.data() + kRecordHeaderSize, m_zbuf.data(), z);
    finish_record(out, h, level);
}

size_t max_record_bytes() {
    return kRecordHeaderSize + ZSTD_compressBound(2 * size_t(kMaxPaletteEntries) + 2 * size_t(kChunkVolume));
}

Result<RecordHeader> read_record_header(std::span<const uint8_t> record, int level) {
    if (record.size() < kRecordHeaderSize)
        return fail("truncated to " + std::to_string(record.size()) + " bytes (header is 40)");
    if (record.size() > max_record_bytes())
        return fail("too long (" + std::to_string(record.size()) + " bytes)");
    const uint8_t* p = record.data();
    if (get<uint32_t>(p) != kRecordMagic)
        return fail("bad magic (not a vx chunk record)");
    RecordHeader h;
    h.version = get<uint16_t>(p + 4);
    h.kind = RecordKind(p[6]);
    h.codec = RecordCodecId(p[7]);
    h.coord = ChunkCoord(get<int32_t>(p + 8), get<int32_t>(p + 12), get<int32_t>(p + 16));
    h.palette_entries = get<uint32_t>(p + 20);
    h.raw_size = get<uint32_t>(p + 24);
    h.stored_size = get<uint32_t>(p + 28);
    if (size_t(h.stored_size) != record.size() - kRecordHeaderSize)
        return fail("length mismatch: header says " + std::to_string(h.stored_size) + " payload bytes, record has " +
                    std::to_string(record.size() - kRecordHeaderSize));
    if (get<uint64_t>(p + 32) != record_checksum(p, p + kRecordHeaderSize, h.stored_size, level))
        return fail(level == 0 ? "checksum mismatch" : "checksum mismatch (or a record of another level)");
    if (h.version != kRecordFormatVersion)
        return fail("unsupported format version " + std::to_string(h.version));
    return h;
}

Result<Chunk> RecordCodec::decode(std::span<const uint8_t> record, ChunkCoord expected) {
    return decode_lod(record, LodCoord{0, expected});
}

Result<Chunk> RecordCodec::decode_lod(std::span<const uint8_t> record, LodCoord expected) {
    if (!valid_lod_level(expected.level))
        return fail("level " + std::to_string(expected.level) + " out of range");
    Result<RecordHeader> hr = read_record_header(record, expected.level);
    if (!hr)
        return Error{hr.error()};
    const RecordHeader& h = *hr;
    if (h.coord != expected.chunk)
        return fail("record of chunk " + coord_str(h.coord) + " filed under " + coord_str(expected.chunk));
    const std::span<const uint8_t> payload = record.subspan(kRecordHeaderSize);
    switch (h.kind) {
    case RecordKind::Uniform:
        if (h.codec != RecordCodecId::Raw || h.palette_entries != 1 || h.raw_size != 2 || h.stored_size != 2)
            return fail("malformed uniform record");
        return Chunk(get<uint16_t>(payload.data()));
    case RecordKind::Palette8:
    case RecordKind::Palette16:
        return decode_palette(h, payload);
    }
    return fail("unknown record kind " + std::to_string(int(h.kind)));
}

Result<Chunk> RecordCodec::decode_palette(const RecordHeader& h, std::span<const uint8_t> payload) {
    const uint32_t n = h.palette_entries;
    const size_t width = index_width(h.kind);
    if (n < 2 || n > kMaxPaletteEntries || (width == 1 && n > 256))
        return fail("bad palette size " + std::to_string(n));
    // Every size is checked against what n implies before anything is allocated.
    const size_t raw_size = 2 * size_t(n) + width * kChunkVolume;
    if (h.raw_size != raw_size)
        return fail("raw size " + std::to_string(h.raw_size) + " does not match the palette");
    m_raw.resize(raw_size);
    if (h.codec == RecordCodecId::Raw) {
        if (payload.size() != raw_size)
            return fail("raw payload size mismatch");
        std::memcpy(m_raw.data(), payload.data(), raw_size);
    } else if (h.codec == RecordCodecId::Zstd) {
        if (payload.size() > ZSTD_compressBound(raw_size))
            return fail("compressed payload larger than the bound");
        const size_t got = ZSTD_decompressDCtx(m_dctx, m_raw.data(), raw_size, payload.data(), payload.size());
        if (ZSTD_isError(got))
            return fail(std::string("zstd: ") + ZSTD_getErrorName(got));
        if (got != raw_size)
            return fail("payload decompressed to " + std::to_string(got) + " bytes, expected " +
                        std::to_string(raw_size));
    } else {
        return fail("unknown codec " + std::to_string(int(h.codec)));
    }
    ChunkPalette pal;
    pal.ids.resize(n);
    std::memcpy(pal.ids.data(), m_raw.data(), 2 * size_t(n));
    std::vector<uint64_t> seen(65536 / 64, 0);
    for (BlockId id : pal.ids) {
        uint64_t& w = seen[id >> 6];
        if (w & (uint64_t(1) << (id & 63)))
            return fail("palette repeats block id " + std::to_string(id));
        w |= uint64_t(1) << (id & 63);
    }
    const uint8_t* src = m_raw.data() + 2 * size_t(n);
    std::vector<uint32_t> counts(n, 0);
    const uint32_t bits = bits_for_count(n);
    pal.indices = PackedArray(kChunkVolume, bits);
    if (width == 1) {
        if (n <= kCountByCompare) {
            // Counting only values below n: all kChunkVolume of them are in range exactly when
            // the counts add up, so no separate range pass.
            count_small8(src, counts);
            uint32_t total = 0;
            for (uint32_t c : counts)
                total += c;
            if (total != uint32_t(kChunkVolume))
                return fail("palette index out of range");
        } else {
            if (max_value(src) >= n) // Checked before counting: counts[] has only n slots.
                return fail("palette index out of range");
            histogram8(src, counts);
        }
        pack_indices8(src, bits, pal.indices.words()); // PackedArray starts zeroed.
    } else {
        m_indices.resize(kChunkVolume);
        std::memcpy(m_indices.data(), src, 2 * size_t(kChunkVolume));
        if (max_value(m_indices.data()) >= n)
            return fail("palette index out of range");
        for (uint16_t e : m_indices)
            ++counts[e];
        pack_indices(m_indices.data(), bits, pal.indices.words());
    }
    pal.counts.resize(n);
    for (uint32_t e = 0; e < n; ++e) {
        if (counts[e] == 0)
            return fail("unused palette entry " + std::to_string(e));
        pal.counts[e] = uint16_t(counts[e]); // n >= 2 and none is 0, so each is < kChunkVolume.
    }
    return Chunk::from_palette(std::move(pal));
}

std::vector<uint8_t> encode_chunk_record(ChunkCoord coord, const Chunk& chunk) {
    RecordCodec codec;
    std::vector<uint8_t> out;
    codec.encode(coord, chunk, out);
    return out;
}

Result<Chunk> decode_chunk_record(std::span<const uint8_t> record, ChunkCoord expected) {
    RecordCodec codec;
    return codec.decode(record, expected);
}

} // namespace vx::world
