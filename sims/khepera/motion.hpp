#pragma once
// The four actions and differential-drive kinematics of the Khepera.
//
// An action is a fixed wheel command held for one control step, written as the
// distance each wheel rolls during the step (cm). With the defaults:
//   forward:      both wheels +1.5 cm             -> the centre moves 1.5 cm ahead;
//   rotate left:  left -b t / 2, right +b t / 2   -> the heading turns t = 15 deg
//                 counter-clockwise on the spot (b = wheel base: 0.68 cm per wheel);
//   rotate right: the mirror image (15 deg clockwise);
//   backward:     both wheels -1.5 cm.
// Each wheel's actual travel is its command times its own factor drawn from
// U[1 - wheel_noise, 1 + wheel_noise) (slip, motor noise), so a noisy forward step
// curves slightly and a noisy rotation drifts the centre a little.
//
// Thread-safety: plain data and pure functions.

#include <cstdint>
#include <string_view>

#include "sims/khepera/pose.hpp"

namespace ggk::sims::khepera {

// Actions in the paper's order (sec. 4.2).
inline constexpr std::int32_t kForward = 0;
inline constexpr std::int32_t kRotateLeft = 1;   // counter-clockwise
inline constexpr std::int32_t kRotateRight = 2;  // clockwise
inline constexpr std::int32_t kBackward = 3;
inline constexpr std::int32_t kNumActions = 4;

// "forward", "left", "right", "backward"; throws std::out_of_range otherwise.
std::string_view action_name(std::int32_t action);
// Throws std::out_of_range unless 0 <= action < kNumActions.
void check_action(std::int32_t action);

struct MotionModel {
  double step_cm = 1.5;       // > 0; forward/backward distance of the centre per step
  double turn_deg = 15.0;     // (0, 180); heading change per rotate step
  double wheel_noise = 0.05;  // [0, 1); each wheel's travel x U[1 - n, 1 + n)
  // The body is tested for overlap at this many evenly spaced points along the
  // step's arc (the last one the end pose), >= 1. With 1.5 cm steps and 4
  // sub-steps the body sweeps past nothing more than 0.01 cm unseen.
  std::int32_t collision_substeps = 4;
  friend bool operator==(const MotionModel&, const MotionModel&) = default;
};

// Distance each wheel rolls during one control step, cm (negative: backwards).
struct WheelTravel {
  double left = 0.0;
  double right = 0.0;
  friend bool operator==(const WheelTravel&, const WheelTravel&) = default;
};

// The noiseless command of `action`; throws std::out_of_range for a bad action.
WheelTravel wheel_command(const MotionModel& motion, double wheel_base, std::int32_t action);

// The pose after the wheels roll `travel` at constant speeds: exact integration of
// the differential drive (a circular arc of heading change (right - left) /
// wheel_base, or a straight line when the two are equal).
Pose drive(const Pose& pose, WheelTravel travel, double wheel_base);

}  // namespace ggk::sims::khepera
