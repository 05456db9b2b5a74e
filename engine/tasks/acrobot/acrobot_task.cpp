#include "engine/tasks/acrobot/acrobot_task.hpp"

#include <algorithm>
#include <array>
#include <memory>
#include <numbers>
#include <string_view>

#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/continuous_table.hpp"
#include "engine/tasks/continuous_task.hpp"
#include "sims/acrobot/acrobot.hpp"

namespace ggk::engine {

namespace {

namespace acrobot = sims::acrobot;

struct AcrobotTask {
  acrobot::AcrobotConfig acrobot;
  bool walk_from_reset = false;
  ContinuousProtocol protocol;
};

constexpr std::array<std::string_view, 9> kKeys = {
    "series", "steps_per_series", "test_episodes", "test_max_steps", "som", "scale", "torque_noise",
    "dt",     "walk_start"};
constexpr std::array<std::string_view, 2> kWalkStarts = {"state_box", "reset"};
// Gymnasium's observation box: cos and sin in [-1, 1], velocities in +-4 pi, +-9 pi.
constexpr std::array<ObservationDimension, 6> kDimensions = {
    {{"cos_theta1", 2.0},
     {"sin_theta1", 2.0},
     {"cos_theta2", 2.0},
     {"sin_theta2", 2.0},
     {"velocity1", 2.0 * acrobot::kMaxVelocity1},
     {"velocity2", 2.0 * acrobot::kMaxVelocity2}}};

AcrobotTask parse_table(const TomlTableReader& job, const std::filesystem::path&) {
  const TomlTableReader table = job.subtable_or_empty("acrobot", kKeys);
  AcrobotTask task;
  task.acrobot.torque_noise =
      table.number("torque_noise", NumberRange::at_least(0.0), task.acrobot.torque_noise);
  task.acrobot.dt = table.number("dt", NumberRange::above(0.0), task.acrobot.dt);
  task.walk_from_reset = table.choice("walk_start", kWalkStarts, "state_box") == "reset";
  ContinuousProtocol defaults;
  defaults.series = 200;
  defaults.steps_per_series = 100;
  defaults.test_episodes = 10;
  defaults.test_max_steps = 500;  // Gymnasium's TimeLimit for Acrobot-v1
  defaults.som_grid_from_samples = true;
  task.protocol = read_continuous_protocol(table, defaults, kDimensions);
  check_kernel_widths(job, continuous_distance_scale(task.protocol, 6));
  return task;
}

class AcrobotEpisode final : public ContinuousEpisode {
 public:
  explicit AcrobotEpisode(const AcrobotTask& task) : task_(task) {}
  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    if (task_.walk_from_reset) return start_test(random, observation);
    constexpr double kPi = std::numbers::pi;
    state_ = {random.uniform(-kPi, kPi), random.uniform(-kPi, kPi),
              random.uniform(-acrobot::kMaxVelocity1, acrobot::kMaxVelocity1),
              random.uniform(-acrobot::kMaxVelocity2, acrobot::kMaxVelocity2)};
    observe(observation);
  }
  void start_test(kernels::RandomStream& random, std::span<double> observation) override {
    for (double& x : state_) x = random.uniform(-0.1, 0.1);  // Gymnasium's reset
    observe(observation);
  }
  ContinuousStep step(std::int32_t action, kernels::RandomStream& random,
                      std::span<double> observation) override {
    const double noise = task_.acrobot.torque_noise;
    const double torque = (action - 1) + (noise > 0.0 ? random.uniform(-noise, noise) : 0.0);
    state_ = acrobot::step(task_.acrobot, state_, torque);
    observe(observation);
    const bool up = acrobot::tip_above_bar(state_);
    return {up ? 0.0 : -1.0, up, false, false};
  }
  void trace(std::vector<double>& out) const override {
    out.insert(out.end(), state_.begin(), state_.end());
  }

 private:
  void observe(std::span<double> observation) const {
    const std::array<double, 6> o = acrobot::observation(state_);
    std::copy(o.begin(), o.end(), observation.begin());
  }
  const AcrobotTask& task_;
  acrobot::State state_{};
};

// The share of test episodes that ended before the cap (a fraction).
constexpr char kEnded[] = "success_rate";

ContinuousEnvironment environment(const AcrobotTask& task) {
  ContinuousEnvironment env;
  env.observation_dimension = 6;
  env.num_actions = acrobot::kNumActions;
  env.action_names = {"torque_minus", "torque_zero", "torque_plus"};
  env.new_episode = [&task] { return std::make_unique<AcrobotEpisode>(task); };
  env.trace_dimension = 4;  // theta1, theta2, theta1', theta2'
  env.ended_metric = kEnded;
  env.reward_low = -1.0;  // -1 a step, 0 at the end
  env.reward_high = 0.0;
  return env;
}

ContinuousSizes sizes(const AcrobotTask&) {
  return {6.0, acrobot::kNumActions, 4.0, 0.0, 0.0};
}

}  // namespace

TaskDefinition acrobot_task_definition() {
  return continuous_task_definition<parse_table, environment, sizes>("acrobot");
}

}  // namespace ggk::engine
