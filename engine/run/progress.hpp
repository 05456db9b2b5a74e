#pragma once
// Progress of a sweep on stderr: a redrawn bar (runs done / total, fits per
// second, ETA) when stderr is a terminal, plain lines every few seconds otherwise.
//
// Thread-safety: fit_done() and run_done() may be called from any thread.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace ggk::engine {

// The time left after `done` of `total` runs in `elapsed_seconds` ("42s"), or
// "--" while no run has ended.
std::string eta_text(std::int32_t done, std::int32_t total, double elapsed_seconds);

class Progress {
 public:
  // quiet: print nothing. fits_per_run: sweep points per run.
  Progress(std::int32_t total_runs, std::int32_t fits_per_run, bool quiet);
  ~Progress();  // stops the printer and prints the final line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void run_done() { runs_done_.fetch_add(1, std::memory_order_relaxed); }

 private:
  void print(bool final_line);
  void loop();

  const std::int32_t total_runs_;
  const std::int32_t fits_per_run_;
  const bool quiet_;
  const bool terminal_;
  const std::chrono::steady_clock::time_point start_;
  std::atomic<std::int32_t> runs_done_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread printer_;
};

}  // namespace ggk::engine
