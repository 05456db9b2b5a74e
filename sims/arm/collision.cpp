#include "sims/arm/collision.hpp"

#include <algorithm>

namespace ggk::sims::arm {

bool segment_meets_rectangle(Point2 a, Point2 b, const Rectangle& rectangle) {
  // Points a + t (b - a), t in [0, 1]. Each of the four slab inequalities
  // p t <= q narrows [t_enter, t_leave]; the segment meets the box iff the
  // interval stays non-empty.
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  double t_enter = 0.0;
  double t_leave = 1.0;
  const auto clip = [&](double p, double q) {
    if (p == 0.0) return q >= 0.0;  // parallel to this slab: inside it or never
    const double t = q / p;
    if (p < 0.0) {
      t_enter = std::max(t_enter, t);
    } else {
      t_leave = std::min(t_leave, t);
    }
    return t_enter <= t_leave;
  };
  return clip(-dx, a.x - rectangle.min.x) && clip(dx, rectangle.max.x - a.x) &&
         clip(-dy, a.y - rectangle.min.y) && clip(dy, rectangle.max.y - a.y);
}

bool segment_meets_disc(Point2 a, Point2 b, const Disc& disc) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const double length_squared = dx * dx + dy * dy;
  double t = 0.0;  // nearest point a + t (b - a) to the centre
  if (length_squared > 0.0) {
    t = ((disc.center.x - a.x) * dx + (disc.center.y - a.y) * dy) / length_squared;
    t = std::clamp(t, 0.0, 1.0);
  }
  const double ex = a.x + t * dx - disc.center.x;
  const double ey = a.y + t * dy - disc.center.y;
  return ex * ex + ey * ey <= disc.radius * disc.radius;
}

bool segment_meets_obstacle(Point2 a, Point2 b, const Obstacle& obstacle) {
  if (const auto* rectangle = std::get_if<Rectangle>(&obstacle)) {
    return segment_meets_rectangle(a, b, *rectangle);
  }
  return segment_meets_disc(a, b, std::get<Disc>(obstacle));
}

bool arm_collides(const ArmGeometry& geometry, const ArmPose& pose) {
  const auto link_meets = [&](const Obstacle& obstacle) {
    return segment_meets_obstacle(pose.base, pose.elbow, obstacle) ||
           segment_meets_obstacle(pose.elbow, pose.end_effector, obstacle);
  };
  return std::any_of(geometry.obstacles.begin(), geometry.obstacles.end(), link_meets);
}

bool touches_object(const ArmGeometry& geometry, const ArmPose& pose) {
  const double dx = pose.end_effector.x - geometry.object.center.x;
  const double dy = pose.end_effector.y - geometry.object.center.y;
  return dx * dx + dy * dy <= geometry.object.radius * geometry.object.radius;
}

}  // namespace ggk::sims::arm
