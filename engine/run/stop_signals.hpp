#pragma once
// What `ggk run` does on SIGINT (Ctrl-C), SIGTERM (a batch system's stop; mpirun
// sends it to every rank on a Ctrl-C) or SIGHUP (a closed terminal), in a single
// process and on MPI ranks alike:
//  - removes the results' .part file if no run has landed yet (the output stays
//    as it was) and the output's lock file (so a resume on another node of a
//    cluster is not refused by a lock nobody holds);
//  - prints on a fresh line what the output holds and the command that goes on
//    (resume_command.hpp: go_on_text), and any details the runner adds;
//  - ends with status 128 + signal.
// After job_complete() (the summary is written) it says so and names the results.
// open_results installs it as soon as it holds the output's lock (a resume's
// reading back of its output is a phase of `run` like any other) and the runner's
// JobWriter takes it over (set_report), so no moment of `run` lacks it.
//
// kStopInHandler (a single process): the handler does all of it,
// async-signal-safe (unlink and write of buffers filled beforehand), then dies
// of the same signal (default action), so shells and batch systems see how it
// ended. kRecord (MPI ranks): the handler only records the signal; the runner
// polls received() and calls report() once it knows what to add (rank 0: which
// ranks answered, the runs in flight), then exits; or goes on when nothing is
// lost.

#include <csignal>
#include <filesystem>
#include <string>

namespace ggk::engine {

class StopSignals {
 public:
  enum class Mode { kStopInHandler, kRecord };

  struct Report {
    std::filesystem::path output;
    std::filesystem::path temporary;  // "<output>.part" until published; empty when resuming
    std::filesystem::path lock_file;
    std::string published;    // what to do once runs are in the output
    std::string unpublished;  // what to do while none is
  };

  // Installs the handlers until destruction. One instance at a time. Without a
  // report (an MPI worker), stop() removes and prints nothing.
  explicit StopSignals(Mode mode);
  StopSignals(Mode mode, const Report& report);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // Aims the handler at another report (a runner taking over the instance
  // open_results installed while it read the output back): a signal sees the old
  // report or the new one, whole. Clears results_published().
  void set_report(const Report& report);
  // Switches between handling a stop in the handler and recording it.
  void set_mode(Mode mode);

  // The results file has its name (its first run landed): from now on a stop
  // keeps it and says how to resume it.
  void results_published();
  // Every run and the summary are written: a stop now only names the results.
  void job_complete();

  // kRecord: the first signal received, 0 when none.
  int received() const;

  // What the handler does in kStopInHandler, for a kRecord runner that is about
  // to exit: removes the files, prints "ggk: <headline>; <what the output
  // holds>" and `details` (whole lines, may be empty).
  void report(const std::string& headline, const std::string& details) const;

  // "interrupted (SIGINT)", "stopped by SIGTERM", "stopped by SIGHUP".
  static const char* headline_of(int signal);
  // "SIGINT", "SIGTERM", "SIGHUP".
  static const char* name_of(int signal);
};

}  // namespace ggk::engine
