#pragma once
// A fixed-length array of unsigned integers of 1..16 bits each, packed back to back in 64-bit
// words (an entry may straddle two words, so 3-bit entries cost exactly 3 bits). Used for the
// palette indices of a chunk. Not thread-safe for writes; concurrent reads are safe.

#include <cstdint>
#include <cstring>
#include <memory>

#include "world/base/assert.h"

namespace vx::world {

class PackedArray {
public:
    PackedArray() = default;
    // `count` entries of `bits` bits, all zero.
    PackedArray(uint32_t count, uint32_t bits);
    PackedArray(const PackedArray& other);
    PackedArray& operator=(const PackedArray& other);
    PackedArray(PackedArray&&) noexcept = default;
    PackedArray& operator=(PackedArray&&) noexcept = default;

    uint32_t bits() const { return m_bits; }
    uint32_t size() const { return m_count; }
    // Words of storage, including one zero word of padding so reads never branch.
    uint32_t word_count() const { return word_count_for(m_count, m_bits); }
    const uint64_t* words() const { return m_words.get(); }
    uint64_t* words() { return m_words.get(); }
    size_t memory_bytes() const { return size_t(word_count()) * 8; }

    static uint32_t word_count_for(uint32_t count, uint32_t bits) {
        return uint32_t((uint64_t(count) * bits + 63) / 64) + 1;
    }

    uint32_t get(uint32_t i) const {
        VX_DEBUG_ASSERT(i < m_count);
        const uint64_t pos = uint64_t(i) * m_bits;
        const uint64_t* w = m_words.get() + (pos >> 6);
        const uint32_t off = uint32_t(pos & 63);
        // The second word's part is shifted twice so a shift by 64 never happens.
        const uint64_t v = (w[0] >> off) | ((w[1] << 1) << (63 - off));
        return uint32_t(v & m_mask);
    }

    void set(uint32_t i, uint32_t value) {
        VX_DEBUG_ASSERT(i < m_count && value <= m_mask);
        const uint64_t pos = uint64_t(i) * m_bits;
        uint64_t* w = m_words.get() + (pos >> 6);
        const uint32_t off = uint32_t(pos & 63);
        w[0] = (w[0] & ~(m_mask << off)) | (uint64_t(value) << off);
        if (off + m_bits > 64) {
            const uint32_t lo = 64 - off;
            w[1] = (w[1] & ~(m_mask >> lo)) | (uint64_t(value) >> lo);
        }
    }

    // Sets every entry from `values` (size() of them), faster than set() one by one.
    void set_all(const uint16_t* values);

    // A copy with another entry width; values must fit.
    PackedArray resized(uint32_t new_bits) const;

private:
    std::unique_ptr<uint64_t[]> m_words;
    uint64_t m_mask = 0;
    uint32_t m_count = 0;
    uint32_t m_bits = 0;
};

// Bits needed to index `n` palette entries (at least 1).
inline uint32_t bits_for_count(uint32_t n) {
    uint32_t b = 1;
    while ((1u << b) < n)
        ++b;
    return b;
}

} // namespace vx::world
