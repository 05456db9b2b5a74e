#pragma once
// The mountain car (Moore 1990; Sutton & Barto 2018, ex. 10.1) with Gymnasium
// MountainCar-v0's constants and update: actions push left, none, push right;
//   v' = clip(v + (a - 1) force - cos(3 x) gravity, -max_speed, max_speed)
//   x' = clip(x + v', min_position, max_position), v' = 0 at the left wall
// terminal when x' >= goal_position and v' >= goal_velocity; reward -1 a step.
// Deterministic; Gymnasium's reset draws x ~ U(-0.6, -0.4), v = 0.
//
// Thread-safety: pure functions of their arguments.

#include <cstdint>

namespace ggk::sims::mountain_car {

inline constexpr std::int32_t kNumActions = 3;  // 0 push left, 1 no push, 2 push right

struct MountainCarConfig {
  double force = 0.001;
  double gravity = 0.0025;
  double max_speed = 0.07;
  double min_position = -1.2;
  double max_position = 0.6;
  double goal_position = 0.5;
  double goal_velocity = 0.0;
};

struct State {
  double position = 0.0;
  double velocity = 0.0;
};

// One step of MountainCar-v0 (an action outside 0..2 is a programmer error).
State step(const MountainCarConfig& config, State state, std::int32_t action);

// Whether `state` ends the episode (the goal).
bool at_goal(const MountainCarConfig& config, State state);

}  // namespace ggk::sims::mountain_car
