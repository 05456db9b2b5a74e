#pragma once
// The [arm] table of a job file (task = "arm"): the arm's geometry (links, base,
// joint limits, obstacles, object, start A) and the sampling protocol; keys,
// types and defaults in jobs/README.md.

#include "engine/job/toml_table_reader.hpp"
#include "sims/arm/arm_config.hpp"

namespace ggk::engine {

// Reads the [arm] table of `job` (the job file's root table); the table and its
// geometry keys are required. The arm is built here (sims::arm::Arm), so a
// geometry without a free pose or without a goal, or a start A that collides, is
// reported at the key that set it. Throws JobError.
sims::arm::ArmConfig parse_arm_table(const TomlTableReader& job);

}  // namespace ggk::engine
