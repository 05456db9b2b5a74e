#pragma once
// `ggk merge OUT part1.h5 part2.h5 ...`: joins shards of one job (each from
// `ggk run JOB --runs A:B`) into the file the whole job would have written.
//
// The shards must hold the same job (job text and input files, compared); a run
// complete in two shards is refused (overlap), and runs complete in none are
// reported as gaps, refused unless allow_partial, in which case the printed
// `ggk run JOB [--set K=V]... --resume -o OUT` (the shards' job file and
// overrides) computes them later. Only complete runs are taken; their
// groups are copied whole (HDF5 object copy), the summary is rebuilt in run
// order. OUT is written under a temporary name beside it and renamed into place
// when complete, so a failed merge leaves no OUT and an existing OUT is refused.
//
// An adaptive study's shards (`--shard I/N` by run configurations:
// run/adaptive_shards.hpp) hold different numbers of runs per configuration:
// every complete run is merged, a run of a configuration not the shard's own is
// refused, and the rule is replayed on the merged file: one it is not done with
// is refused naming the configurations that lack runs (allow_partial: merged,
// with the `ggk run JOB --resume -o OUT` that finishes it).

#include <sys/types.h>

#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace ggk::engine {

struct MergeOptions {
  bool allow_partial = false;
  // The ggk program as invoked: the command printed to compute missing runs
  // (`PROGRAM run JOB [--set K=V]... --resume -o OUT`) starts with it.
  std::string program = "ggk";
  // `ggk merge --shards-of JOB --set ... --sweep ...`: the options the shards must
  // have been run with (their root attributes job_overrides / job_sweeps, one a
  // line); a shard of other options is refused naming both. Checked only when
  // check_run_options (shard files merged by name are not asked).
  bool check_run_options = false;
  std::vector<std::string> expected_overrides = {}, expected_sweeps = {};
};

// Throws UsageError for what the user can fix (unreadable or foreign shards,
// overlaps, gaps, an existing OUT). Reports what it merged to `log`.
// The temporary file a merge by process `pid` writes OUT under:
// "OUT.merging-<pid>", renamed to OUT when whole.
std::filesystem::path merging_path(const std::filesystem::path& output, pid_t pid);

void merge_results(const std::filesystem::path& output,
                   std::span<const std::filesystem::path> shards, const MergeOptions& options,
                   std::ostream& log);

}  // namespace ggk::engine
