#pragma once
// Shards of a job without index arithmetic: `ggk run JOB --shard I/N` computes the
// I-th of N contiguous, balanced pieces of the job's runs (I from 0), `--shard
// slurm` takes I and N from a Slurm job array's environment, and the shard writes
// `<output stem>.shard-I-of-N<ext>` beside the job's output (results/x.h5 ->
// results/x.shard-1-of-4.h5; never the `<out>.part` temporaries ggk writes).
// `ggk merge --shards-of JOB` finds the shards of the job's output by that name
// and refuses when one is missing, naming it.
//
// Pure functions of their arguments (find_shards lists a folder); errors are
// UsageErrors naming the flag and the value.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {

struct Shard {
  std::int32_t index = 0;  // 0 .. count-1
  std::int32_t count = 1;
};

// Looks an environment variable up: nullptr when unset (std::getenv's contract).
using EnvironmentLookup = std::function<const char*(const char*)>;

// "I/N" (0 <= I < N), or "slurm": I = SLURM_ARRAY_TASK_ID and N the array's size,
// from SLURM_ARRAY_TASK_COUNT or SLURM_ARRAY_TASK_MIN / _MAX (and _STEP). Refuses an
// array that is not 0..N-1 in steps of 1 (`--array=1-4`, `--array=0-6:2`), and
// "slurm" outside an array task.
Shard parse_shard(std::string_view text, const EnvironmentLookup& environment);

// The runs of `shard` among `runs` runs: run r belongs to shard floor(r N / runs)'s
// range, i.e. shard I holds runs floor(I runs / N) .. floor((I+1) runs / N) - 1, so the
// shards are contiguous, cover every run once and differ in size by at most one.
// Refuses N > runs (a shard would be empty).
RunRange shard_runs(const Shard& shard, std::int32_t runs);
// The same range of `items` things (runs, or an adaptive study's groups of
// configurations: adaptive_shards.hpp) without the check.
RunRange shard_range(const Shard& shard, std::int32_t items);

// results/x.h5 -> results/x.shard-I-of-N.h5 (the same folder and extension).
std::filesystem::path shard_output(const std::filesystem::path& output, const Shard& shard);

// `ggk run JOB --shard`: options.runs = the shard's runs of `job` (after --set),
// options.output = the shard's file, named after -o (options.output) when given,
// else after the job's output.
void select_shard(const Shard& shard, const JobSpec& job, RunOptions& options);

// `ggk run JOB --shard TEXT [--set ...] [-o OUT]`: reads the job (with the
// overrides; its output unchecked) for its runs and output, then select_shard
// (an adaptive study's: select_adaptive_shard, by run configurations);
// "slurm" reads the process's environment.
void apply_shard_option(std::string_view text, const std::filesystem::path& job_path,
                        JobLoadOptions load, RunOptions& options);

// `ggk merge [OUT] --shards-of JOB [--set ...] [--sweep ...]`: reads the job with
// `load`'s overrides and sweeps (a UsageError for a bad one, as run gives), sets an
// empty `output` to the job's output (refused when there are overrides or sweeps:
// their shards are named after the run's -o) and returns find_shards(output,
// allow_missing).
std::vector<std::filesystem::path> shards_of_job(const std::filesystem::path& job_path,
                                                 JobLoadOptions load, std::string& output,
                                                 bool allow_missing);

// The shard files of `output` (x.shard-I-of-N<ext> beside it), in shard order.
// Refuses when there are none, when they come from splits into different N, and
// when one of 0..N-1 is missing (naming the files), unless allow_missing (then the
// files that exist; merge --allow-partial reports the runs they lack).
std::vector<std::filesystem::path> find_shards(const std::filesystem::path& output,
                                               bool allow_missing);

}  // namespace ggk::engine
