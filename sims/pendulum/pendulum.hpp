#pragma once
// The inverted pendulum on a cart of Lagoudakis & Parr (JMLR 4, 2003, sec. 9.2;
// from Wang, Tanaka & Griffin 1996): state (angle theta from upright, angular
// velocity), a force u on the cart of -50, 0 or +50 N plus uniform noise in
// [-noise, noise], held for dt = 0.1 s;
//   theta'' = (g sin theta - alpha m l theta'^2 sin(2 theta) / 2 - alpha cos(theta) u)
//             / (4 l / 3 - alpha m l cos^2 theta),   alpha = 1 / (m + M),
// m = 2 kg, M = 8 kg, l = 0.5 m, g = 9.8 m/s^2. The pendulum has fallen (reward
// -1, terminal) when |theta| >= pi / 2, else reward 0. The paper names no
// integrator: RK4 over `substeps` equal steps of dt (default 10: within 3.1e-7 of
// an adaptive solver over a control step, jobs/README.md) or one explicit Euler step.
//
// Thread-safety: pure functions of their arguments.

#include <cstdint>

#include "kernels/random_stream.hpp"

namespace ggk::sims::pendulum {

inline constexpr std::int32_t kNumActions = 3;  // 0 left (-force), 1 none, 2 right (+force)

enum class Integrator { rk4, euler };

struct PendulumConfig {
  double pendulum_mass = 2.0;  // m, kg
  double cart_mass = 8.0;      // M, kg
  double length = 0.5;         // l, m (some copies use 0.25: a key, not a guess)
  double gravity = 9.8;        // m/s^2
  double force = 50.0;         // N, the magnitude of a push
  double noise = 10.0;         // N, uniform noise on every action's force
  double dt = 0.1;             // s, the control step
  Integrator integrator = Integrator::rk4;
  std::int32_t substeps = 10;  // RK4 steps per control step
};

struct State {
  double angle = 0.0;     // rad, 0 = upright
  double velocity = 0.0;  // rad/s
};

// theta'' at `state` under force u (N).
double angular_acceleration(const PendulumConfig& config, State state, double force);

// The state after dt under the constant force u (no noise added here).
State integrate(const PendulumConfig& config, State state, double force);

// The force of `action` plus its noise, one uniform from `random`.
double applied_force(const PendulumConfig& config, std::int32_t action,
                     kernels::RandomStream& random);

bool fallen(State state);  // |theta| >= pi / 2

}  // namespace ggk::sims::pendulum
