#pragma once
// What the arm sims tests share: degrees to radians, a point compared to 1e-12.

#include <numbers>

#include <gtest/gtest.h>

#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm::test_helpers {

inline constexpr double kTol = 1e-12;

inline double deg(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

inline void expect_point(const Point2& actual, double x, double y) {
  EXPECT_NEAR(actual.x, x, kTol);
  EXPECT_NEAR(actual.y, y, kTol);
}

}  // namespace ggk::sims::arm::test_helpers
