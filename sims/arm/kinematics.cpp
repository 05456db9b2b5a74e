#include "sims/arm/kinematics.hpp"

#include <cmath>
#include <numbers>

namespace ggk::sims::arm {

ArmPose forward_kinematics(const ArmGeometry& geometry, double shoulder_deg, double elbow_deg) {
  constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
  const double shoulder = shoulder_deg * kRadiansPerDegree;
  const double forearm = (shoulder_deg + elbow_deg) * kRadiansPerDegree;
  ArmPose pose;
  pose.base = geometry.base;
  pose.elbow = {geometry.base.x + geometry.link1_length * std::cos(shoulder),
                geometry.base.y + geometry.link1_length * std::sin(shoulder)};
  pose.end_effector = {pose.elbow.x + geometry.link2_length * std::cos(forearm),
                       pose.elbow.y + geometry.link2_length * std::sin(forearm)};
  return pose;
}

}  // namespace ggk::sims::arm
