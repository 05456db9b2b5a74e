#include "engine/tasks/maze/maze_task.hpp"

#include "engine/tasks/maze/maze_table.hpp"

namespace ggk::engine {

DiscreteEnvironment maze_environment(const sims::maze::Maze& maze, double slip) {
  DiscreteEnvironment env;
  env.num_states = maze.num_states();
  env.num_actions = maze.num_actions();
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

TaskDefinition maze_task_definition() {
  return {{"maze",
           [](const TomlTableReader& job, const std::filesystem::path& job_dir,
              std::vector<JobInput>& inputs) -> std::any {
             return parse_maze_table(job, job_dir, inputs);
           }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_maze(task_config_as<sims::maze::MazeConfig>(job), job, run, points);
          }};
}

}  // namespace ggk::engine
