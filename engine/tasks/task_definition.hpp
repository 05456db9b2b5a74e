#pragma once
// What a task gives the engine: its table in job files (name and parser) and the
// computation of one run. A task lives in its own folder under engine/tasks/ and
// is registered with one line in task_list.cpp; the job reader, the runner and
// the store know tasks only through this type.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/task_table.hpp"
#include "engine/tasks/dataset_spec.hpp"
#include "engine/tasks/metric_spec.hpp"
#include "engine/tasks/run_memory.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

// Computes one run of `job` (whose task_config the task's own parser produced)
// for every sweep point, in sweep order. No I/O; may run as a oneTBB task beside
// other runs, so it must depend only on its arguments (random numbers from
// seeds.hpp's streams). Throws only on programmer errors: a fit that cannot
// start or fails is recorded with its status.
using RunComputation = RunRecord (*)(const JobSpec& job, std::int32_t run,
                                     std::span<const SweepPoint> points);

// The peak memory one run of `job` needs (run_memory.hpp), from the job's sizes
// alone: cheap, allocates nothing that scales with the job, never throws for a
// job its parser accepted. The runner refuses a job that cannot fit before it
// creates the output file (engine/run/memory_check.hpp).
using RunMemoryEstimator = RunMemoryEstimate (*)(const JobSpec& job);

// The metrics the task's fits report for `job` (metric_spec.hpp: kind, unit,
// meaning, range), in summary-column order: what compute_run records in
// RunRecord::metric_specs, known before any run (an adaptive rule's ranges are
// checked against it). Cheap: builds at most the task's environment.
using MetricSpecsOf = std::vector<MetricSpec> (*)(const JobSpec& job);

struct TaskDefinition {
  TaskTable table;  // table.name is the task's name
  RunComputation compute_run = nullptr;
  RunMemoryEstimator estimate_run_bytes = nullptr;
  MetricSpecsOf metric_specs = nullptr;
  // What its runs add to a results file beyond what every run has
  // (dataset_spec.hpp): its own declarations first, then its protocols'. The
  // runner hands them to the store with each run (RunRecord::dataset_specs).
  std::vector<DatasetSpecs> datasets;
};

}  // namespace ggk::engine
