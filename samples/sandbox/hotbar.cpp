#include "hotbar.h"

namespace sandbox {

Hotbar::Hotbar(vx::BlockId first) {
    for (int i = 0; i < kSlots; ++i)
        m_slots[size_t(i)] = vx::BlockId(first + i);
}

void Hotbar::select(int i) {
    if (i >= 0 && i < kSlots)
        m_selected = i;
}

void Hotbar::scroll(int steps) {
    m_selected = ((m_selected + steps) % kSlots + kSlots) % kSlots;
}

void Hotbar::pick(vx::BlockId id) {
    if (id == vx::kAir)
        return;
    for (int i = 0; i < kSlots; ++i)
        if (m_slots[size_t(i)] == id) {
            m_selected = i;
            return;
        }
    m_slots[size_t(m_selected)] = id;
}

} // namespace sandbox
