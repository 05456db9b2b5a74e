#pragma once
// `ggk info FILE`: what a results file holds (job, runs complete, and per sweep
// point the fits, how many failed or stopped at the iteration cap, and the mean
// of each metric over the complete runs with its 95 % confidence interval), as
// plain text or CSV. The rows come from the complete runs themselves, so a
// sweep that is still running (or was killed) shows the runs done so far.

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <span>
#include <string_view>

#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

enum class InfoFormat { kText, kCsv };

// The kind of a metric column of a task's results (a mean, or a rate in [0, 1]),
// which decides its interval; the engine passes tasks/task_list.hpp's metric_kind.
using MetricKindLookup = MetricKind (*)(std::string_view task, std::string_view metric);

// Throws UsageError when the file cannot be opened or is not a ggk results file.
void print_results_info(const std::filesystem::path& file, std::ostream& out, InfoFormat format,
                        MetricKindLookup metric_kind);

// A 95 % confidence interval: [low, high] around the estimate; NaN bounds when
// there are too few values for one.
struct Interval {
  double estimate = 0.0;
  double low = 0.0;
  double high = 0.0;
};

// Two-sided 95 % quantile of Student's t with `dof` >= 1 degrees of freedom
// (scipy.stats.t.ppf(0.975, dof) to 4 decimals).
double student_t_975(std::int64_t dof);
// Mean of the finite values with its Student-t interval (NaN values dropped).
Interval mean_interval(std::span<const double> values);
// Success rate of `successes` out of `trials` with Wilson's score interval:
// inside [0, 1], and of non-zero width at 0 % and 100 %.
Interval wilson_interval(std::int64_t successes, std::int64_t trials);
// The interval `ggk info` gives a metric of this kind over runs (run_record.hpp:
// MetricKind): Wilson for a rate whose every value is 0 or 1, Student's t
// clipped to [0, 1] for other rates and fractions, Student's t for means.
Interval metric_interval(std::span<const double> values, MetricKind kind);

}  // namespace ggk::engine
