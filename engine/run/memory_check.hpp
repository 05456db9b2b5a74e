#pragma once
// The memory check of `ggk run`: before the results file is created or an old
// one touched, the job's peak memory is estimated from its sizes (the tasks'
// estimate_run_bytes, tasks/run_memory.hpp) and compared with the memory this
// process may use; a job that cannot fit is refused with a UsageError (exit
// status 2) naming the estimate, what dominates it and the memory available,
// unless --ignore-memory-check asks to run it anyway.
//
// The job's peak, for `threads` worker threads and `runs` runs to compute:
//   C = min(threads, runs) runs at once, each holding its run_bytes;
//   min(threads, C x sweep points) fits at once, each holding its fit_bytes;
//   a finished record per computing run waiting for the writer thread (its queue
//   admits 64, but a run computes for far longer than its record takes to write);
//   the run lists (a few int32 per run) and the summary table, which is read
//   whole at the end (runs x sweep points rows of about 1 KB);
//   the program itself (libraries, thread stacks, HDF5's caches: 48 MB).
// Under an address-space limit the threads' reservations count too
// (reserved_address_space, address_space.hpp).

#include <cstdint>
#include <limits>
#include <string>

#include "engine/job/job_spec.hpp"
#include "engine/run/job_runner.hpp"

namespace ggk::engine {

struct AvailableMemory {
  double bytes = std::numeric_limits<double>::infinity();
  std::string source;  // what limits it, e.g. "MemAvailable in /proc/meminfo"; empty: unknown
};

// The memory this process may still use: the least of /proc/meminfo's
// MemAvailable; the cgroup's limit (v2 memory.max, v1 memory.limit_in_bytes, the
// process's group and its ancestors) less its usage, page cache not counted; and
// the address-space limit (ulimit -v) less the address space in use and
// `reserved_address_space` (what threads reserve but do not use: address_space.hpp).
// Infinite, with an empty source, when none can be read (not Linux).
AvailableMemory available_memory(double reserved_address_space = 0.0);

struct JobMemoryEstimate {
  double bytes = 0.0;    // the job's peak
  double per_run = 0.0;  // one run's peak with one fit at a time
  // The parts that dominate, largest first, "; "-separated (at most three), e.g.
  // "a 40000 x 40000 SOM (1600000000 units): 550 GB per run x 2 runs at once
  // (2 threads)".
  std::string largest;
};

// The peak of computing `runs` runs of `job` with `threads` threads (see above);
// `variants`: a study's fit variants per sweep point (study.hpp), each a fit more.
JobMemoryEstimate estimate_job_memory(const JobSpec& job, std::int32_t threads, std::int64_t runs,
                                      std::int64_t variants = 1);

// Throws UsageError when the estimate exceeds available_memory(); with `ignore`
// it prints a note to stderr instead and returns.
void check_memory(const JobSpec& job, std::int32_t threads, std::int64_t runs, bool ignore,
                  std::int64_t variants = 1);

// The check as `ggk run` makes it: the threads oneTBB allows now (call it after
// ComputeThreads), the runs of options.runs (or all; with --resume an upper
// bound), options.ignore_memory_check.
void check_memory(const JobSpec& job, const RunOptions& options, std::int64_t variants = 1);

}  // namespace ggk::engine
