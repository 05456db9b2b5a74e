#include "engine/tasks/pendulum/pendulum_task.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string_view>

#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/continuous_table.hpp"
#include "engine/tasks/continuous_task.hpp"
#include "sims/pendulum/pendulum.hpp"

namespace ggk::engine {

namespace {

namespace pendulum = sims::pendulum;

struct PendulumTask {
  pendulum::PendulumConfig pendulum;
  double start_perturbation = 0.1;  // rad and rad/s
  ContinuousProtocol protocol;
};

constexpr std::array<std::string_view, 16> kKeys = {"series",
                                                    "steps_per_series",
                                                    "test_episodes",
                                                    "test_max_steps",
                                                    "som",
                                                    "scale",
                                                    "pendulum_mass",
                                                    "cart_mass",
                                                    "length",
                                                    "gravity",
                                                    "force",
                                                    "noise",
                                                    "dt",
                                                    "integrator",
                                                    "substeps",
                                                    "start_perturbation"};
constexpr std::array<std::string_view, 2> kIntegrators = {"rk4", "euler"};

PendulumTask parse_table(const TomlTableReader& job, const std::filesystem::path&) {
  const TomlTableReader table = job.subtable_or_empty("pendulum", kKeys);
  PendulumTask task;
  pendulum::PendulumConfig& p = task.pendulum;
  const NumberRange positive = NumberRange::above(0.0);
  p.pendulum_mass = table.number("pendulum_mass", positive, p.pendulum_mass);
  p.cart_mass = table.number("cart_mass", positive, p.cart_mass);
  p.length = table.number("length", positive, p.length);
  p.gravity = table.number("gravity", NumberRange::at_least(0.0), p.gravity);
  p.force = table.number("force", NumberRange::at_least(0.0), p.force);
  p.noise = table.number("noise", NumberRange::at_least(0.0), p.noise);
  p.dt = table.number("dt", positive, p.dt);
  p.integrator = table.choice("integrator", kIntegrators, "rk4") == "euler"
                     ? pendulum::Integrator::euler
                     : pendulum::Integrator::rk4;
  p.substeps = static_cast<std::int32_t>(table.integer("substeps", {1, 10'000}, p.substeps));
  task.start_perturbation =
      table.number("start_perturbation", NumberRange::half_open(0.0, 1.5), task.start_perturbation);
  ContinuousProtocol defaults;
  defaults.series = 1000;  // random episodes, each ended by a fall (about 6 steps)
  defaults.steps_per_series = 100;
  defaults.test_episodes = 10;
  defaults.test_max_steps = 3000;  // the paper's 5 minutes of balancing
  defaults.som_grid_from_samples = true;
  // Angles within +-pi/2 (beyond, the pendulum has fallen); velocities within
  // +-sqrt(3 g / (2 l)), the speed of an unforced fall from upright to the
  // horizontal with the cart's reaction neglected.
  const std::array<ObservationDimension, 2> dimensions = {
      {{"angle", std::numbers::pi}, {"velocity", 2.0 * std::sqrt(1.5 * p.gravity / p.length)}}};
  task.protocol = read_continuous_protocol(table, defaults, dimensions);
  check_kernel_widths(job, continuous_distance_scale(task.protocol, 2));
  return task;
}

class PendulumEpisode final : public ContinuousEpisode {
 public:
  explicit PendulumEpisode(const PendulumTask& task) : task_(task) {}
  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    const double p = task_.start_perturbation;
    state_.angle = random.uniform(-p, p);
    state_.velocity = random.uniform(-p, p);
    observe(observation);
  }
  void start_test(kernels::RandomStream& random, std::span<double> observation) override {
    start_walk(random, observation);
  }
  ContinuousStep step(std::int32_t action, kernels::RandomStream& random,
                      std::span<double> observation) override {
    const double force = pendulum::applied_force(task_.pendulum, action, random);
    state_ = pendulum::integrate(task_.pendulum, state_, force);
    observe(observation);
    const bool fell = pendulum::fallen(state_);
    return {fell ? -1.0 : 0.0, fell, false, false};
  }
  void trace(std::vector<double>& out) const override {
    out.insert(out.end(), {state_.angle, state_.velocity});
  }

 private:
  void observe(std::span<double> observation) const {
    observation[0] = state_.angle;
    observation[1] = state_.velocity;
  }
  const PendulumTask& task_;
  pendulum::State state_;
};

// The share of test episodes that ended before the cap (a fraction).
constexpr char kEnded[] = "fall_fraction";

ContinuousEnvironment environment(const PendulumTask& task) {
  ContinuousEnvironment env;
  env.observation_dimension = 2;
  env.num_actions = pendulum::kNumActions;
  env.action_names = {"left", "none", "right"};
  env.new_episode = [&task] { return std::make_unique<PendulumEpisode>(task); };
  env.trace_dimension = 2;
  env.ended_metric = kEnded;
  env.reward_low = -1.0;  // -1 when it falls, else 0
  env.reward_high = 0.0;
  return env;
}

// A run's memory follows its samples: random episodes fall after 8.9 steps on
// average (20 x 1000 in jobs/pendulum.toml; 99.9 % within 23, the longest 28),
// so a series counts 20 steps, over twice the mean.
ContinuousSizes sizes(const PendulumTask&) {
  return {2.0, pendulum::kNumActions, 2.0, 0.0, 0.0, 20.0};
}

}  // namespace

TaskDefinition pendulum_task_definition() {
  return continuous_task_definition<parse_table, environment, sizes>("pendulum");
}

}  // namespace ggk::engine
