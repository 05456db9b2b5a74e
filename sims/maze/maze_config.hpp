#pragma once
// Parameters of the maze task as a job file gives them (plain data; the engine's
// job-file parser fills it, the maze protocol reads it).

#include <cstdint>
#include <string>

namespace ggk::sims::maze {

struct MazeConfig {
  std::string map_text;                 // ASCII art, as Maze's constructor reads it
  double slip = 0.0;                    // probability of a move in another direction, [0, 1)
  std::int32_t series = 20;             // random-walk series per run
  std::int32_t steps_per_series = 500;  // random moves per series
  std::int32_t test_max_steps = 100;    // step limit when testing a greedy policy
};

}  // namespace ggk::sims::maze
