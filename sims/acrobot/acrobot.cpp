#include "sims/acrobot/acrobot.hpp"

#include <algorithm>
#include <cmath>

namespace ggk::sims::acrobot {

namespace {

constexpr double kPi = std::numbers::pi;

// Gymnasium's wrap(x, m, M): shifted by the period until inside [m, M].
double wrap(double x, double m, double big_m) {
  const double diff = big_m - m;
  while (x > big_m) x = x - diff;
  while (x < m) x = x + diff;
  return x;
}

}  // namespace

// Transcribed term by term from Gymnasium's Acrobot-v1 (_dsdt), in its order.
State derivative(const AcrobotConfig& c, const State& s, double a) {
  const double m1 = c.link_mass_1, m2 = c.link_mass_2, l1 = c.link_length_1;
  const double lc1 = c.link_com_1, lc2 = c.link_com_2;
  const double i1 = c.link_moment_of_inertia, i2 = c.link_moment_of_inertia, g = c.gravity;
  const double theta1 = s[0], theta2 = s[1], dtheta1 = s[2], dtheta2 = s[3];
  const double d1 =
      m1 * (lc1 * lc1) + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * std::cos(theta2)) + i1 + i2;
  const double d2 = m2 * (lc2 * lc2 + l1 * lc2 * std::cos(theta2)) + i2;
  const double phi2 = m2 * lc2 * g * std::cos(theta1 + theta2 - kPi / 2.0);
  const double phi1 = -m2 * l1 * lc2 * (dtheta2 * dtheta2) * std::sin(theta2) -
                      2 * m2 * l1 * lc2 * dtheta2 * dtheta1 * std::sin(theta2) +
                      (m1 * lc1 + m2 * l1) * g * std::cos(theta1 - kPi / 2) + phi2;
  const double ddtheta2 =
      (a + d2 / d1 * phi1 - m2 * l1 * lc2 * (dtheta1 * dtheta1) * std::sin(theta2) - phi2) /
      (m2 * (lc2 * lc2) + i2 - (d2 * d2) / d1);
  const double ddtheta1 = -(d2 * ddtheta2 + phi1) / d1;
  return {dtheta1, dtheta2, ddtheta1, ddtheta2};
}

State step(const AcrobotConfig& c, const State& s, double torque) {
  const double dt = c.dt, dt2 = dt / 2.0;
  const auto along = [](const State& y, double h, const State& k) {
    return State{y[0] + h * k[0], y[1] + h * k[1], y[2] + h * k[2], y[3] + h * k[3]};
  };
  const State k1 = derivative(c, s, torque);
  const State k2 = derivative(c, along(s, dt2, k1), torque);
  const State k3 = derivative(c, along(s, dt2, k2), torque);
  const State k4 = derivative(c, along(s, dt, k3), torque);
  State next;
  for (std::size_t i = 0; i < 4; ++i) {
    next[i] = s[i] + dt / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
  next[0] = wrap(next[0], -kPi, kPi);
  next[1] = wrap(next[1], -kPi, kPi);
  next[2] = std::clamp(next[2], -kMaxVelocity1, kMaxVelocity1);
  next[3] = std::clamp(next[3], -kMaxVelocity2, kMaxVelocity2);
  return next;
}

bool tip_above_bar(const State& s) {
  return -std::cos(s[0]) - std::cos(s[1] + s[0]) > 1.0;
}

std::array<double, 6> observation(const State& s) {
  return {std::cos(s[0]), std::sin(s[0]), std::cos(s[1]), std::sin(s[1]), s[2], s[3]};
}

}  // namespace ggk::sims::acrobot
