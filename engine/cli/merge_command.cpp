#include "engine/cli/merge_command.hpp"

#include <filesystem>
#include <iostream>
#include <ostream>

#include "engine/job/job_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/isolated_merge.hpp"
#include "engine/run/shards.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/results_merge.hpp"

namespace ggk::engine {

int merge_command(CommandLine& line, const std::vector<std::string>& invocation) {
  std::string& merge_output = line.merge_output;
  const std::string& merge_job = line.merge_job;
  MergeOptions& merge_options = line.merge_options;
  std::vector<std::filesystem::path> shards(line.merge_inputs.begin(), line.merge_inputs.end());
  if (!line.merge_output_option.empty()) {  // -o OUT: every positional is a shard
    if (!merge_output.empty()) shards.insert(shards.begin(), merge_output);
    merge_output = line.merge_output_option;
  }
  if (merge_job.empty() && (!line.merge_overrides.empty() || !line.merge_sweeps.empty())) {
    throw UsageError(
        "merge: --set and --sweep say how the shards of --shards-of JOB were run (ggk merge "
        "--shards-of JOB --sweep ... -o OUT); shard files given by name need neither (ggk "
        "merge OUT a.h5 b.h5 ...)");
  }
  if (!merge_job.empty()) {
    if (!shards.empty()) {
      throw UsageError("merge --shards-of " + merge_job +
                       " finds the shards itself: give no shard files (or give "
                       "them without --shards-of: ggk merge OUT a.h5 b.h5 ...)");
    }
    JobLoadOptions shard_load;
    shard_load.overrides = line.merge_overrides;
    shard_load.sweeps = line.merge_sweeps;
    shards = shards_of_job(merge_job, shard_load, merge_output, merge_options.allow_partial);
    merge_options.check_run_options = true;
    merge_options.expected_overrides = line.merge_overrides;
    merge_options.expected_sweeps = line.merge_sweeps;
  } else if (merge_output.empty() || shards.empty()) {
    throw UsageError(
        "merge: give the output and its shards (ggk merge OUT a.h5 b.h5 ...), or the job "
        "whose shards to merge (ggk merge [OUT] --shards-of JOB)");
  }
  if (auto problem = results_extension_problem(merge_output)) {
    throw UsageError("merge output: " + *problem);
  }
  merge_options.program = invocation.front();
  std::ostream discard(nullptr);  // -q: what would be printed, dropped
  return merge_results_isolated(merge_output, shards, merge_options,
                                line.quiet ? discard : std::cerr);
}

}  // namespace ggk::engine
