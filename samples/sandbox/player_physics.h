#pragma once
// The player: an axis-aligned box (0.6 × 1.8 × 0.6 blocks) that flies freely or walks with
// gravity, jumps, and collides with solid blocks. Collision sweeps the box one axis at a time
// (y, then x, then z) through the block layers it would enter and stops at the first solid one,
// so the box never ends inside a block, whatever the step length. No window, no engine: the
// world is a `solid` query (unloaded blocks count as solid, so nobody falls out of the world).
// Thread: plain values, not shared. Units: world blocks, seconds.
#include <functional>

#include <glm/glm.hpp>

#include <vx/types.h>

namespace sandbox {

// True when the block at a world position stops the player.
using SolidQuery = std::function<bool(vx::BlockPos)>;

struct PlayerParams {
    double half_width = 0.3;   // The box is 2·half_width wide in x and z.
    double height = 1.8;
    double eye_height = 1.62;  // Eye above the feet.
    double walk_speed = 4.3;   // Blocks per second.
    double fly_speed = 10.0;
    double gravity = 32.0;     // Blocks per second².
    double jump_speed = 9.0;   // Initial upward speed (about 1.27 blocks high).
    double max_fall_speed = 78.0;
};

// What the controls ask for this step.
struct MoveIntent {
    glm::dvec3 wish{0.0}; // Horizontal x/z from WASD in world space (length <= 1); y: +1 rise, -1 sink (fly).
    bool jump = false;    // Walk: jump if standing.
};

class Player {
public:
    explicit Player(PlayerParams params = {}) : m_params(params) {}

    // Feet centre (bottom middle of the box), world blocks.
    glm::dvec3 feet() const { return m_feet; }
    glm::dvec3 eye() const { return m_feet + glm::dvec3(0.0, m_params.eye_height, 0.0); }
    void set_feet(glm::dvec3 feet) { m_feet = feet; m_velocity = glm::dvec3(0.0); }
    void set_eye(glm::dvec3 eye) { set_feet(eye - glm::dvec3(0.0, m_params.eye_height, 0.0)); }
    bool walking() const { return m_walking; }
    void set_walking(bool walking) { m_walking = walking; m_velocity = glm::dvec3(0.0); }
    bool on_ground() const { return m_on_ground; }
    glm::dvec3 velocity() const { return m_velocity; }
    const PlayerParams& params() const { return m_params; }
    PlayerParams& params() { return m_params; }

    // Advances by dt seconds. Fly: moves freely at fly_speed. Walk: gravity, jump, collision.
    void step(double dt, const MoveIntent& intent, const SolidQuery& solid);
    // True when block `b` overlaps the player's box (a block must not be placed there).
    bool overlaps_block(vx::BlockPos b) const;
    // True when any solid block overlaps the box now.
    bool inside_solid(const SolidQuery& solid) const;

private:
    // Moves the box by `delta` along `axis`, stopping at the first solid layer; returns the
    // distance actually moved.
    double move_axis(int axis, double delta, const SolidQuery& solid);

    PlayerParams m_params;
    glm::dvec3 m_feet{0.0};
    glm::dvec3 m_velocity{0.0};
    bool m_walking = false;
    bool m_on_ground = false;
};

// The view direction for yaw and pitch in degrees: yaw 0 looks along −Z, yaw 90 along −X,
// positive pitch looks up.
glm::dvec3 view_forward(double yaw_degrees, double pitch_degrees);
// The horizontal right direction for yaw in degrees (yaw 0: +X).
glm::dvec3 view_right(double yaw_degrees);

} // namespace sandbox
