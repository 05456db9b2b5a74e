#pragma once
// Runs a validated job: plans its runs, computes them as oneTBB tasks, and hands
// each finished run to the store writer, which writes it whole and marks it
// complete. --resume skips complete runs; the summary is rebuilt at the end.

#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/job/job_spec.hpp"
#include "engine/job/run_record.hpp"
#include "engine/job/usage_error.hpp"

namespace ggk::engine {

struct RunOptions {
  std::filesystem::path output;  // empty: the job's [output] file
  std::int32_t threads = 0;      // 0: all cores
  bool resume = false;           // continue an existing results file of this job
  bool overwrite = false;        // replace an existing results file
  bool quiet = false;            // no progress output
};

struct RunSummary {
  std::filesystem::path output;
  std::int32_t runs_computed = 0;
  std::int32_t runs_skipped = 0;  // already complete (--resume)
  std::int64_t fits = 0;
  std::int64_t failed_fits = 0;  // invalid or solver_failed
  double seconds = 0.0;
};

RunSummary run_job(const JobSpec& job, const RunOptions& options);

// Runs one run of the job's task for every sweep point (no I/O).
RunRecord compute_run(const JobSpec& job, std::int32_t run);

}  // namespace ggk::engine
