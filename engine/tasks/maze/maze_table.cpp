#include "engine/tasks/maze/maze_table.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/kernel_width.hpp"
#include "engine/job/task_table.hpp"
#include "engine/job/walk_sizes.hpp"
#include "engine/single_quoted.hpp"
#include "sims/maze/maze.hpp"

namespace ggk::engine {
namespace {

constexpr std::array<std::string_view, 6> kMazeKeys = {
    "map", "map_file", "slip", "series", "steps_per_series", "test_max_steps"};
constexpr std::string_view kDefaultMapFile = "maps/four-rooms.txt";

// Whether some free cell reaches a goal. Moves go between neighbouring non-wall
// cells both ways (a blocked move stays put), so the cells that reach a goal are
// those a search from the goals reaches. Linear in the states.
bool goal_reachable(const sims::maze::Maze& maze) {
  std::vector<std::uint8_t> reached(static_cast<std::size_t>(maze.num_states()), 0);
  std::vector<std::int32_t> frontier(maze.goal_states().begin(), maze.goal_states().end());
  for (const std::int32_t goal : frontier) reached[static_cast<std::size_t>(goal)] = 1;
  while (!frontier.empty()) {
    const std::int32_t state = frontier.back();
    frontier.pop_back();
    if (!maze.is_goal(state)) return true;
    for (std::int32_t action = 0; action < maze.num_actions(); ++action) {
      const std::int32_t next = maze.move(state, action);
      if (reached[static_cast<std::size_t>(next)]) continue;
      reached[static_cast<std::size_t>(next)] = 1;
      frontier.push_back(next);
    }
  }
  return false;
}

// State vectors are (row, col): distinct cells are at least 1 apart. A kernel's
// distance is at most a shortest path on the sample graph (fewer than
// num_states edges, each at most the map's diagonal) plus the Euclidean distance
// to the nearest graph node (at most the diagonal).
DistanceScale maze_distance_scale(const sims::maze::Maze& maze) {
  const double diagonal = std::hypot(maze.rows() - 1, maze.cols() - 1);
  return {1.0, static_cast<double>(maze.num_states()) * diagonal, "between neighbouring cells",
          "the number of states times the map's diagonal"};
}

}  // namespace

sims::maze::MazeConfig parse_maze_table(const TomlTableReader& job,
                                        const std::filesystem::path& job_dir,
                                        std::vector<JobInput>& inputs) {
  const TomlTableReader maze = job.subtable_or_empty("maze", kMazeKeys);
  sims::maze::MazeConfig config;

  // Exactly one of map / map_file; neither means the default map file.
  std::string_view map_key = "map_file";
  if (maze.has("map") && maze.has("map_file")) {
    maze.fail("map", "give either map (inline text) or map_file, not both");
  }
  if (maze.has("map")) {
    map_key = "map";
    config.map_text = maze.string("map");
  } else {
    const std::string map_file = maze.string("map_file", std::string(kDefaultMapFile));
    if (map_file.empty()) maze.fail("map_file", "expected a file name, got \"\"");
    inputs.push_back(read_job_input(maze, "map_file", job_dir, map_file, "map file"));
    config.map_text = inputs.back().text;
  }
  // Problems of the map name the map file, if there is one.
  const std::string map_shown =
      map_key == "map_file"
          ? single_quoted(shortened(maze.string("map_file", std::string(kDefaultMapFile)))) + ": "
          : std::string();
  std::optional<sims::maze::Maze> parsed;
  try {
    parsed.emplace(config.map_text);
  } catch (const sims::maze::MazeParseError& error) {
    maze.fail(map_key, map_shown + error.what());
  }
  if (!goal_reachable(*parsed)) {
    maze.fail(map_key, map_shown +
                           "no free cell '.' can reach a goal 'G' (walls enclose every goal), so "
                           "every fit would score success 0");
  }
  check_kernel_widths(job, maze_distance_scale(*parsed));

  config.slip = maze.number("slip", NumberRange::half_open(0.0, 1.0), config.slip);
  const WalkSizes walks = read_walk_sizes(maze, {config.series, config.steps_per_series});
  config.series = walks.series;
  config.steps_per_series = walks.steps_per_series;
  config.test_max_steps = static_cast<std::int32_t>(
      maze.integer("test_max_steps", kTestMaxStepsRange, config.test_max_steps));
  return config;
}

}  // namespace ggk::engine
