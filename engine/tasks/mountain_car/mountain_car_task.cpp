#include "engine/tasks/mountain_car/mountain_car_task.hpp"

#include <array>
#include <memory>
#include <string_view>

#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/continuous_table.hpp"
#include "engine/tasks/continuous_task.hpp"
#include "sims/mountain_car/mountain_car.hpp"

namespace ggk::engine {

namespace {

namespace car = sims::mountain_car;

struct MountainCarTask {
  car::MountainCarConfig car;
  bool walk_from_reset = false;
  ContinuousProtocol protocol;
};

constexpr std::array<std::string_view, 10> kKeys = {
    "series", "steps_per_series", "test_episodes", "test_max_steps", "som", "scale",
    "force",  "gravity",          "max_speed",     "walk_start"};
constexpr std::array<std::string_view, 2> kWalkStarts = {"state_box", "reset"};
// Gymnasium's observation box: position in [-1.2, 0.6], velocity in [-0.07, 0.07].
constexpr std::array<ObservationDimension, 2> kDimensions = {
    {{"position", 1.8}, {"velocity", 0.14}}};

MountainCarTask parse_table(const TomlTableReader& job, const std::filesystem::path&) {
  const TomlTableReader table = job.subtable_or_empty("mountain_car", kKeys);
  MountainCarTask task;
  task.car.force = table.number("force", NumberRange::above(0.0), task.car.force);
  task.car.gravity = table.number("gravity", NumberRange::at_least(0.0), task.car.gravity);
  task.car.max_speed = table.number("max_speed", NumberRange::above(0.0), task.car.max_speed);
  task.walk_from_reset = table.choice("walk_start", kWalkStarts, "state_box") == "reset";
  ContinuousProtocol defaults;
  defaults.series = 200;
  defaults.steps_per_series = 100;
  defaults.test_episodes = 10;
  defaults.test_max_steps = 200;  // Gymnasium's TimeLimit for MountainCar-v0
  defaults.som_grid_from_samples = true;
  task.protocol = read_continuous_protocol(table, defaults, kDimensions);
  check_kernel_widths(job, continuous_distance_scale(task.protocol, 2));
  return task;
}

class MountainCarEpisode final : public ContinuousEpisode {
 public:
  explicit MountainCarEpisode(const MountainCarTask& task) : task_(task) {}
  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    const car::MountainCarConfig& c = task_.car;
    if (task_.walk_from_reset) return start_test(random, observation);
    state_.position = random.uniform(c.min_position, c.goal_position);
    state_.velocity = random.uniform(-c.max_speed, c.max_speed);
    observe(observation);
  }
  void start_test(kernels::RandomStream& random, std::span<double> observation) override {
    state_ = {random.uniform(-0.6, -0.4), 0.0};  // Gymnasium's reset
    observe(observation);
  }
  ContinuousStep step(std::int32_t action, kernels::RandomStream&,
                      std::span<double> observation) override {
    state_ = car::step(task_.car, state_, action);
    observe(observation);
    return {-1.0, car::at_goal(task_.car, state_), false, false};
  }
  void trace(std::vector<double>& out) const override {
    out.insert(out.end(), {state_.position, state_.velocity});
  }

 private:
  void observe(std::span<double> observation) const {
    observation[0] = state_.position;
    observation[1] = state_.velocity;
  }
  const MountainCarTask& task_;
  car::State state_;
};

// The share of test episodes that ended before the cap (a fraction).
constexpr char kEnded[] = "success_rate";

ContinuousEnvironment environment(const MountainCarTask& task) {
  ContinuousEnvironment env;
  env.observation_dimension = 2;
  env.num_actions = car::kNumActions;
  env.action_names = {"push_left", "no_push", "push_right"};
  env.new_episode = [&task] { return std::make_unique<MountainCarEpisode>(task); };
  env.trace_dimension = 2;
  env.ended_metric = kEnded;
  env.reward_low = -1.0;  // -1 a step
  env.reward_high = -1.0;
  return env;
}

ContinuousSizes sizes(const MountainCarTask&) {
  return {2.0, car::kNumActions, 2.0, 0.0, 0.0};
}

}  // namespace

TaskDefinition mountain_car_task_definition() {
  return continuous_task_definition<parse_table, environment, sizes>("mountain_car");
}

}  // namespace ggk::engine
