#include "player_physics.h"

#include <algorithm>
#include <cmath>

namespace sandbox {
namespace {

// Faces closer than this count as touching, not overlapping (positions land exactly on block
// boundaries after a clamp).
constexpr double kEps = 1e-7;

struct Box {
    glm::dvec3 min, max;
};

int64_t first_cell(double lo) { return int64_t(std::floor(lo + kEps)); }
int64_t last_cell(double hi) { return int64_t(std::ceil(hi - kEps)) - 1; }

// True when any solid block lies in cells [lo, hi] of the other two axes at `layer` of `axis`.
bool layer_blocked(const Box& box, int axis, int64_t layer, const SolidQuery& solid) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int64_t i = first_cell(box.min[a1]); i <= last_cell(box.max[a1]); ++i)
        for (int64_t j = first_cell(box.min[a2]); j <= last_cell(box.max[a2]); ++j) {
            vx::BlockPos p;
            p[axis] = layer;
            p[a1] = i;
            p[a2] = j;
            if (solid(p))
                return true;
        }
    return false;
}

} // namespace

glm::dvec3 view_forward(double yaw_degrees, double pitch_degrees) {
    const double yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
    return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

glm::dvec3 view_right(double yaw_degrees) {
    const double yaw = glm::radians(yaw_degrees);
    return {std::cos(yaw), 0.0, -std::sin(yaw)};
}

double Player::move_axis(int axis, double delta, const SolidQuery& solid) {
    if (delta == 0.0)
        return 0.0;
    const double hw = m_params.half_width;
    Box box{m_feet - glm::dvec3(hw, 0.0, hw), m_feet + glm::dvec3(hw, m_params.height, hw)};
    double moved = delta;
    if (delta > 0) {
        // Layers the leading (max) face enters: those starting before its end position.
        const double start = box.max[axis], end = start + delta;
        for (int64_t k = int64_t(std::ceil(start - kEps)); k <= last_cell(end); ++k)
            if (layer_blocked(box, axis, k, solid)) {
                moved = std::max(0.0, double(k) - start);
                break;
            }
    } else {
        const double start = box.min[axis], end = start + delta;
        for (int64_t k = first_cell(start) - 1; k >= first_cell(end); --k)
            if (layer_blocked(box, axis, k, solid)) {
                moved = std::min(0.0, double(k + 1) - start);
                break;
            }
    }
    m_feet[axis] += moved;
    return moved;
}

void Player::step(double dt, const MoveIntent& intent, const SolidQuery& solid) {
    if (!m_walking) { // Fly: no collision, so the camera goes anywhere (as in creative flight).
        m_velocity = intent.wish * m_params.fly_speed;
        m_feet += m_velocity * dt;
        m_on_ground = false;
        return;
    }
    glm::dvec3 horizontal(intent.wish.x, 0.0, intent.wish.z);
    m_velocity.x = horizontal.x * m_params.walk_speed;
    m_velocity.z = horizontal.z * m_params.walk_speed;
    if (intent.jump && m_on_ground)
        m_velocity.y = m_params.jump_speed;
    m_velocity.y = std::max(m_velocity.y - m_params.gravity * dt, -m_params.max_fall_speed);

    const double want_y = m_velocity.y * dt;
    const double got_y = move_axis(1, want_y, solid);
    m_on_ground = want_y < 0 && got_y > want_y;
    if (got_y != want_y)
        m_velocity.y = 0.0;
    for (int axis : {0, 2}) {
        const double want = m_velocity[axis] * dt;
        if (move_axis(axis, want, solid) != want)
            m_velocity[axis] = 0.0;
    }
    // Standing still on the ground: probe below, so walking off a ledge starts a fall.
    if (m_on_ground && move_axis(1, -kEps * 10, solid) != 0.0)
        m_on_ground = false;
}

bool Player::overlaps_block(vx::BlockPos b) const {
    const double hw = m_params.half_width;
    const glm::dvec3 lo = m_feet - glm::dvec3(hw, 0.0, hw), hi = m_feet + glm::dvec3(hw, m_params.height, hw);
    for (int a = 0; a < 3; ++a)
        if (double(b[a]) >= hi[a] - kEps || double(b[a] + 1) <= lo[a] + kEps)
            return false;
    return true;
}

bool Player::inside_solid(const SolidQuery& solid) const {
    const double hw = m_params.half_width;
    const Box box{m_feet - glm::dvec3(hw, 0.0, hw), m_feet + glm::dvec3(hw, m_params.height, hw)};
    for (int64_t y = first_cell(box.min.y); y <= last_cell(box.max.y); ++y)
        if (layer_blocked(box, 1, y, solid))
            return true;
    return false;
}

} // namespace sandbox
