#pragma once
// The acrobot (Sutton 1996; Sutton & Barto 2018, sec. 11.3) with Gymnasium
// Acrobot-v1's constants and update ("book" dynamics): two links of length 1 m
// and mass 1 kg, centres of mass at 0.5 m, moments of inertia 1, g = 9.8; a
// torque of -1, 0 or +1 on the joint between the links (plus uniform noise in
// +-torque_noise, 0 as Gymnasium's default), held for one RK4 step of 0.2 s;
// the angles then wrapped into [-pi, pi], the velocities clipped to +-4 pi and
// +-9 pi. Terminal when the tip rises above the bar:
// -cos(theta1) - cos(theta1 + theta2) > 1; reward -1 a step, 0 at the end.
// Observation (Gymnasium's): cos theta1, sin theta1, cos theta2, sin theta2,
// theta1', theta2'.
//
// Thread-safety: pure functions of their arguments.

#include <array>
#include <cstdint>
#include <numbers>

namespace ggk::sims::acrobot {

inline constexpr std::int32_t kNumActions = 3;  // torque -1, 0, +1
inline constexpr double kMaxVelocity1 = 4.0 * std::numbers::pi;
inline constexpr double kMaxVelocity2 = 9.0 * std::numbers::pi;

struct AcrobotConfig {
  double link_length_1 = 1.0;
  double link_mass_1 = 1.0;
  double link_mass_2 = 1.0;
  double link_com_1 = 0.5;
  double link_com_2 = 0.5;
  double link_moment_of_inertia = 1.0;
  double gravity = 9.8;
  double dt = 0.2;
  double torque_noise = 0.0;
};

// theta1, theta2, theta1', theta2'.
using State = std::array<double, 4>;

// The time derivative of `state` under `torque` (Gymnasium's _dsdt, "book").
State derivative(const AcrobotConfig& config, const State& state, double torque);

// One control step: Gymnasium's rk4 over [0, dt], then the wrap and the clip.
State step(const AcrobotConfig& config, const State& state, double torque);

bool tip_above_bar(const State& state);

std::array<double, 6> observation(const State& state);

}  // namespace ggk::sims::acrobot
