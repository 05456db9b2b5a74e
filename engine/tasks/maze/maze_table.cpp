#include "engine/tasks/maze/maze_table.hpp"

#include <array>
#include <limits>
#include <string_view>

#include "sims/maze/maze.hpp"

namespace ggk::engine {
namespace {

constexpr std::array<std::string_view, 6> kMazeKeys = {
    "map", "map_file", "slip", "series", "steps_per_series", "test_max_steps"};
constexpr std::string_view kDefaultMapFile = "maps/four-rooms.txt";
constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();

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
  try {
    const sims::maze::Maze parsed(config.map_text);
  } catch (const sims::maze::MazeParseError& error) {
    std::string detail = error.what();
    if (map_key == "map_file") {
      detail = single_quoted(maze.string("map_file", std::string(kDefaultMapFile))) + ": " + detail;
    }
    maze.fail(map_key, detail);
  }

  config.slip = maze.number("slip", NumberRange::half_open(0.0, 1.0), config.slip);
  config.series = static_cast<std::int32_t>(maze.integer("series", {1, kInt32Max}, config.series));
  config.steps_per_series = static_cast<std::int32_t>(
      maze.integer("steps_per_series", {1, kInt32Max}, config.steps_per_series));
  config.test_max_steps = static_cast<std::int32_t>(
      maze.integer("test_max_steps", {1, kInt32Max}, config.test_max_steps));
  // Sample ids are 32-bit: a run's samples must fit.
  const std::int64_t samples =
      static_cast<std::int64_t>(config.series) * static_cast<std::int64_t>(config.steps_per_series);
  if (samples > kInt32Max) {
    maze.fail("steps_per_series", "series x steps_per_series = " + std::to_string(samples) +
                                      " samples per run, more than " + std::to_string(kInt32Max));
  }
  return config;
}

}  // namespace ggk::engine
