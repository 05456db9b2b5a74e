#include "engine/run/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "engine/tasks/fit_count.hpp"

namespace ggk::engine {

std::string eta_text(std::int64_t done, std::int64_t total, double elapsed_seconds) {
  // No estimate before the first unit ends: "--", not a made-up 0 s.
  if (done <= 0) return "--";
  char text[32];
  std::snprintf(text, sizeof text, "%.0fs",
                elapsed_seconds * static_cast<double>(std::max<std::int64_t>(total - done, 0)) /
                    static_cast<double>(done));
  return text;
}

std::optional<double> weighted_seconds_left(std::span<const ConfigurationProgress> configurations,
                                            double elapsed_seconds) {
  std::int64_t done = 0;
  double seconds = 0.0;
  for (const ConfigurationProgress& c : configurations) {
    // Units ended that were never expected (an MPI rank 0, which counts runs
    // only): no estimate of this kind.
    if (c.done > c.expected) return std::nullopt;
    done += c.done;
    seconds += c.seconds;
  }
  if (done <= 0 || !(elapsed_seconds > 0.0) || !(seconds > 0.0)) return std::nullopt;
  const double mean = seconds / static_cast<double>(done);
  double left = 0.0;  // unit-seconds still to compute
  for (const ConfigurationProgress& c : configurations) {
    const double cost = c.done > 0 ? c.seconds / static_cast<double>(c.done) : mean;
    left += static_cast<double>(std::max<std::int64_t>(c.expected - c.done, 0)) * cost;
  }
  return left / (seconds / elapsed_seconds);
}

std::string progress_text(std::int32_t runs_done, std::int32_t total_runs, std::int64_t fits_done,
                          std::int64_t total_fits, double elapsed_seconds,
                          std::optional<double> eta_seconds) {
  char text[160];
  const auto eta = [&](std::int64_t done, std::int64_t total) {
    if (!eta_seconds) return eta_text(done, total, elapsed_seconds);
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.0fs", *eta_seconds);
    return std::string(seconds);
  };
  if (fits_done < 0) {
    const double fits_per_second =
        elapsed_seconds > 0
            ? static_cast<double>(runs_done) *
                  (total_runs > 0 ? static_cast<double>(total_fits) / total_runs : 0.0) /
                  elapsed_seconds
            : 0;
    std::snprintf(text, sizeof text, "runs %d/%d, %.1f fits/s, elapsed %.0fs, eta %s", runs_done,
                  total_runs, fits_per_second, elapsed_seconds, eta(runs_done, total_runs).c_str());
    return text;
  }
  fits_done = std::min(fits_done, total_fits);
  const double fits_per_second =
      elapsed_seconds > 0 ? static_cast<double>(fits_done) / elapsed_seconds : 0;
  std::snprintf(text, sizeof text, "runs %d/%d, fits %lld/%lld, %.1f fits/s, elapsed %.0fs, eta %s",
                runs_done, total_runs, static_cast<long long>(fits_done),
                static_cast<long long>(total_fits), fits_per_second, elapsed_seconds,
                eta(fits_done, total_fits).c_str());
  return text;
}

Progress::Progress(std::int32_t total_runs, std::int32_t fits_per_run, bool quiet, bool count_fits)
    : total_runs_(total_runs),
      fits_per_run_(fits_per_run),
      quiet_(quiet),
      terminal_(isatty(STDERR_FILENO) == 1),
      count_fits_(count_fits),
      fits_before_(fits_done()),
      start_(std::chrono::steady_clock::now()) {
  if (!quiet_) printer_ = std::thread([this] { loop(); });
}

Progress::~Progress() {
  if (quiet_) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  printer_.join();
  print(true);
}

void Progress::expect_unit(std::int32_t configuration) {
  std::lock_guard lock(mutex_);
  const auto c = static_cast<std::size_t>(configuration);
  if (c >= configurations_.size()) configurations_.resize(c + 1);
  ++configurations_[c].expected;
}

void Progress::unit_cost(std::int32_t configuration, double seconds) {
  std::lock_guard lock(mutex_);
  const auto c = static_cast<std::size_t>(configuration);
  if (c >= configurations_.size()) configurations_.resize(c + 1);
  ++configurations_[c].done;
  configurations_[c].seconds += seconds;
}

void Progress::set_stage(std::string text) {
  std::lock_guard lock(mutex_);
  stage_ = std::move(text);
}

void Progress::loop() {
  const auto period = terminal_ ? std::chrono::milliseconds(250) : std::chrono::seconds(10);
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, period, [this] { return stopping_; })) print(false);
}

void Progress::print(bool final_line) {
  const std::int32_t done = runs_done_.load(std::memory_order_relaxed);
  const std::int32_t total_runs = total_runs_.load(std::memory_order_relaxed);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::int64_t total_fits = static_cast<std::int64_t>(total_runs) * fits_per_run_;
  const std::int64_t fits =
      count_fits_ ? fits_done() - fits_before_ + remote_fits_.load(std::memory_order_relaxed) : -1;
  // Weighted by each configuration's cost once a unit has ended (print runs under
  // mutex_: the loop holds it, and the final line comes after the loop ended).
  const std::optional<double> weighted = weighted_seconds_left(configurations_, elapsed);
  const std::string text = (stage_.empty() ? std::string() : stage_ + ": ") +
                           progress_text(done, total_runs, fits, total_fits, elapsed, weighted);
  if (terminal_) {
    constexpr int kWidth = 30;
    const double fraction =
        fits >= 0 ? (total_fits > 0 ? static_cast<double>(std::min(fits, total_fits)) /
                                          static_cast<double>(total_fits)
                                    : 1.0)
                  : (total_runs > 0 ? static_cast<double>(done) / total_runs : 1.0);
    const int filled = static_cast<int>(kWidth * fraction);
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r[%s] %s   ", bar, text.c_str());
    if (final_line) std::fputc('\n', stderr);
  } else {
    std::fprintf(stderr, "ggk: %s\n", text.c_str());
  }
  std::fflush(stderr);
}

}  // namespace ggk::engine
