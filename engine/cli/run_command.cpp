#include "engine/cli/run_command.hpp"

#include <cstdio>
#include <stdexcept>

#include "engine/job/job_file.hpp"
#include "engine/job/study.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/cpu_affinity.hpp"
#include "engine/run/fit_warnings.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/shards.hpp"
#include "engine/tasks/task_list.hpp"
#if GGK_WITH_MPI
#include "engine/run/mpi_runner.hpp"
#endif

namespace ggk::engine {

namespace {

// A run with --set or --sweep computes something other than its job file: its
// results never take the file's output name (where the plain job's results
// live) unless an override names the output. Refused (exit 2) with how to name it.
void require_own_output(const std::vector<std::string>& overrides,
                        const std::vector<std::string>& sweeps, const std::string& output) {
  if (!output.empty() || (overrides.empty() && sweeps.empty())) return;
  for (const std::string& text : overrides) {
    std::string key = text.substr(0, text.find('='));
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    if (key == "output" || key == "output.file") return;
  }
  throw UsageError(
      std::string(overrides.empty() ? "--sweep" : "--set") +
      " makes another job than the job file, whose [output] file holds (or will hold) the plain "
      "job's results: name this one's results file with -o FILE.h5 (or --set output.file=...)");
}

// "A:B" -> runs A..B-1; the range is checked against the job when it runs.
RunRange parse_run_range(const std::string& text) {
  const std::size_t colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    std::size_t used_first = 0, used_last = 0;
    const int first = std::stoi(text.substr(0, colon), &used_first);
    const int last = std::stoi(text.substr(colon + 1), &used_last);
    if (used_first != colon || used_last != text.size() - colon - 1) {
      throw std::invalid_argument("trailing characters");
    }
    return {first, last};
  } catch (const std::exception&) {
    throw UsageError("--runs " + text + ": expected A:B, the runs A..B-1 (e.g. --runs 0:10)");
  }
}

}  // namespace

int run_command(CommandLine& line, const std::vector<std::string>& invocation, bool quiet_rank,
                [[maybe_unused]] MpiSession* mpi) {
  RunOptions& options = line.options;
  if (options.resume && options.overwrite) {
    throw UsageError("--resume and --overwrite exclude each other");
  }
  JobLoadOptions load;
  load.overrides = line.overrides;
  load.sweeps = line.sweeps;
  require_own_output(line.overrides, line.sweeps, line.output);
  options.output = line.output;
  options.invocation = invocation;
  if (!line.runs_text.empty()) options.runs = parse_run_range(line.runs_text);
  if (!line.shard_text.empty()) {
    if (!line.runs_text.empty()) {
      throw UsageError("--shard " + line.shard_text + " and --runs " + line.runs_text +
                       " exclude each other: a shard is a range of runs");
    }
    apply_shard_option(line.shard_text, line.job_path, load, options);
  }
  if (!quiet_rank) {  // a warning, printed under -q too
    const auto warning = oversubscription_warning(options.threads, affinity_cpus());
    if (warning) std::fprintf(stderr, "ggk: warning: %s\n", warning->c_str());
  }
#if GGK_WITH_MPI
  if (mpi != nullptr && mpi->size() > 1) {
    MpiRunOptions mpi_options;
    mpi_options.run = options;
    mpi_options.load = load;
    mpi_options.load.check_output = options.output.empty();
    mpi_options.rank_timeout_seconds = line.rank_timeout;
    return run_job_over_mpi(*mpi, line.job_path, mpi_options);
  }
#endif
  load.check_output = options.output.empty();  // -o replaces the job's output
  const Study study = load_study(line.job_path, task_tables(), load);
  const RunSummary summary = run_study(study, options);
  print_fit_warnings(summary);
  if (!options.quiet) print_run_summary(study.job(), summary);
  return 0;
}

}  // namespace ggk::engine
