#include "engine/tasks/arm/arm_task.hpp"

#include "engine/tasks/arm/arm_table.hpp"

namespace ggk::engine {

DiscreteEnvironment arm_environment(const sims::arm::Arm& arm) {
  DiscreteEnvironment env;
  env.num_states = arm.num_states();
  env.num_actions = arm.num_actions();
  env.state_vectors = arm.state_vectors();
  env.goal_states = arm.goal_states();
  for (std::int32_t s = 0; s < arm.num_states(); ++s) {
    if (!arm.is_goal(s)) env.start_states.push_back(s);
  }
  env.named_starts = {{"A", arm.start_state_A()}};
  env.step = [&arm](std::int32_t state, std::int32_t action, kernels::RandomStream&) {
    const sims::arm::StepResult r = arm.step(state, action);
    return Transition{r.next_state, r.reward, r.terminal};
  };
  return env;
}

RunRecord run_arm(const sims::arm::ArmConfig& config, const JobSpec& job, std::int32_t run,
                  std::span<const SweepPoint> points) {
  const sims::arm::Arm arm(config);
  const DiscreteEnvironment env = arm_environment(arm);
  // The walk goes on through goals so that all 16 goals join the graph and become
  // the first centres, as in the paper (a restart at each goal leaves ~9 of them
  // unvisited: the inner goal cells are only reachable through other goals).
  const DiscreteProtocol protocol{config.series, config.steps_per_series, config.test_max_steps,
                                  /*walk_through_goals=*/true};
  RunRecord record = run_discrete_protocol(env, protocol, job, run, points);

  const std::int64_t rows = arm.shoulder_steps(), cols = arm.elbow_steps();
  NamedArray state_of{"grid/state_of", {rows, cols}, {}};
  NamedArray goal{"grid/goal", {rows, cols}, {}};
  for (std::int32_t i = 0; i < rows; ++i) {
    for (std::int32_t j = 0; j < cols; ++j) {
      const std::int32_t s = arm.state_of(i, j);
      state_of.values.push_back(s);
      goal.values.push_back(s != sims::arm::kNoState && arm.is_goal(s) ? 1.0 : 0.0);
    }
  }
  record.arrays.push_back(std::move(state_of));
  record.arrays.push_back(std::move(goal));
  return record;
}

RunMemoryEstimate estimate_arm_run(const sims::arm::ArmConfig& config, const JobSpec& job) {
  const sims::arm::Arm arm(config);  // at most 72 x 72 poses, as the parser built it
  const double cells = static_cast<double>(arm.shoulder_steps()) * arm.elbow_steps();
  DiscreteSizes sizes;
  sizes.states = arm.num_states();
  sizes.actions = arm.num_actions();
  sizes.named_starts = 1.0;  // A
  // The grid of state ids and per state its cell and goal flag.
  sizes.simulator_bytes = 4.0 * cells + 9.0 * arm.num_states();
  sizes.states_are = "free poses of the arm";
  const DiscreteProtocol protocol{config.series, config.steps_per_series, config.test_max_steps,
                                  /*walk_through_goals=*/true};
  RunMemoryEstimate estimate = estimate_discrete_run(sizes, protocol, job);
  // grid/state_of and grid/goal in the record (doubles, grown by doubling).
  const double grid = 2.0 * 2.0 * 8.0 * cells;
  estimate.add("the joint grid (" + count_text(cells) + " poses)", grid);
  estimate.record_bytes += grid;
  return estimate;
}

TaskDefinition arm_task_definition() {
  return {{"arm",
           [](const TomlTableReader& job, const std::filesystem::path&,
              std::vector<JobInput>&) -> std::any { return parse_arm_table(job); }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_arm(task_config_as<sims::arm::ArmConfig>(job), job, run, points);
          },
          [](const JobSpec& job) {
            return estimate_arm_run(task_config_as<sims::arm::ArmConfig>(job), job);
          }};
}

}  // namespace ggk::engine
