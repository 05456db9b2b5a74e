#include "sims/pendulum/pendulum.hpp"

#include <cmath>
#include <numbers>

namespace ggk::sims::pendulum {

double angular_acceleration(const PendulumConfig& c, State s, double force) {
  const double alpha = 1.0 / (c.pendulum_mass + c.cart_mass);
  const double m = c.pendulum_mass, l = c.length, cos_theta = std::cos(s.angle);
  return (c.gravity * std::sin(s.angle) -
          alpha * m * l * s.velocity * s.velocity * std::sin(2.0 * s.angle) / 2.0 -
          alpha * cos_theta * force) /
         (4.0 * l / 3.0 - alpha * m * l * cos_theta * cos_theta);
}

State integrate(const PendulumConfig& c, State s, double force) {
  if (c.integrator == Integrator::euler) {
    return {s.angle + c.dt * s.velocity, s.velocity + c.dt * angular_acceleration(c, s, force)};
  }
  const double h = c.dt / c.substeps;
  for (std::int32_t i = 0; i < c.substeps; ++i) {
    const auto slope = [&](State x) {
      return State{x.velocity, angular_acceleration(c, x, force)};
    };
    const State k1 = slope(s);
    const State k2 = slope({s.angle + h / 2.0 * k1.angle, s.velocity + h / 2.0 * k1.velocity});
    const State k3 = slope({s.angle + h / 2.0 * k2.angle, s.velocity + h / 2.0 * k2.velocity});
    const State k4 = slope({s.angle + h * k3.angle, s.velocity + h * k3.velocity});
    s = {
        s.angle + h / 6.0 * (k1.angle + 2.0 * k2.angle + 2.0 * k3.angle + k4.angle),
        s.velocity + h / 6.0 * (k1.velocity + 2.0 * k2.velocity + 2.0 * k3.velocity + k4.velocity)};
  }
  return s;
}

double applied_force(const PendulumConfig& c, std::int32_t action, kernels::RandomStream& random) {
  return (action - 1) * c.force + random.uniform(-c.noise, c.noise);
}

bool fallen(State s) {
  return std::abs(s.angle) >= std::numbers::pi / 2.0;
}

}  // namespace ggk::sims::pendulum
