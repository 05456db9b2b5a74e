#pragma once
// The [maze] table of a job file (task = "maze"); keys, types and defaults in
// jobs/README.md.

#include <filesystem>
#include <vector>

#include "engine/job/job_input.hpp"
#include "engine/job/toml_table_reader.hpp"
#include "sims/maze/maze_config.hpp"

namespace ggk::engine {

// Reads the [maze] table of `job` (the job file's root table; an absent [maze]
// means all defaults). map_file is resolved against job_dir, the job file's
// folder. The map is parsed here, so a bad map is reported with the job file's
// key and the maze's row and column; a map file read is appended to `inputs`.
// Throws JobError.
sims::maze::MazeConfig parse_maze_table(const TomlTableReader& job,
                                        const std::filesystem::path& job_dir,
                                        std::vector<JobInput>& inputs);

}  // namespace ggk::engine
