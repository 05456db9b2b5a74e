#include "sims/arm/kinematics.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "sims/arm/arm_test_helpers.hpp"

#include "sims/arm/arm.hpp"
#include "sims/arm/arm_geometry.hpp"
#include "sims/arm/collision.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {
namespace {

using namespace test_helpers;

TEST(ArmKinematics, HandComputedPoses) {
  ArmGeometry geometry;
  geometry.link1_length = 2.0;
  geometry.link2_length = 1.0;
  geometry.base = {1.0, 0.5};

  ArmPose pose = forward_kinematics(geometry, 0.0, 0.0);  // stretched along +x
  expect_point(pose.base, 1.0, 0.5);
  expect_point(pose.elbow, 3.0, 0.5);
  expect_point(pose.end_effector, 4.0, 0.5);

  pose = forward_kinematics(geometry, 90.0, 0.0);  // straight up
  expect_point(pose.elbow, 1.0, 2.5);
  expect_point(pose.end_effector, 1.0, 3.5);

  pose = forward_kinematics(geometry, 90.0, -90.0);  // up, forearm to the right
  expect_point(pose.elbow, 1.0, 2.5);
  expect_point(pose.end_effector, 2.0, 2.5);

  pose = forward_kinematics(geometry, 180.0, -180.0);  // left, folded back to the right
  expect_point(pose.elbow, -1.0, 0.5);
  expect_point(pose.end_effector, 0.0, 0.5);

  pose = forward_kinematics(geometry, 45.0, 90.0);
  const double h = std::sqrt(0.5);
  expect_point(pose.elbow, 1.0 + 2.0 * h, 0.5 + 2.0 * h);
  expect_point(pose.end_effector, 1.0 + 2.0 * h - h, 0.5 + 2.0 * h + h);

  pose = forward_kinematics(geometry, 30.0, -60.0);
  expect_point(pose.elbow, 1.0 + 2.0 * std::cos(deg(30)), 0.5 + 2.0 * std::sin(deg(30)));
  expect_point(pose.end_effector, pose.elbow.x + std::cos(deg(-30)),
               pose.elbow.y + std::sin(deg(-30)));
}
}  // namespace
}  // namespace ggk::sims::arm
