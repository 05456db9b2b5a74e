#pragma once
// The maze task: a grid maze (sims/maze) run through the discrete protocol.

#include <cstdint>
#include <span>

#include "engine/job/job_spec.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/run_record.hpp"
#include "engine/tasks/task_definition.hpp"
#include "sims/maze/maze.hpp"
#include "sims/maze/maze_config.hpp"

namespace ggk::engine {

// The environment view of a maze; `maze` must outlive it. Series and tests start
// from every non-goal free cell.
DiscreteEnvironment maze_environment(const sims::maze::Maze& maze, double slip);

RunRecord run_maze(const sims::maze::MazeConfig& config, const JobSpec& job, std::int32_t run,
                   std::span<const SweepPoint> points);

// The peak memory of one run (estimate_discrete_run with the map's free cells).
RunMemoryEstimate estimate_maze_run(const sims::maze::MazeConfig& config, const JobSpec& job);

// The maze task for the task list: table [maze], runs through run_maze().
TaskDefinition maze_task_definition();

}  // namespace ggk::engine
