#pragma once
// `ggk info FILE`: what a results file holds (job, runs complete, and per sweep
// point the fits, how many failed or stopped at the iteration cap, and the mean
// of each metric over the complete runs with its 95 % confidence interval), as
// plain text or CSV. The rows come from the complete runs themselves, so a
// sweep that is still running (or was killed) shows the runs done so far.
// `--columns a,b` shows those metrics only; `--paired basis=ggk,ogk` shows, per
// point of the other axes, each metric's mean difference ggk - ogk paired by
// run (and a study's configuration), with the interval python/ggk_results'
// paired() gives: Newcombe's for rates whose values are all 0 or 1, else the
// paired Student t (scipy's ttest_rel).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/tasks/metric_spec.hpp"

namespace ggk::engine {

enum class InfoFormat { kText, kCsv };

// `--paired AXIS=A,B`: the axis (a column between sweep_point and status) and
// its two values, as the file writes them (basis=ggk,ogk; kernels=64,16).
struct PairedComparison {
  std::string axis;
  std::string a, b;
};
// Throws UsageError for text that is not AXIS=A,B.
PairedComparison parse_paired_option(std::string_view text);
// "a,b,c" as names (empty: every metric); an empty name is a UsageError.
std::vector<std::string> info_column_list(std::string_view text);

struct InfoOptions {
  InfoFormat format = InfoFormat::kText;
  std::vector<std::string> columns;        // metrics to show, in order; empty: all
  std::optional<PairedComparison> paired;  // differences instead of means
  bool adaptive = false;                   // an adaptive study's cells only (adaptive_info.hpp)
};

// Throws UsageError when the file cannot be opened or is not a ggk results file,
// a column is no metric of the file, or the paired axis or a value is not in it
// (each named, with what the file has).
void print_results_info(const std::filesystem::path& file, std::ostream& out,
                        const InfoOptions& options);
void print_results_info(const std::filesystem::path& file, std::ostream& out, InfoFormat format);

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
// The mean difference of a - b paired by position (a and b of equal length,
// pairs with a NaN left out) with the paired Student-t interval (scipy's
// ttest_rel(a, b).confidence_interval(); zero width when every difference is
// the same, NaN bounds for fewer than two pairs).
Interval paired_t_interval(std::span<const double> a, std::span<const double> b);
// The difference of two success rates from paired 0/1 outcomes with Newcombe's
// hybrid score interval (1998, method 10; python/ggk_results/intervals.py,
// newcombe_paired_ci): inside [-1, 1].
Interval newcombe_paired_interval(std::span<const double> a, std::span<const double> b);

// The interval `ggk info` gives a metric over runs, by its declaration
// (tasks/metric_spec.hpp): Wilson's for an indicator whose every value is 0 or
// 1; else Student's t, intersected with the metric's range (which keeps its
// coverage and a bounded metric's interval inside its bounds).
Interval metric_interval(std::span<const double> values, const MetricSpec& spec);

}  // namespace ggk::engine
