// The mountain car (sims/mountain_car): a fixed action sequence against the
// update written out by hand from Gymnasium's MountainCar-v0, and its edges:
// the speed limit, the left wall, the goal.

#include "sims/mountain_car/mountain_car.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::sims::mountain_car {
namespace {

TEST(MountainCar, FollowsGymnasiumsUpdate) {
  const MountainCarConfig c;
  State s{-0.5, 0.0};
  double x = -0.5, v = 0.0;
  const std::vector<std::int32_t> actions = {2, 2, 2, 0, 0, 1, 2, 0, 2, 2, 1, 0};
  for (const std::int32_t a : actions) {
    v += (a - 1) * 0.001 + std::cos(3 * x) * (-0.0025);
    v = std::min(std::max(v, -0.07), 0.07);
    x += v;
    x = std::min(std::max(x, -1.2), 0.6);
    if (x == -1.2 && v < 0) v = 0;
    s = step(c, s, a);
    EXPECT_NEAR(s.position, x, 1e-12);
    EXPECT_NEAR(s.velocity, v, 1e-12);
    EXPECT_EQ(s.position, x);  // the same operations in the same order: the same bits
    EXPECT_EQ(s.velocity, v);
  }
}

TEST(MountainCar, SpeedLimitLeftWallAndGoal) {
  const MountainCarConfig c;
  // The speed limit: a push at the limit stays at the limit.
  EXPECT_EQ(step(c, {-0.5236, 0.07}, 2).velocity, 0.07);  // cos(3 x) ~ 0: no gravity
  EXPECT_EQ(step(c, {-0.5236, -0.07}, 0).velocity, -0.07);
  // The left wall stops the car.
  const State wall = step(c, {-1.19, -0.05}, 0);
  EXPECT_EQ(wall.position, -1.2);
  EXPECT_EQ(wall.velocity, 0.0);
  // The goal: x >= 0.5 with v >= 0.
  EXPECT_TRUE(at_goal(c, {0.5, 0.0}));
  EXPECT_FALSE(at_goal(c, {std::nextafter(0.5, 0.0), 0.07}));
  EXPECT_FALSE(at_goal(c, {0.55, -1e-9}));
  // The right edge is clipped to max_position.
  EXPECT_EQ(step(c, {0.59, 0.07}, 2).position, 0.6);
}

}  // namespace
}  // namespace ggk::sims::mountain_car
