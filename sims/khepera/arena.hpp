#pragma once
// The Khepera's world as a job file describes it (plain data; the engine's
// job-file parser fills it from an arena table, jobs/arenas/default.toml).
// Lengths in centimetres.

#include <vector>

#include "sims/khepera/geometry.hpp"
#include "sims/khepera/pose.hpp"

namespace ggk::sims::khepera {

struct Arena {
  // The arena's box [min, max]. Random start poses are drawn inside it; when
  // `walled`, its four sides are walls (segments) as well.
  Point2 min{0.0, 0.0};
  Point2 max{100.0, 100.0};
  bool walled = true;
  // Walls and obstacles inside (or across) the box, in any order.
  std::vector<Shape> obstacles;
  // The fixed start pose of the evaluation episodes (paper sec. 4.2): inside the
  // box, the body clear of every wall and obstacle.
  Pose start;
};

}  // namespace ggk::sims::khepera
