#pragma once
// What a metric of a task's fits is, declared once beside the task that sets it
// (its protocol's metric list) and written into every results file: name, kind,
// unit, meaning and range. The store writes the declarations of a run's metrics
// as the table metric_specs beside its fit_metrics (store/metric_specs_table.hpp);
// `ggk info` and python/ggk_results read kinds, units and ranges from there and
// guess nothing from names. Plain data: no I/O, nothing of the store.

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ggk::engine {

// What one run contributes to a metric, which decides the 95 % interval of its
// mean over runs (`ggk info`, python/ggk_results/intervals.py):
//  - kMean: any value per run: Student's t over the runs;
//  - kIndicator: one 0/1 outcome per run (success from a named start):
//    Wilson's score interval (Student's t when a value is not 0 or 1);
//  - kFraction: a per-run share of episodes or states (the Khepera's collision
//    fraction): Student's t over runs, never Wilson (a run is not one trial).
// Every interval is then intersected with the metric's declared range, which
// keeps its coverage (the mean lies in the range) and a bounded metric's
// interval inside its bounds.
enum class MetricKind { kMean, kIndicator, kFraction };

// "mean", "indicator", "fraction": the words the file's metric_specs use.
std::string_view kind_name(MetricKind kind);
// The kind a word names; nullopt for any other text.
std::optional<MetricKind> kind_from_name(std::string_view name);

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// One metric of a task's fits.
struct MetricSpec {
  std::string name;
  MetricKind kind = MetricKind::kMean;
  // A value of the test of a greedy policy, so that [lspi] evaluate_iterations
  // measures it for every iterate too (history/<name>); the others (LSPI's
  // iteration count, the graph's diagnostics) belong to the fit or the run.
  bool tested = false;
  bool integer = false;  // always a whole number: stored as an int64 column and attribute
  // The unit in UDUNITS words ("1" for a dimensionless share or ratio, "steps",
  // "s"), and what the metric measures in one line (xarray's units and long_name).
  std::string unit = "1";
  std::string meaning;
  // Every value lies in [low, high] (NaN apart: a fit that could not measure it);
  // -kUnbounded / kUnbounded where the task knows no bound.
  double low = -kUnbounded;
  double high = kUnbounded;
};

// Declarations by kind: a mean in `unit` within [low, high]; a fraction or an
// indicator, unit "1" within [0, 1]. (Functions, not designated initializers:
// g++ 12 warns of every member such an initializer leaves out.)
MetricSpec mean_metric(std::string name, std::string unit, std::string meaning,
                       double low = -kUnbounded, double high = kUnbounded);
MetricSpec fraction_metric(std::string name, std::string meaning);
MetricSpec indicator_metric(std::string name, std::string meaning);
// The declaration marked tested (a value of a greedy policy's test), or integer.
MetricSpec tested(MetricSpec spec);
MetricSpec integer(MetricSpec spec);

// The names of the metrics `specs` declare integer (fit_metrics' int64 columns).
std::vector<std::string> integer_metric_names(std::span<const MetricSpec> specs);

// The declaration of `metric` in `specs`; nullptr when they do not declare it.
const MetricSpec* find_metric_spec(std::span<const MetricSpec> specs, std::string_view metric);

// The kind `specs` declare for `metric`; a mean for a metric they do not declare.
MetricKind declared_kind(std::span<const MetricSpec> specs, std::string_view metric);

// The fit's wall time, the column the store adds after a task's metrics.
MetricSpec fit_seconds_spec();

// One declaration of each metric over runs whose declarations are `a` and `b`
// (the runs of a study's configurations: a range may follow a configuration's
// keys): a's order and words, then b's metrics a does not declare; each range the
// smallest that holds both.
std::vector<MetricSpec> united_metric_specs(std::span<const MetricSpec> a,
                                            std::span<const MetricSpec> b);

}  // namespace ggk::engine
