#include "sims/mountain_car/mountain_car.hpp"

#include <algorithm>
#include <cmath>

namespace ggk::sims::mountain_car {

State step(const MountainCarConfig& c, State s, std::int32_t action) {
  // Gymnasium's `velocity += (action - 1) * force + cos(3 * position) * (-gravity)`,
  // summed in its order.
  double velocity = s.velocity + ((action - 1) * c.force + std::cos(3.0 * s.position) * -c.gravity);
  velocity = std::clamp(velocity, -c.max_speed, c.max_speed);
  double position = std::clamp(s.position + velocity, c.min_position, c.max_position);
  if (position == c.min_position && velocity < 0.0) velocity = 0.0;
  return {position, velocity};
}

bool at_goal(const MountainCarConfig& c, State s) {
  return s.position >= c.goal_position && s.velocity >= c.goal_velocity;
}

}  // namespace ggk::sims::mountain_car
