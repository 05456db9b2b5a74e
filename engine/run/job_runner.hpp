#pragma once
// Runs a validated job: checks that it fits in memory (memory_check.hpp), plans
// its runs, computes them as oneTBB tasks, and hands each finished run to the
// store writer, which writes it whole and marks it complete. --resume skips
// complete runs; the summary is rebuilt at the end.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "engine/job/job_spec.hpp"
#include "engine/job/study.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/fit_warnings.hpp"
#include "engine/store/adaptive_state.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

class JobWriter;

// Runs first..last-1 of a job (`--runs A:B`): a shard for a job array; the runs
// keep the seeds and results they have in the whole job (ggk merge joins shards).
struct RunRange {
  std::int32_t first = 0;
  std::int32_t last = 0;  // exclusive
};

// An adaptive study's shard (`--shard I/N`, adaptive_shards.hpp): shard I of N
// over the run configurations, which the rule's cells never link across shards.
struct ConfigurationShard {
  std::int32_t index = 0;
  std::int32_t count = 1;
  AdaptiveScope scope;  // its configurations and the whole study's cells
};

struct RunOptions {
  std::filesystem::path output;  // empty: the job's [output] file
  std::int32_t threads = 0;      // 0: all cores
  bool resume = false;           // continue an existing results file of this job
  bool overwrite = false;        // replace an existing results file
  bool quiet = false;            // no progress output
  std::optional<RunRange> runs;  // only these runs (a shard); checked against job.runs
  // only these run configurations (an adaptive study's shard)
  std::optional<ConfigurationShard> configuration_shard;
  bool ignore_memory_check = false;  // run a job whose estimate exceeds the memory available
  // The command line as typed (argv, the program as invoked first): what the
  // resume commands ggk prints repeat (resume_command.hpp). Empty: built from
  // the job and these options.
  std::vector<std::string> invocation;
};

struct RunSummary {
  std::filesystem::path output;
  std::int32_t runs_computed = 0;
  std::int32_t runs_skipped = 0;  // already complete (--resume)
  // Of runs_computed, those whose fits were spread over several MPI ranks
  // (run_pieces.hpp).
  std::int32_t runs_in_pieces = 0;
  std::int64_t fits = 0;
  std::int64_t failed_fits = 0;  // invalid or solver_failed
  double seconds = 0.0;
  // FitWarnings::lines() of the fits computed (fit_warnings.hpp); empty under
  // MPI, where the workers' runs reach rank 0 as file images (the fits'
  // attribute `warning` holds them there too).
  std::vector<std::string> warnings;
  // An adaptive study's closing lines (adaptive_runner.hpp); empty for others.
  std::vector<std::string> adaptive;
};

// A job that stopped because a run could not be computed or written (a full
// disk, an I/O error): not the user's mistake, not a bug; the message says what
// the results file holds and how to go on. The CLI exits with status 1.
class RunFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

RunSummary run_job(const JobSpec& job, const RunOptions& options);
// A study: its units over oneTBB's threads, every configuration in one file.
RunSummary run_study(const Study& study, const RunOptions& options);

// The CLI's closing lines on stderr: runs computed and skipped, fits, failures,
// time, and where the results are.
void print_run_summary(const JobSpec& job, const RunSummary& summary);
// The summary's warnings, one "ggk: warning: " line each (printed under -q too).
void print_fit_warnings(const RunSummary& summary);

// Runs one run of the job's task for every sweep point (no I/O); the record
// carries the task's dataset declarations (TaskDefinition::datasets).
RunRecord compute_run(const JobSpec& job, std::int32_t run);
// One unit of a study: the run of its configuration, every fit of every variant.
RunRecord compute_unit(const Study& study, const WorkUnit& unit);

// The largest configuration's memory check (memory_check.hpp) for the study's
// units to compute.
void check_study_memory(const Study& study, const RunOptions& options);

// The fits of `record` that failed (status invalid or solver_failed).
std::int64_t failed_fits_of(const RunRecord& record);

// What a job's computed runs add up to, for its summary.
struct RunTally {
  std::atomic<std::int64_t> fits{0};
  std::atomic<std::int64_t> failed_fits{0};
  FitWarnings warnings;
};

// Computes `units` as oneTBB tasks (one each, simple partitioner) and commits
// each run through `writer` as it ends, counting into `tally`.
void compute_units(const Study& study, std::span<const WorkUnit> units, JobWriter& writer,
                   RunTally& tally);

// The RunFailure of a job that stopped on `error` (a run that could not be
// computed or written): waits for the writer, then says what the file holds and
// the command that goes on.
RunFailure stopped_job(JobWriter& writer, const std::runtime_error& error);

// Prints open_results' notes (a damaged run computed again, an empty file
// started afresh) to stderr, one "ggk: " line each.
void print_notes(const std::vector<std::string>& notes);

// Sets oneTBB's thread limit for the caller's lifetime (threads = 0: all cores) and
// makes the BLAS single-threaded per call; throws UsageError when the BLAS is not
// safe to call concurrently and more than one thread may run.
class ComputeThreads {
 public:
  explicit ComputeThreads(std::int32_t threads);

 private:
  std::unique_ptr<tbb::global_control> limit_;
};

}  // namespace ggk::engine
