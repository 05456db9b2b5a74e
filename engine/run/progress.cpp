#include "engine/run/progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace ggk::engine {

std::string eta_text(std::int32_t done, std::int32_t total, double elapsed_seconds) {
  // No estimate before the first run ends: "--", not a made-up 0 s.
  if (done <= 0) return "--";
  char text[32];
  std::snprintf(text, sizeof text, "%.0fs", elapsed_seconds * (total - done) / done);
  return text;
}

Progress::Progress(std::int32_t total_runs, std::int32_t fits_per_run, bool quiet)
    : total_runs_(total_runs),
      fits_per_run_(fits_per_run),
      quiet_(quiet),
      terminal_(isatty(STDERR_FILENO) == 1),
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

void Progress::loop() {
  const auto period = terminal_ ? std::chrono::milliseconds(250) : std::chrono::seconds(10);
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, period, [this] { return stopping_; })) print(false);
}

void Progress::print(bool final_line) {
  const std::int32_t done = runs_done_.load(std::memory_order_relaxed);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fits_per_second =
      elapsed > 0 ? done * static_cast<double>(fits_per_run_) / elapsed : 0;
  const std::string eta = eta_text(done, total_runs_, elapsed);
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = total_runs_ > 0 ? kWidth * done / total_runs_ : kWidth;
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r[%s] runs %d/%d  %.1f fits/s  elapsed %.0fs  eta %s   ", bar, done,
                 total_runs_, fits_per_second, elapsed, eta.c_str());
    if (final_line) std::fputc('\n', stderr);
  } else {
    std::fprintf(stderr, "ggk: runs %d/%d, %.1f fits/s, elapsed %.0fs, eta %s\n", done, total_runs_,
                 fits_per_second, elapsed, eta.c_str());
  }
  std::fflush(stderr);
}

}  // namespace ggk::engine
