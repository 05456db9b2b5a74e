#pragma once
// Workspace of the two-joint arm (paper sec. 4.1, Fig. 1(a)): two links hinged at a
// fixed base, obstacles (closed axis-aligned rectangles and closed discs) and the
// object to reach (a disc). Plain data; lengths in one arbitrary unit. The job
// file gives every value (jobs/arm-paper.toml); nothing here has a calibrated
// default.

#include <variant>
#include <vector>

namespace ggk::sims::arm {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

// The closed box [min.x, max.x] x [min.y, max.y]; min <= max in both coordinates.
struct Rectangle {
  Point2 min;
  Point2 max;
  friend bool operator==(const Rectangle&, const Rectangle&) = default;
};

// The closed disc of `radius` > 0 around `center`.
struct Disc {
  Point2 center;
  double radius = 1.0;
  friend bool operator==(const Disc&, const Disc&) = default;
};

using Obstacle = std::variant<Rectangle, Disc>;

struct ArmGeometry {
  double link1_length = 1.0;  // shoulder (at base) to elbow, > 0
  double link2_length = 1.0;  // elbow to end effector, > 0
  Point2 base;                // the shoulder joint
  std::vector<Obstacle> obstacles;
  // The end effector touches the object when it lies in this closed disc. The
  // object is a target, not an obstacle: the links may pass over it (a flat
  // object on the table the arm moves above, in the top view of Fig. 1(a)).
  Disc object;
};

// Throws ArmConfigError (arm_config_error.hpp) for the first bad field: a
// non-finite number, a link length or radius <= 0, a rectangle with min > max.
void check_geometry(const ArmGeometry& geometry);

}  // namespace ggk::sims::arm
