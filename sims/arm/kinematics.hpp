#pragma once
// Forward kinematics of the planar two-link arm. The shoulder angle is measured
// counter-clockwise from the +x axis, the elbow angle counter-clockwise from the
// direction of link 1 (elbow 0 = arm stretched out):
//
//   elbow          = base  + link1 (cos s, sin s)
//   end_effector   = elbow + link2 (cos(s + e), sin(s + e))
//
// Thread-safety: pure functions.

#include "sims/arm/arm_geometry.hpp"

namespace ggk::sims::arm {

struct ArmPose {
  Point2 base;          // shoulder joint
  Point2 elbow;         // end of link 1
  Point2 end_effector;  // end of link 2
};

// Angles in degrees.
ArmPose forward_kinematics(const ArmGeometry& geometry, double shoulder_deg, double elbow_deg);

}  // namespace ggk::sims::arm
