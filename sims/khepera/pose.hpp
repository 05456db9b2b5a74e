#pragma once
// Pose of the robot in the arena: the centre of its body disc (cm) and the
// direction it faces, in radians counter-clockwise from the x axis, kept in
// [-pi, pi). Plain data.

#include <cmath>
#include <numbers>

namespace ggk::sims::khepera {

struct Pose {
  double x = 0.0;
  double y = 0.0;
  double heading = 0.0;
  friend bool operator==(const Pose&, const Pose&) = default;
};

// `angle` (radians, finite) wrapped into [-pi, pi).
inline double wrap_angle(double angle) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double wrapped = std::fmod(angle + std::numbers::pi, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  wrapped -= std::numbers::pi;
  // Rounding can land exactly on pi; keep the interval half-open.
  return wrapped >= std::numbers::pi ? -std::numbers::pi : wrapped;
}

inline double degrees_to_radians(double degrees) {
  return degrees * (std::numbers::pi / 180.0);
}

}  // namespace ggk::sims::khepera
