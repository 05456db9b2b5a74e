#pragma once
// Workspace of the two-joint arm (paper sec. 4.1, Fig. 1(a)): two links hinged at a
// fixed base, obstacles (closed axis-aligned rectangles and closed discs) and the
// object to reach (a disc). Plain data; lengths in one arbitrary unit. The job
// file gives every value (jobs/arm-paper.toml); nothing here has a calibrated
// default.

#include <variant>
#include <vector>

#include "sims/geometry.hpp"

namespace ggk::sims::arm {

// Obstacles are closed axis-aligned boxes (min <= max in both coordinates) and
// closed discs (radius > 0), as sims/geometry.hpp defines them.
using sims::Disc;
using sims::Point2;
using sims::Rectangle;

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
