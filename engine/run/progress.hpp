#pragma once
// Progress of a sweep on stderr: a redrawn bar when stderr is a terminal, plain
// lines every few seconds otherwise. Runs done / total, and fits done / total as
// each fit ends (tasks/fit_count.hpp; an MPI rank 0 adds its workers', which
// their heartbeats report), so a long run shows its progress; the ETA
// from fits once one has ended (a fit is the finer unit of work), else from runs.
//
// Thread-safety: run_done() may be called from any thread.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace ggk::engine {

// The time left after `done` of `total` units in `elapsed_seconds` ("42s"), or
// "--" while none has ended.
std::string eta_text(std::int64_t done, std::int64_t total, double elapsed_seconds);

// What the display says (without the bar): "runs 0/1, fits 10/40, 2.0 fits/s,
// elapsed 5s, eta 15s". fits_done < 0: fits are not counted: runs only, fits/s
// from whole runs.
// eta_seconds: an estimate made otherwise (weighted_seconds_left), shown instead.
std::string progress_text(std::int32_t runs_done, std::int32_t total_runs, std::int64_t fits_done,
                          std::int64_t total_fits, double elapsed_seconds,
                          std::optional<double> eta_seconds = std::nullopt);

// The units of one run configuration: how many the job computes, how many have
// ended and the seconds they took together.
struct ConfigurationProgress {
  std::int64_t expected = 0;
  std::int64_t done = 0;
  double seconds = 0.0;
};

// The time left when each configuration's units cost what its ended ones did (a
// configuration none of whose units has ended: the mean of all ended units), at
// the pace of the work so far (the ended units' seconds per elapsed second: the
// threads that computed them). nullopt before a unit has ended. Configurations
// of different cost (a larger SOM, more samples) then weigh as they should: two
// cheap configurations done first no longer promise that the dear ones go as fast.
std::optional<double> weighted_seconds_left(std::span<const ConfigurationProgress> configurations,
                                            double elapsed_seconds);

class Progress {
 public:
  // quiet: print nothing. fits_per_run: sweep points per run. count_fits: count
  // the fits ended (this process's, and other ranks' as add_remote_fits reports).
  Progress(std::int32_t total_runs, std::int32_t fits_per_run, bool quiet, bool count_fits = true);
  ~Progress();  // stops the printer and prints the final line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void run_done() { runs_done_.fetch_add(1, std::memory_order_relaxed); }
  // The units the job computes, by configuration (their costs weigh the ETA), and
  // one that ended after `seconds` of computing (with run_done()).
  void expect_unit(std::int32_t configuration);
  void unit_cost(std::int32_t configuration, double seconds);
  // An adaptive study's next look: `runs` more to do, and what the line leads
  // with ("look 2, 14 of 216 cells open").
  void add_runs(std::int32_t runs) { total_runs_.fetch_add(runs, std::memory_order_relaxed); }
  void set_stage(std::string text);
  // Fits ended in another process (an MPI worker's, which its heartbeats report).
  void add_remote_fits(std::int64_t fits) {
    remote_fits_.fetch_add(fits, std::memory_order_relaxed);
  }

 private:
  void print(bool final_line);
  void loop();

  std::atomic<std::int32_t> total_runs_;
  const std::int32_t fits_per_run_;
  const bool quiet_;
  const bool terminal_;
  const bool count_fits_;
  const std::int64_t fits_before_;  // fits_done() at the start
  const std::chrono::steady_clock::time_point start_;
  std::atomic<std::int32_t> runs_done_{0};
  std::atomic<std::int64_t> remote_fits_{0};  // add_remote_fits
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::string stage_;                                  // under mutex_
  std::vector<ConfigurationProgress> configurations_;  // under mutex_
  std::thread printer_;
};

}  // namespace ggk::engine
