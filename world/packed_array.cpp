#include "world/packed_array.h"

namespace vx::world {

PackedArray::PackedArray(uint32_t count, uint32_t bits)
    : m_words(new uint64_t[word_count_for(count, bits)]()), m_mask((uint64_t(1) << bits) - 1), m_count(count),
      m_bits(bits) {
    VX_ASSERT(bits >= 1 && bits <= 16);
}

PackedArray::PackedArray(const PackedArray& other)
    : m_mask(other.m_mask), m_count(other.m_count), m_bits(other.m_bits) {
    if (other.m_words) {
        m_words.reset(new uint64_t[other.word_count()]);
        std::memcpy(m_words.get(), other.m_words.get(), other.memory_bytes());
    }
}

PackedArray& PackedArray::operator=(const PackedArray& other) {
    if (this != &other)
        *this = PackedArray(other);
    return *this;
}

void PackedArray::set_all(const uint16_t* values) {
    std::memset(m_words.get(), 0, memory_bytes());
    uint64_t* w = m_words.get();
    uint64_t pos = 0;
    for (uint32_t i = 0; i < m_count; ++i, pos += m_bits) {
        const uint64_t v = values[i] & m_mask;
        const uint32_t off = uint32_t(pos & 63);
        w[pos >> 6] |= v << off;
        if (off + m_bits > 64)
            w[(pos >> 6) + 1] |= v >> (64 - off);
    }
}

PackedArray PackedArray::resized(uint32_t new_bits) const {
    PackedArray out(m_count, new_bits);
    for (uint32_t i = 0; i < m_count; ++i)
        out.set(i, get(i));
    return out;
}

} // namespace vx::world
