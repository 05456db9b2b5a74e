#pragma once
// What the Khepera sims tests share: F written out by hand, an open arena
// without noise, one wall.

#include <utility>
#include <vector>

#include "sims/khepera/khepera.hpp"

namespace ggk::sims::khepera::test_helpers {

// F of DESIGN.md sec. 3 written out with the default constants.
inline double hand_f(double x) {
  if (x > 10.0) return 0.0;
  return 1200.0 * (7.0 - 0.81) / (x * x + 1.8 * x + 7.0);
}

// A config whose arena has only the given obstacles (no box walls), noise off.
inline KheperaConfig open_config(std::vector<Shape> obstacles, Pose start = {50.0, 50.0, 0.0}) {
  KheperaConfig config;
  config.arena.walled = false;
  config.arena.obstacles = std::move(obstacles);
  config.arena.start = start;
  config.sensors.noise_fraction = 0.0;
  config.sensors.noise_sd = 0.0;
  config.motion.wheel_noise = 0.0;
  return config;
}

// A vertical wall x = 60 from y = 0 to y = 100.
inline const Shape kWallAt60 = Segment{{60.0, 0.0}, {60.0, 100.0}};

}  // namespace ggk::sims::khepera::test_helpers
