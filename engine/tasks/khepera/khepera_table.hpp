#pragma once
// The [khepera] table of a job file (task = "khepera"): the arena (inline as
// [khepera.arena] or read from arena_file), the robot, sensor, motion and reward
// models, the sampling and evaluation protocol, and the self-organising map;
// keys, types and defaults in jobs/README.md.

#include <filesystem>
#include <vector>

#include "engine/job/job_input.hpp"
#include "engine/job/toml_table_reader.hpp"
#include "engine/tasks/khepera/khepera_task_config.hpp"

namespace ggk::engine {

// Reads the [khepera] table of `job` (the job file's root table); the table is
// required, and so is its arena: exactly one of arena_file (resolved against
// job_dir, the job file's folder) and [khepera.arena]. Errors in an arena file
// are reported with that file's path, line and key. The simulator is built here
// (sims::khepera::Khepera), so what only the whole configuration can tell (a
// sensor outside the body, a start pose overlapping an obstacle) is reported at
// the key that set it. An arena file read is appended to `inputs`. Throws JobError.
KheperaTaskConfig parse_khepera_table(const TomlTableReader& job,
                                      const std::filesystem::path& job_dir,
                                      std::vector<JobInput>& inputs);

}  // namespace ggk::engine
