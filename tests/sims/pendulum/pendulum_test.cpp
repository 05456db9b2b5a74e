// Lagoudakis & Parr's inverted pendulum (sims/pendulum): a fixed force sequence
// against RK4 and Euler written out by hand from the paper's equation (to
// 1e-12), the noise's bounds, and the fall's edge.

#include "sims/pendulum/pendulum.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/random_stream.hpp"

namespace ggk::sims::pendulum {
namespace {

// theta'' = (g sin th - a m l w^2 sin(2 th) / 2 - a cos(th) u) / (4 l / 3 - a m l cos^2 th)
double paper_acceleration(double th, double w, double u) {
  const double m = 2.0, big_m = 8.0, l = 0.5, g = 9.8, a = 1.0 / (m + big_m);
  return (g * std::sin(th) - a * m * l * w * w * std::sin(2.0 * th) / 2.0 - a * std::cos(th) * u) /
         (4.0 * l / 3.0 - a * m * l * std::cos(th) * std::cos(th));
}

TEST(Pendulum, Rk4AndEulerAgainstTheEquationByHand) {
  const std::vector<double> forces = {50.0, -50.0, 0.0, 37.5, -12.25, 50.0, 0.0, -50.0};
  PendulumConfig rk4;
  PendulumConfig euler;
  euler.integrator = Integrator::euler;
  State a{0.05, -0.1}, b{0.05, -0.1};
  double th = 0.05, w = -0.1, eth = 0.05, ew = -0.1;
  for (const double u : forces) {
    // RK4, ten steps of 0.01 s.
    for (int i = 0; i < 10; ++i) {
      const double h = 0.01;
      const double k1t = w, k1w = paper_acceleration(th, w, u);
      const double k2t = w + h / 2 * k1w, k2w = paper_acceleration(th + h / 2 * k1t, k2t, u);
      const double k3t = w + h / 2 * k2w, k3w = paper_acceleration(th + h / 2 * k2t, k3t, u);
      const double k4t = w + h * k3w, k4w = paper_acceleration(th + h * k3t, k4t, u);
      th += h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t);
      w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
    }
    a = integrate(rk4, a, u);
    EXPECT_NEAR(a.angle, th, 1e-12);
    EXPECT_NEAR(a.velocity, w, 1e-12);
    // Euler, one step of 0.1 s.
    const double acc = paper_acceleration(eth, ew, u);
    eth += 0.1 * ew;
    ew += 0.1 * acc;
    b = integrate(euler, b, u);
    EXPECT_NEAR(b.angle, eth, 1e-12);
    EXPECT_NEAR(b.velocity, ew, 1e-12);
  }
  // A push to the right accelerates the pole to the left (theta'' < 0 upright).
  EXPECT_LT(angular_acceleration(rk4, {0.0, 0.0}, 50.0), 0.0);
  EXPECT_EQ(angular_acceleration(rk4, {0.0, 0.0}, 0.0), 0.0);
}

TEST(Pendulum, NoiseIsUniformWithinItsBound) {
  const PendulumConfig c;
  kernels::RandomStream random(1, 2, 3);
  double lo = 1e9, hi = -1e9, sum = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double u = applied_force(c, 2, random) - 50.0;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    sum += u;
  }
  EXPECT_GE(lo, -10.0);
  EXPECT_LT(hi, 10.0);
  EXPECT_LT(lo, -9.9);
  EXPECT_GT(hi, 9.9);
  EXPECT_NEAR(sum / 20000, 0.0, 0.1);
  PendulumConfig quiet = c;
  quiet.noise = 0.0;
  EXPECT_EQ(applied_force(quiet, 0, random), -50.0);
  EXPECT_EQ(applied_force(quiet, 1, random), 0.0);
}

TEST(Pendulum, FallsAtHalfPi) {
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  EXPECT_TRUE(fallen({kHalfPi, 0.0}));
  EXPECT_TRUE(fallen({-kHalfPi, 0.0}));
  EXPECT_FALSE(fallen({std::nextafter(kHalfPi, 0.0), 5.0}));
  EXPECT_FALSE(fallen({0.0, 100.0}));
}

}  // namespace
}  // namespace ggk::sims::pendulum
