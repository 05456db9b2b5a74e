#include "sims/khepera/motion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "sims/khepera/khepera.hpp"

namespace ggk::sims::khepera {
namespace {

TEST(KheperaMotion, ArcsMatchFineNumericalIntegration) {
  const double b = 5.2;
  const Pose start{10.0, -3.0, 2.5};
  for (const WheelTravel travel :
       {WheelTravel{1.5, 1.5}, WheelTravel{-1.5, -1.5}, WheelTravel{1.43, 1.57},
        WheelTravel{-0.68, 0.68}, WheelTravel{0.7, -0.66}, WheelTravel{3.0, -1.0}}) {
    // Euler with 10^5 sub-steps of the wheel speeds.
    constexpr int kSteps = 100000;
    Pose p = start;
    for (int k = 0; k < kSteps; ++k) {
      const double ds = 0.5 * (travel.left + travel.right) / kSteps;
      const double dth = (travel.right - travel.left) / b / kSteps;
      p.x += ds * std::cos(p.heading + 0.5 * dth);
      p.y += ds * std::sin(p.heading + 0.5 * dth);
      p.heading += dth;
    }
    const Pose exact = drive(start, travel, b);
    EXPECT_NEAR(exact.x, p.x, 1e-9);
    EXPECT_NEAR(exact.y, p.y, 1e-9);
    EXPECT_NEAR(exact.heading, wrap_angle(p.heading), 1e-9);
  }
  // The documented commands: 1.5 cm ahead, 15 degrees on the spot.
  const MotionModel motion;
  const Pose ahead = drive(start, wheel_command(motion, b, kForward), b);
  EXPECT_NEAR(std::hypot(ahead.x - start.x, ahead.y - start.y), 1.5, 1e-12);
  EXPECT_EQ(ahead.heading, start.heading);
  const Pose left = drive(start, wheel_command(motion, b, kRotateLeft), b);
  EXPECT_NEAR(left.heading - start.heading, 15.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_NEAR(left.x, start.x, 1e-12);
  EXPECT_NEAR(left.y, start.y, 1e-12);
  const Pose right = drive(start, wheel_command(motion, b, kRotateRight), b);
  EXPECT_NEAR(right.heading - start.heading, -15.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_NEAR(wrap_angle(std::numbers::pi), -std::numbers::pi, 0.0);
  EXPECT_NEAR(wrap_angle(3.0 * std::numbers::pi + 0.25), -std::numbers::pi + 0.25, 1e-12);
}
}  // namespace
}  // namespace ggk::sims::khepera
