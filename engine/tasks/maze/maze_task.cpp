#include "engine/tasks/maze/maze_task.hpp"

#include "engine/tasks/maze/maze_table.hpp"

namespace ggk::engine {

DiscreteEnvironment maze_environment(const sims::maze::Maze& maze, double slip) {
  DiscreteEnvironment env;
  env.num_states = maze.num_states();
  env.num_actions = maze.num_actions();
  for (std::int32_t a = 0; a < env.num_actions; ++a) {
    env.action_names.emplace_back(sims::maze::action_name(a));
  }
  env.state_vectors = maze.state_vectors();
  env.goal_states = maze.goal_states();
  for (std::int32_t s = 0; s < maze.num_states(); ++s) {
    if (!maze.is_goal(s)) env.start_states.push_back(s);
  }
  env.step = [&maze, slip](std::int32_t state, std::int32_t action, kernels::RandomStream& random) {
    const sims::maze::StepResult r = maze.step(state, action, random, slip);
    return Transition{r.next_state, r.reward, r.terminal};
  };
  return env;
}

RunRecord run_maze(const sims::maze::MazeConfig& config, const JobSpec& job, std::int32_t run,
                   std::span<const SweepPoint> points) {
  const sims::maze::Maze maze(config.map_text);
  const DiscreteEnvironment env = maze_environment(maze, config.slip);
  const DiscreteProtocol protocol{config.series, config.steps_per_series, config.test_max_steps};
  return run_discrete_protocol(env, protocol, job, run, points);
}

RunMemoryEstimate estimate_maze_run(const sims::maze::MazeConfig& config, const JobSpec& job) {
  const sims::maze::Maze maze(config.map_text);  // linear in the map, as its parser
  DiscreteSizes sizes;
  sizes.states = maze.num_states();
  sizes.actions = maze.num_actions();
  sizes.successors = config.slip > 0.0 ? maze.num_actions() : 1.0;
  // The map's text, its grid of state ids, and per state its cell and vector.
  sizes.simulator_bytes = static_cast<double>(config.map_text.size()) +
                          4.0 * maze.rows() * maze.cols() + 32.0 * maze.num_states();
  sizes.states_are = "free cells of the map";
  const DiscreteProtocol protocol{config.series, config.steps_per_series, config.test_max_steps};
  return estimate_discrete_run(sizes, protocol, job);
}

TaskDefinition maze_task_definition() {
  return {{"maze",
           [](const TomlTableReader& job, const std::filesystem::path& job_dir,
              std::vector<JobInput>& inputs) -> std::any {
             return parse_maze_table(job, job_dir, inputs);
           }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_maze(task_config_as<sims::maze::MazeConfig>(job), job, run, points);
          },
          [](const JobSpec& job) {
            return estimate_maze_run(task_config_as<sims::maze::MazeConfig>(job), job);
          },
          [](const JobSpec& job) {
            const auto& config = task_config_as<sims::maze::MazeConfig>(job);
            const DiscreteProtocol protocol{config.series, config.steps_per_series,
                                            config.test_max_steps};
            return discrete_metric_specs({}, {}, protocol);  // the goal test, no named start
          },
          discrete_dataset_specs()};
}

}  // namespace ggk::engine
