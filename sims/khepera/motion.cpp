#include "sims/khepera/motion.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ggk::sims::khepera {

std::string_view action_name(std::int32_t action) {
  check_action(action);
  constexpr std::string_view kNames[kNumActions] = {"forward", "left", "right", "backward"};
  return kNames[action];
}

void check_action(std::int32_t action) {
  if (action < 0 || action >= kNumActions)
    throw std::out_of_range("khepera: action " + std::to_string(action) + " is not in [0, " +
                            std::to_string(kNumActions) + ")");
}

WheelTravel wheel_command(const MotionModel& motion, double wheel_base, std::int32_t action) {
  check_action(action);
  // Turning on the spot by t radians rolls each wheel an arc of radius b / 2.
  const double turn = 0.5 * wheel_base * degrees_to_radians(motion.turn_deg);
  switch (action) {
    case kForward:
      return {motion.step_cm, motion.step_cm};
    case kRotateLeft:
      return {-turn, turn};
    case kRotateRight:
      return {turn, -turn};
    default:
      return {-motion.step_cm, -motion.step_cm};
  }
}

Pose drive(const Pose& pose, WheelTravel travel, double wheel_base) {
  const double distance = 0.5 * (travel.left + travel.right);  // arc length of the centre
  const double turn = (travel.right - travel.left) / wheel_base;
  // The centre moves along a chord of the arc: length distance * sin(h) / h with
  // h = turn / 2, in the direction of the mean heading. The series keeps sin(h) / h
  // accurate near h = 0 (straight moves), where the quotient would lose digits.
  const double half = 0.5 * turn;
  const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
  const double chord = distance * sinc;
  const double mid_heading = pose.heading + half;
  return {pose.x + chord * std::cos(mid_heading), pose.y + chord * std::sin(mid_heading),
          wrap_angle(pose.heading + turn)};
}

}  // namespace ggk::sims::khepera
