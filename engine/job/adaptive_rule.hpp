#pragma once
// The rule of an adaptive study (issue 35): runs are added, a batch at a time,
// to the run configurations whose paired comparisons are still undecided.
//
//   runs = 40                        # at most this many runs per configuration
//   [adaptive]
//   compare = "basis=ggk,ogk"        # AXIS=A,B (or an array of them): A - B, paired by run
//   metrics = ["success_rate"]       # the metrics compared (one or more)
//   target = "sign"                  # "sign": until the difference's sign is decided;
//                                    # "width": until its interval is narrower than `width`
//   batch = 5                        # runs per configuration per look
//   level = 0.95                     # the confidence of all decisions together
//   correction = "bonferroni"        # over the cells ("none": each cell at `level`)
//   method = "bernstein"             # the confidence sequence: "bernstein" (needs each
//                                    #   metric's range) or "asymptotic" (needs none)
//   [adaptive.range]                 # "bernstein": each compared metric's range where
//   mean_return = [-2.0, 150.0]      #   the task does not know it (rates and
//                                    #   fractions: [0, 1])
//
// A cell is a point of the other axes: the pair of fits that differ only in the
// compared axis, for one metric. Its paired differences over runs 0, 1, ... are
// bounded by the metric's range, and the anytime-valid confidence sequence of
// their mean (kernels/confidence_sequence.hpp) decides it (store/adaptive_state.hpp).
//
// The job reader parses the table; the study reader checks the axes and values
// against the study (check_adaptive_rule). That the metrics exist is checked
// against the task's results (run/adaptive_study.hpp).
//
// Thread-safety: plain data.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ggk::engine {

class TomlTableReader;

// AXIS=A,B: the difference A - B over the axis's two values, as the job writes them.
struct AdaptiveComparison {
  std::string axis;
  std::string a;
  std::string b;
  std::string text() const { return axis + "=" + a + "," + b; }
};

struct MetricRange {
  std::string metric;
  double low = 0.0;
  double high = 1.0;
};

enum class AdaptiveTarget { kSign, kWidth };
enum class AdaptiveCorrection { kBonferroni, kNone };
// The confidence sequence a cell is judged by (kernels/confidence_sequence.hpp):
// the empirical-Bernstein one, valid at every number of runs for values in a
// known range; or the asymptotic one, which needs no range and is valid as the
// runs grow (as a t interval is).
enum class AdaptiveMethod { kBernstein, kAsymptotic };

struct AdaptiveRule {
  std::vector<AdaptiveComparison> comparisons;  // at least one
  std::vector<std::string> metrics;             // at least one, distinct
  std::vector<MetricRange> ranges;              // declared in [adaptive.range]
  AdaptiveTarget target = AdaptiveTarget::kSign;
  double width = 0.0;  // target kWidth: decided when upper - lower < width
  std::int32_t batch = 5;
  double level = 0.95;
  AdaptiveCorrection correction = AdaptiveCorrection::kBonferroni;
  AdaptiveMethod method = AdaptiveMethod::kBernstein;

  // The declared range of `metric`, or nullopt.
  std::optional<MetricRange> declared_range(std::string_view metric) const;
};

// "basis=ggk,ogk" -> {basis, ggk, ogk}; nullopt when the text is not AXIS=A,B
// with A != B.
std::optional<AdaptiveComparison> parse_adaptive_comparison(std::string_view text);

// The job's [adaptive] table, or nullopt when it has none. `runs`: the job's
// runs (the most per configuration): a batch above it is refused. Throws
// JobError naming the key.
std::optional<AdaptiveRule> parse_adaptive_table(const TomlTableReader& job, std::int32_t runs);

// The [adaptive] table of a job's TOML text as stored with its results (the root
// attribute `job`), or nullopt when it has none. Throws JobError when the table
// is not a valid rule.
std::optional<AdaptiveRule> adaptive_rule_of_text(const std::string& job_text,
                                                  const std::string& file, std::int32_t runs);

}  // namespace ggk::engine
