#pragma once
// Where an adaptive study stands (issue 35; the rule: job/adaptive_rule.hpp), as
// a function of its file's complete runs alone, never of timing, thread or rank
// count: the runner asks it which runs the next look needs, `ggk info` shows its
// cells.
//
// The looks are replayed from the start. Look 1 gives every run configuration
// `batch` runs. Once every configuration has the runs of the look, each cell
// (per comparison AXIS=A,B and metric, a point of the other axes: the fits that
// differ only in AXIS) is judged on its paired differences A - B over runs
// 0 .. n-1 (n: the runs both sides' configurations have): the confidence
// sequence of their mean (kernels/confidence_sequence.hpp; method "bernstein":
// the empirical-Bernstein one, its bounds from the metric's range; "asymptotic":
// the asymptotic one, tightest at the job's runs) at the cell's level. A cell is
// decided when the interval leaves out 0 (target "sign": "+" or "-") or is
// narrower than `width` (target "width": "narrow"), and stays as it was at that
// look (its runs, mean and bounds then), however many runs its configurations
// get later for other cells; an undecided cell asks for `batch` more runs of
// both its configurations, up to the job's runs ("capped" there). The next look
// gives each configuration the most runs its open cells ask for; the study is
// done when no cell asks for more. A cell with a failed fit (a NaN metric) in
// its runs is "failed": it asks for nothing.
//
// The rule stops each cell on its own: the runs a look adds hold only the
// sweep points of the cells still open (and those in no cell), so a cell's fits
// are computed in exactly the runs it is judged on. As cells never reopen,
// every run a cell is judged on holds its fits.
//
// The guarantee, "bernstein" (Waudby-Smith & Ramdas 2023, Theorem 2, for
// independent runs): with correction "bonferroni", the chance that any cell's
// interval misses its true mean difference at any look (so that any decided
// sign is wrong) is at most 1 - level, however the looks went; each cell is
// judged at level 1 - (1 - level) / cells. With "none", that holds for each
// cell on its own. "asymptotic" (Waudby-Smith, Arnold, Wu, Chang & Ramdas 2024):
// the same as the runs grow, as for a t interval; tests/python/
// test_confidence_sequence.py measures it at the looks a study takes.
//
// Thread-safety: pure functions of plain data.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/adaptive_rule.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

enum class CellState { kPositive, kNegative, kNarrow, kOpen, kCapped, kFailed };
// "+", "-", "narrow", "open", "capped", "failed".
std::string_view cell_state_name(CellState state);

struct AdaptiveCell {
  std::size_t comparison = 0;    // index into the rule's comparisons
  std::vector<std::string> key;  // the other axes' values (AdaptiveState::key_names)
  std::string metric;
  std::int32_t configuration_a = 0;  // the configurations of its two sides
  std::int32_t configuration_b = 0;
  std::int64_t runs = 0;  // paired runs judged (n)
  double mean = 0.0;      // of the differences A - B over those runs (NaN: none)
  double lower = 0.0;     // the confidence sequence after n runs
  double upper = 0.0;
  CellState state = CellState::kOpen;
};

// The sweep points (indices into the configuration's expand_points, ascending)
// its runs hold from `first_run` on, up to the next such segment.
struct RunPoints {
  std::int64_t first_run = 0;
  std::vector<std::int32_t> points;
  bool operator==(const RunPoints&) const = default;
};

// A run the current look needs that the file lacks whole or in part.
struct RunNeed {
  std::int32_t configuration = 0;
  std::int32_t run = 0;
  bool new_run = true;  // absent: computed with `points`; else stored, lacking `points`
  // new_run: the points it needs, empty for all of them; else the points it
  // lacks, none when it only carries other indices than the study's (a study
  // grown by fit-level values renumbers its points).
  std::vector<std::int32_t> points;
};

struct AdaptiveState {
  std::vector<AdaptiveCell> cells;  // comparison by comparison, then by point, then metric
  std::vector<std::vector<std::string>> key_names;  // per comparison: the other axes' names
  // Per configuration: the runs the current look gives it (runs 0 .. n-1).
  std::vector<std::int32_t> runs_wanted;
  std::int32_t looks = 1;        // the looks taken, the current one included
  bool done = false;             // every configuration has its runs and no cell asks for more
  double cell_level = 0.0;       // each cell's level (after the correction)
  std::int64_t level_cells = 0;  // the cells the correction divides over: the study's
  // The configurations judged: a shard's (AdaptiveScope), else every one.
  std::int64_t configurations_judged = 0;
  // Per configuration: the points its runs need, segment by segment. Run r
  // needs the points of the cells still open at the look that first asked for
  // it (a point in no cell: always), so a decided cell's fits are not computed
  // in later runs.
  std::vector<std::vector<RunPoints>> run_points;
  // The current look's runs the file lacks or lacks points of (none once done).
  std::vector<RunNeed> needs;
  std::int64_t fits_wanted = 0;  // the fits the current look's runs need, summed
  std::int64_t fits_whole = 0;   // the same runs' fits had each run every point
  std::int64_t open_cells() const;
};

// The range [low, high] of one value of `metric`: the rule's [adaptive.range]
// entry, else [0, 1] for a rate or a fraction (`kind`); nullopt when neither.
std::optional<MetricRange> metric_range(const AdaptiveRule& rule, std::string_view metric,
                                        MetricKind kind);

// What one process of an adaptive study judges: a shard's run configurations
// (run/adaptive_shards.hpp), a set the rule's cells never link to others, and
// the whole study's cell count, which sets each cell's level. Empty / none: the
// whole study, its cells counted in the file.
struct AdaptiveScope {
  std::vector<std::int32_t> configurations;  // ascending
  std::optional<std::int64_t> cells;
};

// The scope of a file: an adaptive study's shard's (its header's
// configurations_selected), or the whole study.
AdaptiveScope adaptive_scope_of(const ResultsHeader& header);

// The state of the study with `configurations` run configurations, at most
// `max_runs` runs each, whose file holds `contents` (a metric's kind: its
// declaration, contents.metric_specs). Throws UsageError when a compared metric is no column of
// the file, has no range, or a value lies outside its range (naming the run).
// Under a scope the configurations outside it want no runs and its looks wait
// for none of theirs; each cell's level is that of scope.cells cells. A cell
// group of a closed set of configurations (adaptive_plan) goes through the same
// looks alone as in the whole study, so a shard of such sets computes the runs
// the whole study gives them.
//
// The sweep points are the file's, or with `planned` (run/adaptive_shards.hpp:
// the study's, as the file will list them) the study's: a study grown by
// fit-level values has points no run holds yet. A look is complete when every
// run it gives a configuration is stored with the points that run needs.
AdaptiveState adaptive_state(const ResultsContents& contents, const AdaptiveRule& rule,
                             std::int32_t configurations, std::int32_t max_runs,
                             const AdaptiveScope& scope = {},
                             const ResultsContents* planned = nullptr);

// The cells of a study and the run configurations they link, from `planned`:
// one fit row per configuration and sweep point, its axes (axis_names, key) as
// the file will hold them, no values (run/adaptive_shards.hpp builds it).
struct AdaptivePlan {
  std::int64_t cells = 0;              // pairings x the rule's metrics
  std::vector<std::int32_t> group_of;  // per configuration: its group, numbered by first member
  std::int32_t groups = 0;
};
AdaptivePlan adaptive_plan(const ResultsContents& planned, const AdaptiveRule& rule,
                           std::int32_t configurations);

}  // namespace ggk::engine
