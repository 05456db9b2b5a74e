#pragma once
// The peak memory of one Khepera run (run_memory.hpp), from the job's sizes alone.

#include "engine/job/job_spec.hpp"
#include "engine/tasks/khepera/khepera_task_config.hpp"
#include "engine/tasks/run_memory.hpp"

namespace ggk::engine {

// The walks' readings and samples in their copies, the SOM (training and the
// map), the unit graph and distances, per fit the kernel and feature tables over
// every reading and the LSPI system, and the fits' results (episode trajectories).
RunMemoryEstimate estimate_khepera_run(const KheperaTaskConfig& config, const JobSpec& job);

}  // namespace ggk::engine
