#pragma once
// Collision tests of the arm against its workspace. Links are closed line
// segments (no thickness), obstacles closed sets: meeting a boundary counts as a
// collision. The links collide neither with each other (the elbow may fold link 2
// back over link 1) nor with the object, which is only a target.
//
// Thread-safety: pure functions.

#include "sims/arm/arm_geometry.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {

// Whether the segment [a, b] meets the closed rectangle (Liang-Barsky clipping).
bool segment_meets_rectangle(Point2 a, Point2 b, const Rectangle& rectangle);

// Whether the segment [a, b] meets the closed disc (distance from the centre to
// the nearest point of the segment <= radius).
bool segment_meets_disc(Point2 a, Point2 b, const Disc& disc);

bool segment_meets_obstacle(Point2 a, Point2 b, const Obstacle& obstacle);

// Whether link 1 (base-elbow) or link 2 (elbow-end effector) meets any obstacle.
bool arm_collides(const ArmGeometry& geometry, const ArmPose& pose);

// Whether the end effector lies in the closed object disc.
bool touches_object(const ArmGeometry& geometry, const ArmPose& pose);

}  // namespace ggk::sims::arm
