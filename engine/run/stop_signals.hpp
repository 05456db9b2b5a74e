#pragma once
// What `ggk run` does on Ctrl-C (SIGINT), SIGTERM (a batch system's time limit)
// or SIGHUP (a closed terminal), in a single process; the MPI runner has its own
// (mpi_runner.hpp). The handler, async-signal-safe:
//  - removes the results' .part file if no run has landed yet (the output stays
//    as it was) and the output's lock file (so a resume on another node of a
//    cluster is not refused by a lock nobody holds);
//  - prints on a fresh line how to finish the job (every run written is
//    complete; the one being written is discarded by --resume);
//  - then dies of the same signal (default action), so shells and batch systems
//    see how it ended.

#include <atomic>
#include <filesystem>
#include <string>

namespace ggk::engine {

class StopSignals {
 public:
  // Installs the handlers until destruction. One instance at a time.
  StopSignals(const std::filesystem::path& job_file, const std::filesystem::path& output,
              const std::filesystem::path& temporary, const std::filesystem::path& lock_file);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The results file has its name (its first run landed): from now on a stop
  // keeps it and says how to resume it.
  void results_published();
};

}  // namespace ggk::engine
