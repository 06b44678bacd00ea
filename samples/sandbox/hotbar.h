#pragma once
// The hotbar: nine block ids, one selected. Keys 1–9 pick a slot, the wheel cycles, middle click
// puts the block under the crosshair into the selected slot (or selects the slot holding it).
// Thread: plain value, not shared.
#include <array>

#include <vx/types.h>

namespace sandbox {

class Hotbar {
public:
    static constexpr int kSlots = 9;
    // Slots hold ids first, first + 1, ... (the built-in palette: stone, dirt, grass, ...).
    explicit Hotbar(vx::BlockId first = 1);

    vx::BlockId selected_block() const { return m_slots[size_t(m_selected)]; }
    int selected_slot() const { return m_selected; } // 0-based.
    vx::BlockId slot(int i) const { return m_slots[size_t(i)]; }
    // Slot i (0-based); out-of-range values are ignored.
    void select(int i);
    // The wheel: +steps to the right, wrapping around.
    void scroll(int steps);
    // Selects the slot that holds `id`, or puts `id` into the selected slot.
    void pick(vx::BlockId id);

private:
    std::array<vx::BlockId, kSlots> m_slots{};
    int m_selected = 0;
};

} // namespace sandbox
